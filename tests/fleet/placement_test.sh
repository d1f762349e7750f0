#!/usr/bin/env bash
# Placement of creates in a fleet (issue 20, docs/fleet.md): 3 servers and a
# 3-member etcd in lab hosts 1-3, a client in host 4 that creates 60
# sessions, one `groundsim create` after another, as any client would
# (nothing in the client knows of the fleet), lockstep so that 60 sessions
# cost no CPU while they wait. Checked with `groundsim list`
# (its SERVER column): every create was taken by exactly one server (60
# sessions listed, 60 distinct ids), and
#   spread: each server holds 20 +- 4;
#   packed (--max-sessions 25): the servers fill one after another, 25, 25, 10.
# Prints the create-to-reply times (p50, p99; figures, not verdicts) and,
# with spread, 60 more creates of real time sessions by service_bench
# (`firststate`: the create request to the session's first state, p50 and
# p99; a figure for docs/fleet.md, not a verdict).
#   tests/fleet/placement_test.sh FLEET_LAB_SH GROUNDSIM_SERVER GROUNDSIM SCENARIO spread|packed [SERVICE_BENCH LIGHT_SCENARIO]
set -euo pipefail
lab=$1 server=$2 client=$3 scenario=$4 placement=$5 bench=${6:-} light=${7:-}
. "$(dirname "$0")/fleet_lab_common.sh"
fleet_lab_begin fp
fail() {
  echo "FAIL: $*" >&2
  for i in 1 2 3; do echo "--- server s$i (last lines)" >&2; tail -n 8 "$tmp/s$i.log" >&2 || true; done
  exit 1
}
max=64
[ "$placement" = packed ] && max=25
# 60 creates from this one client: no per-client bounds (--client-*: 0)
fleet_start_servers --placement "$placement" --max-sessions "$max" --client-sessions 0 --client-creates 0 --quiet
fleet_wait_capacities  # every server has beaten once: the capacities are in the members' registrations

for k in $(seq 60); do
  t0=$(date +%s%N)
  "$lab" exec "$name" 4 "$client" create "$scenario" --lcm-url "$url" --mode lockstep --timeout 10 \
    --token-file "$tmp/tokens.json" >"$tmp/create.out" 2>"$tmp/create.err" || fail "create $k: $(cat "$tmp/create.err")"
  t1=$(date +%s%N)
  echo $(( (t1 - t0) / 1000000 )) >>"$tmp/ms"
done
# the listing is the servers' heartbeats: wait until they list all 60 (a
# loaded machine's heartbeat comes late), for at most 60 tries
for _ in $(seq 60); do
  "$lab" exec "$name" 4 "$client" list --lcm-url "$url" --timeout 5 >"$tmp/list" || fail "list: $?"
  [ "$(tail -n +2 "$tmp/list" | grep -c .)" -ge 60 ] && break
  sleep 0.5
done
python3 - "$tmp/list" "$tmp/ms" "$placement" <<'PY'
import sys, collections
rows = [l.split() for l in open(sys.argv[1]).read().splitlines()[1:] if l.strip()]
ids = [r[0] for r in rows]
servers = collections.Counter(r[-3] for r in rows)
ms = sorted(int(x) for x in open(sys.argv[2]))
p = lambda q: ms[min(len(ms) - 1, int(q * len(ms)))]
print(f"{len(ids)} sessions on {dict(sorted(servers.items()))}; create to reply p50 {p(0.5)} ms, p99 {p(0.99)} ms "
      f"(a groundsim create process each, in a lab host)")
if len(ids) != 60 or len(set(ids)) != 60:
    sys.exit(f"FAIL: {len(ids)} sessions listed ({len(set(ids))} distinct), not 60")
counts = sorted(servers.values(), reverse=True)
if sys.argv[3] == "spread":
    if len(counts) != 3 or any(abs(c - 20) > 4 for c in counts):
        sys.exit(f"FAIL: spread placed {counts}, not 20 +- 4 each")
else:
    if counts != [25, 25, 10]:
        sys.exit(f"FAIL: packed placed {counts}, not 25, 25, 10")
PY
if [ "$placement" = spread ] && [ -n "$bench" ] && [ -x "$bench" ]; then
  "$lab" exec "$name" 4 "$bench" --lcm-url "$url" firststate "$light" --count 60 | sed 's/^/figure: /' ||
    fail "service_bench firststate failed"
fi
