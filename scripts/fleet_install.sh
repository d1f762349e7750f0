#!/bin/sh
# Installs a groundsim fleet member on a Debian (bookworm) host with systemd:
# the units of deploy/systemd, their settings, the multicast route, the LCM
# receive buffer sysctl and, with --etcd-name, this host's member of the
# 3-member etcd cluster (Debian's etcd-server). docs/fleet.md, Deployment.
#
#   sudo scripts/fleet_install.sh --binary build/server/lcm/groundsim-server \
#        --etcd http://192.0.2.1:2379,http://192.0.2.2:2379,http://192.0.2.3:2379 \
#        --etcd-name h1 --etcd-ip 192.0.2.1 \
#        --etcd-cluster h1=http://192.0.2.1:2380,h2=http://192.0.2.2:2380,h3=http://192.0.2.3:2380
#
# Options:
#   --binary PATH        groundsim-server to install as /usr/local/bin/groundsim-server
#   --client PATH        the groundsim client, as /usr/local/bin/groundsim
#   --etcd URLS          the servers' etcd endpoints (GROUNDSIM_ETCD)
#   --dev IFACE          the LAN interface of the bus (GROUNDSIM_MCAST_DEV, default eth0)
#   --etcd-name NAME     make this host an etcd member NAME (with --etcd-ip, --etcd-cluster)
#   --etcd-ip IP         this member's address (peer :2380, client :2379)
#   --etcd-cluster LIST  name=http://ip:2380,... of all members, the same on every member
#   --etcd-token TOKEN   the cluster's initial token (default groundsim-fleet)
#   --no-apt             install no package (fail if one is missing)
#   --no-start           enable the units, start nothing
#   --root DIR           install into DIR instead of / (no apt, no user, no
#                        systemctl; for checking what would be written)
#
# Idempotent: a second run with the same options changes nothing and
# restarts nothing. Files under /etc that an administrator edits
# (/etc/default/groundsim-server) are created once; an option given again
# only rewrites its own line. Needs root and, for missing packages, apt.
# "A && B || C" here: B is an assignment, which cannot fail
# shellcheck disable=SC2015
set -eu

here=$(cd "$(dirname "$0")/.." && pwd)
src=$here/deploy/systemd

binary='' client='' etcd_urls='' dev='' etcd_name='' etcd_ip='' etcd_cluster='' etcd_token=groundsim-fleet
apt=1 start=1 root=''
usage() { sed -n '2,/^set -eu/p' "$0" | sed -e '/^set -eu/d' -e '/shellcheck\|A && B/d' -e 's/^# \{0,1\}//' >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --binary) binary=$2; shift 2 ;;
    --client) client=$2; shift 2 ;;
    --etcd) etcd_urls=$2; shift 2 ;;
    --dev) dev=$2; shift 2 ;;
    --etcd-name) etcd_name=$2; shift 2 ;;
    --etcd-ip) etcd_ip=$2; shift 2 ;;
    --etcd-cluster) etcd_cluster=$2; shift 2 ;;
    --etcd-token) etcd_token=$2; shift 2 ;;
    --no-apt) apt=0; shift ;;
    --no-start) start=0; shift ;;
    --root) root=$2; shift 2 ;;
    -h|--help) usage ;;
    *) echo "fleet_install: unknown option $1" >&2; usage ;;
  esac
done

say() { echo "fleet_install: $*"; }
die() { echo "fleet_install: $*" >&2; exit 1; }

if [ -n "$etcd_name$etcd_ip$etcd_cluster" ]; then
  [ -n "$etcd_name" ] && [ -n "$etcd_ip" ] && [ -n "$etcd_cluster" ] ||
    die "--etcd-name, --etcd-ip and --etcd-cluster go together"
  case ",$etcd_cluster," in
    *",$etcd_name=http://$etcd_ip:2380,"*) ;;
    *) die "--etcd-cluster must contain $etcd_name=http://$etcd_ip:2380" ;;
  esac
