#!/usr/bin/env bash
# A multi-host lab on one machine (docs/fleet.md, "The lab"): N "hosts",
# each a network namespace gs-<lab>-h<i> with one interface eth0 at
# 192.0.2.<i>/24 (RFC 5737 TEST-NET-1), joined by veth pairs to a bridge br0
# in a switch namespace gs-<lab>-sw. Hosts have loopback, the lab subnet and
# a multicast route (LCM's udpm refuses to start without one), and no default
# route: no traffic can leave the lab. Needs root (ip netns); the root
# namespace is not touched. <lab> names one lab ([a-z0-9], up to 12), so
# parallel runs do not meet.
#
#   scripts/fleet_lab.sh up LAB N              make the switch and hosts 1..N
#   scripts/fleet_lab.sh down LAB              kill every process of the lab, delete its namespaces
#   scripts/fleet_lab.sh exec LAB I CMD...     run CMD in host I
#   scripts/fleet_lab.sh kill LAB I            SIGKILL every process of host I (a host's death)
#   scripts/fleet_lab.sh partition LAB I       cut host I off the switch (link down)
#   scripts/fleet_lab.sh heal LAB I            plug it back
#   scripts/fleet_lab.sh loss LAB I PERCENT    drop PERCENT % of host I's frames on the switch (nftables; 0: none)
#   scripts/fleet_lab.sh addr I                192.0.2.I
#   scripts/fleet_lab.sh etcd-up LAB DIR I...  an etcd cluster of one member in each host I (data and logs
#                                              in DIR); waits until every member answers (30 s) and prints
#                                              the client endpoints, comma-separated
#   scripts/fleet_lab.sh etcd-start LAB DIR I  (re)start host I's member on its data in DIR (after a kill)
#   scripts/fleet_lab.sh hosts LAB             the lab's host namespaces, one a line
#   scripts/fleet_lab.sh check                 exit 0 when a lab can be made here, else 77 saying why
set -euo pipefail

die() { echo "fleet_lab: $*" >&2; exit 2; }
lab_name() {
  [[ "${1:-}" =~ ^[a-z0-9]{1,12}$ ]] || die "lab name '${1:-}' must be 1-12 of [a-z0-9]"
}
host_index() {
  [[ "${1:-}" =~ ^[0-9]+$ ]] && (( $1 >= 1 && $1 <= 250 )) || die "host '${1:-}' must be 1-250"
}
sw() { echo "gs-$1-sw"; }
host() { echo "gs-$1-h$2"; }