fi
[ -z "$binary" ] || [ -x "$binary" ] || die "--binary $binary is not an executable"
[ -z "$client" ] || [ -x "$client" ] || die "--client $client is not an executable"
if [ -n "$root" ]; then
  apt=0 start=0
  mkdir -p "$root"
  root=$(cd "$root" && pwd)
else
  [ "$(id -u)" = 0 ] || die "run as root (or with --root DIR to see what it writes)"
fi

changed_server=0 changed_etcd=0 changed_sysctl=0 changed_units=0

# install_file SRC DST MODE: copy when DST differs; prints what it did
install_file() {
  if [ -f "$root$2" ] && cmp -s "$1" "$root$2"; then
    say "unchanged $2"; return 1
  fi
  install -D -m "$3" "$1" "$root$2"
  say "installed $2"; return 0
}

# set_var FILE VAR VALUE: VAR=VALUE in FILE, replacing a (commented) line of it
set_var() {
  f=$root$1
  if grep -qx "$2=$3" "$f"; then say "unchanged $2 in $1"; return 1; fi
  tmp=$(mktemp)
  awk -v var="$2" -v val="$3" '
    !done && ($0 ~ "^#?" var "=") { print var "=" val; done = 1; next }
    { print }
    END { if (!done) print var "=" val }' "$f" > "$tmp"
  cat "$tmp" > "$f"; rm -f "$tmp"
  say "set $2=$3 in $1"; return 0
}

# ---- packages: runtime libraries of groundsim-server (the image's list), ip, etcd
pkgs="liblcm1 libmuparser2v5 libgomp1 libpng16-16 libssl3 iproute2 etcd-client"
[ -z "$etcd_name" ] || pkgs="$pkgs etcd-server"
missing=
for p in $pkgs; do
  dpkg-query -W -f '${Status}' "$p" 2>/dev/null | grep -q 'ok installed' || missing="$missing $p"
done
etcd_was_installed=1
case " $missing " in *" etcd-server "*) etcd_was_installed=0 ;; esac
if [ -n "$missing" ]; then
  [ "$apt" = 1 ] || { [ -n "$root" ] && say "would install:$missing (--root: skipped)"; } ||
    die "missing packages:$missing (without --no-apt they are installed)"
  if [ "$apt" = 1 ]; then
    # Debian's etcd-server starts a lone member at once, whose data
    # directory a cluster member then refuses; keep it from starting
    policy=
    if [ ! -e /usr/sbin/policy-rc.d ]; then
      printf '#!/bin/sh\nexit 101\n' > /usr/sbin/policy-rc.d; chmod 755 /usr/sbin/policy-rc.d; policy=1
    fi
    say "apt-get install$missing"
    # shellcheck disable=SC2086  # $missing: one word per package
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $missing ||
      { apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $missing; } ||
      { [ -z "$policy" ] || rm -f /usr/sbin/policy-rc.d; die "apt-get install failed"; }
    [ -z "$policy" ] || rm -f /usr/sbin/policy-rc.d
  fi
else
  say "packages present: $pkgs"
fi

# ---- the user the server runs as (its state: /var/lib/groundsim, StateDirectory=)
if [ -z "$root" ]; then
  if getent passwd groundsim >/dev/null; then
    say "user groundsim exists"
  else
    useradd --system --user-group --home-dir /var/lib/groundsim --no-create-home \
            --shell /usr/sbin/nologin groundsim
    say "created system user groundsim"
  fi
fi

# ---- executables
if [ -n "$binary" ]; then
  install_file "$binary" /usr/local/bin/groundsim-server 0755 && changed_server=1
elif [ ! -x "$root/usr/local/bin/groundsim-server" ]; then
  say "note: no /usr/local/bin/groundsim-server yet (give --binary PATH); the unit will fail until there is one"
fi
[ -z "$client" ] || install_file "$client" /usr/local/bin/groundsim 0755 || true
[ ! -f "$here/docs/fleet.md" ] || install_file "$here/docs/fleet.md" /usr/local/share/doc/groundsim/fleet.md 0644 || true