cmd=${1:-}
shift || true
case "$cmd" in
  check)
    if [ "$(id -u)" != 0 ]; then echo "SKIP: the lab needs root (ip netns add)" >&2; exit 77; fi
    command -v ip >/dev/null || { echo "SKIP: no ip (apt-get install iproute2)" >&2; exit 77; }
    probe="gs-probe$$"
    if ! ip netns add "$probe" 2>/dev/null; then echo "SKIP: cannot create a network namespace (ip netns add)" >&2; exit 77; fi
    ok=1
    ip -n "$probe" link add br0 type bridge 2>/dev/null || ok=0
    ip netns del "$probe"
    [ $ok = 1 ] || { echo "SKIP: no bridge devices in this kernel" >&2; exit 77; }
    ;;
  up)
    lab_name "${1:-}"; lab=$1; n=${2:-}
    [[ "$n" =~ ^[0-9]+$ ]] && (( n >= 1 && n <= 250 )) || die "up needs a host count 1-250"
    s=$(sw "$lab")
    ip netns add "$s"
    ip -n "$s" link set lo up
    ip -n "$s" link add br0 type bridge
    # a querier: the bridge forwards multicast to the ports that joined only (else it floods)
    ip -n "$s" link set br0 type bridge mcast_querier 1
    # a general query every second (answered within 0.5 s): a port that went
    # down (partition) loses its groups on the bridge, and its host, which saw
    # only its carrier go, reports them again only when queried
    ip -n "$s" link set br0 type bridge mcast_query_interval 100 mcast_query_response_interval 50
    # IGMPv3 queries: hosts then answer in v3, which has no report
    # suppression; with v2 (the bridge's default) a host that heard another
    # host's report for the group stays silent, and the bridge, whose
    # snooping keeps only the ports it heard, stops forwarding the group to
    # it (seen: servers on hosts 1 and 3 missing from the group, deaf to
    # the re-requests of a recorder)
    ip -n "$s" link set br0 type bridge mcast_igmp_version 3
    ip -n "$s" link set br0 up
    for ((i = 1; i <= n; i++)); do
      h=$(host "$lab" "$i")
      ip netns add "$h"
      ip link add "vh$i" netns "$s" type veth peer name eth0 netns "$h"
      ip -n "$s" link set "vh$i" master br0
      ip -n "$s" link set "vh$i" up
      ip -n "$h" link set lo up
      ip -n "$h" link set lo multicast on
      ip -n "$h" link set eth0 up
      ip -n "$h" addr add "192.0.2.$i/24" dev eth0
      ip -n "$h" route add 224.0.0.0/4 dev eth0
    done
    ;;
  down)
    lab_name "${1:-}"; lab=$1
    for ns in $(ip netns list | awk '{print $1}' | grep -E "^gs-$lab-(h[0-9]+|sw)$" || true); do
      pids=$(ip netns pids "$ns" 2>/dev/null || true)
      [ -n "$pids" ] && kill -9 $pids 2>/dev/null || true
    done
    for ns in $(ip netns list | awk '{print $1}' | grep -E "^gs-$lab-(h[0-9]+|sw)$" || true); do
      # the killed processes may hold the namespace a moment
      for _ in 1 2 3 4 5 6 7 8 9 10; do ip netns del "$ns" 2>/dev/null && break; sleep 0.1; done
    done
    ;;
  exec)
    lab_name "${1:-}"; host_index "${2:-}"
    h=$(host "$1" "$2"); shift 2
    exec ip netns exec "$h" "$@"
    ;;
  kill)
    lab_name "${1:-}"; host_index "${2:-}"
    pids=$(ip netns pids "$(host "$1" "$2")")
    [ -n "$pids" ] && kill -9 $pids 2>/dev/null || true
    ;;
  partition | heal)
    lab_name "${1:-}"; host_index "${2:-}"
    state=down; [ "$cmd" = heal ] && state=up
    ip -n "$(sw "$1")" link set "vh$2" "$state"
    ;;
  loss)
    lab_name "${1:-}"; host_index "${2:-}"
    pct=${3:-}
    [[ "$pct" =~ ^[0-9]+$ ]] && (( pct <= 100 )) || die "loss needs a percentage 0-100"
    command -v nft >/dev/null || die "loss needs nftables (apt-get install nftables)"
    s=$(sw "$1")
    # one chain per host, on the switch: frames coming from host I
    # (a chain named fwd is a syntax error in this nft)
    ip netns exec "$s" nft list table bridge gslab >/dev/null 2>&1 || ip netns exec "$s" nft add table bridge gslab
    ip netns exec "$s" nft list chain bridge gslab "lossy$2" >/dev/null 2>&1 ||
      ip netns exec "$s" nft add chain bridge gslab "lossy$2" "{ type filter hook forward priority 0; }"
    ip netns exec "$s" nft flush chain bridge gslab "lossy$2"
    if (( pct == 100 )); then  # numgen's "< 100" is out of its range
      ip netns exec "$s" nft add rule bridge gslab "lossy$2" iifname "vh$2" drop
    elif (( pct > 0 )); then
      ip netns exec "$s" nft add rule bridge gslab "lossy$2" iifname "vh$2" numgen random mod 100 "<" "$pct" drop
    fi
    ;;
  addr)
    host_index "${1:-}"
    echo "192.0.2.$1"
    ;;
  etcd-up)
    lab_name "${1:-}"; lab=$1; dir=${2:-}; shift 2 || die "etcd-up needs LAB DIR I..."
    [ -n "$dir" ] && [ $# -ge 1 ] || die "etcd-up needs LAB DIR I..."
    command -v etcd >/dev/null || die "no etcd (apt-get install etcd-server)"
    mkdir -p "$dir"
    cluster="" endpoints=""
    for i in "$@"; do
      host_index "$i"
      cluster+="${cluster:+,}e$i=http://192.0.2.$i:2380"
      endpoints+="${endpoints:+,}http://192.0.2.$i:2379"
    done
    # --pre-vote (3.5's default): a member cut off and back does not depose
    # the leader by its higher term
    for i in "$@"; do
      a=192.0.2.$i
      # the command line, for etcd-start after a kill (the data dir then holds the cluster)
      printf '%q ' etcd --name "e$i" --data-dir "$dir/e$i" \
        --listen-client-urls "http://$a:2379" --advertise-client-urls "http://$a:2379" \
        --listen-peer-urls "http://$a:2380" --initial-advertise-peer-urls "http://$a:2380" \
        --initial-cluster "$cluster" --initial-cluster-token "gs-$lab" --initial-cluster-state new \
        --pre-vote --log-level warn >"$dir/e$i.cmd"
      "$0" etcd-start "$lab" "$dir" "$i"
    done
    for i in "$@"; do
      ok=0
      for _ in $(seq 150); do
        if ip netns exec "$(host "$lab" "$i")" etcdctl --endpoints "http://192.0.2.$i:2379" \
             --dial-timeout 1s --command-timeout 1s endpoint health >/dev/null 2>&1; then ok=1; break; fi
        sleep 0.2
      done
      [ $ok = 1 ] || { tail -n 20 "$dir/e$i.log" >&2; die "etcd member e$i (host $i) not healthy within 30 s"; }
    done
    echo "$endpoints"
    ;;
  etcd-start)
    lab_name "${1:-}"; dir=${2:-}; host_index "${3:-}"
    [ -f "$dir/e$3.cmd" ] || die "no $dir/e$3.cmd: start the cluster with etcd-up"
    # detached: output to its log, no terminal, outlives this script
    ip netns exec "$(host "$1" "$3")" setsid sh -c "exec $(cat "$dir/e$3.cmd")" \
      >>"$dir/e$3.log" 2>&1 </dev/null &
    ;;
  hosts)
    lab_name "${1:-}"
    ip netns list | awk '{print $1}' | grep -E "^gs-$1-h[0-9]+$" | sort -V || true
    ;;
  *)
    sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
    exit 2
    ;;
esac