# ---- units, settings, sysctl
for u in groundsim-server.service groundsim-mcast-route.service; do
  install_file "$src/$u" "/etc/systemd/system/$u" 0644 && changed_units=1 && changed_server=1
done
if [ -f "$root/etc/default/groundsim-server" ]; then
  say "kept /etc/default/groundsim-server (edited here; options below only set their lines)"
else
  install_file "$src/groundsim-server.default" /etc/default/groundsim-server 0644
  changed_server=1
fi
[ -z "$etcd_urls" ] || { set_var /etc/default/groundsim-server GROUNDSIM_ETCD "$etcd_urls" && changed_server=1; } || true
[ -z "$dev" ] || { set_var /etc/default/groundsim-server GROUNDSIM_MCAST_DEV "$dev" && changed_server=1; } || true
install_file "$src/90-groundsim.conf" /etc/sysctl.d/90-groundsim.conf 0644 && changed_sysctl=1 || true

# ---- this host's etcd member
if [ -n "$etcd_name" ]; then
  tmp=$(mktemp)
  sed -e "s|@NAME@|$etcd_name|g" -e "s|@IP@|$etcd_ip|g" -e "s|@CLUSTER@|$etcd_cluster|g" \
      -e "s|@TOKEN@|$etcd_token|g" "$src/etcd.default.in" > "$tmp"
  dflt=$root/etc/default/etcd
  if [ -f "$dflt" ] && ! cmp -s "$tmp" "$dflt"; then
    if ! grep -q groundsim "$dflt" && [ ! -e "$dflt.before-groundsim" ]; then
      cp -p "$dflt" "$dflt.before-groundsim"; say "saved the former /etc/default/etcd as /etc/default/etcd.before-groundsim"
    fi
    # a data directory that a member without our settings made (the
    # package's lone member) would keep this host out of the cluster
    data=$root/var/lib/etcd/default
    if ! grep -q groundsim "$dflt" && [ -d "$data/member" ]; then
      [ -n "$root" ] || { systemctl stop etcd 2>/dev/null || true; }
      aside=$data.lone-$(date -u +%Y%m%dT%H%M%SZ)
      mv "$data" "$aside"; say "moved a lone member's data directory aside to ${aside#"$root"}"
    fi
  fi
  install_file "$tmp" /etc/default/etcd 0644 && changed_etcd=1 || true
  rm -f "$tmp"
  install_file "$src/etcd-restart.conf" /etc/systemd/system/etcd.service.d/groundsim.conf 0644 &&
    changed_units=1 && changed_etcd=1 || true
  [ "$etcd_was_installed" = 1 ] || changed_etcd=1
fi

# ---- systemd
if [ -n "$root" ]; then
  say "--root: no systemctl, no sysctl; files are under $root"
  exit 0
fi
if [ ! -d /run/systemd/system ]; then
  say "systemd is not running here: files installed, nothing enabled or started"
  exit 0
fi
[ "$changed_units" = 0 ] || systemctl daemon-reload
[ "$changed_sysctl" = 0 ] || sysctl -q -p /etc/sysctl.d/90-groundsim.conf
systemctl enable groundsim-mcast-route.service groundsim-server.service
[ -z "$etcd_name" ] || systemctl enable etcd.service
[ "$start" = 1 ] || { say "--no-start: enabled, not started"; exit 0; }
systemctl start groundsim-mcast-route.service
if [ -n "$etcd_name" ]; then
  # --no-block: a member waits for a quorum before it reports ready, i.e.
  # until a second member of the cluster runs
  if [ "$changed_etcd" = 1 ]; then systemctl --no-block restart etcd.service; say "etcd (re)started"
  else systemctl --no-block start etcd.service; fi
fi
# a restart of a running server drains it (SIGTERM): only when something changed
if [ "$changed_server" = 1 ]; then
  systemctl restart groundsim-server.service; say "groundsim-server (re)started"
else
  systemctl start groundsim-server.service; say "groundsim-server running (unchanged)"
fi
systemctl --no-pager --lines=0 status groundsim-server.service || true
