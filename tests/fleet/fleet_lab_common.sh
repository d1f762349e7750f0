# Sourced by the fleet's lab tests (failover, placement, shards): the lab
# they share. Needs $lab (scripts/fleet_lab.sh).
#   fleet_lab_begin PREFIX   checks (exit 77 with the reason where no lab can
#                            be made or etcd is missing), a lab named
#                            PREFIX<pid> of 7 hosts torn down on exit (and
#                            those of killed earlier runs): hosts 1-3 for
#                            servers, 4 for clients, a 3-member etcd in
#                            hosts 5-7 (as the issue lays the lab out: a
#                            server's death is not an etcd member's);
#                            sets name, tmp, url, endpoints
#   fleet_start_servers ARG...  groundsim-server ($server) s1-s3 in hosts 1-3
#                            (one worker, --address, the lab's bus and etcd,
#                            then ARG...), logs in $tmp/s<i>.log, pids in
#                            pid[i]; waits until they joined (fleet_wait_joined)
#   fleet_start_servers_via_relays KIND ARG...  as fleet_start_servers, but
#                            each server reaches etcd through
#                            answer_loss_relay.py KIND in its own host
#                            (127.0.0.1:23790, listed first, so its client
#                            prefers it; logs $tmp/relay<i>.log); else fail
#   fleet_wait_joined        waits until servers s1-s3 (logs $tmp/s<i>.log)
#                            said they joined; else calls the test's fail
#   fleet_owner_of SID       "SERVER EPOCH" of session SID in `groundsim list`
#                            ($client, from host 4); nothing while unlisted
#   fleet_session_t SID      the simulated time of SID in `groundsim list`
#   fleet_wait_session_t SID T  waits until SID has run T s of simulated time
#                            (however long the machine takes); else fail
#   fleet_wait_owner SID     sets owner and epoch once SID is listed; else
#                            calls the test's fail
#   fleet_wait_new_owner SID OLD [WHY]  sets new and epoch once a server
#                            other than OLD lists SID; else fail
#                            "no server took session SID over within 120 s[WHY]"
#   fleet_dump NAME FILE [N]  the servers' last 8 lines and FILE's last N (8)
#                            on stderr, for a test's fail()
#   fleet_record SCENARIO    `groundsim record --create` of a 12 s real-time
#                            session at 200 Hz from host 4 into $tmp/rec.mcap
#                            (stderr $tmp/rec.err); sets recorder (its pid)
#                            and sid, else fail "no session was created"
#   fleet_recording_complete SID  `groundsim inspect` of $tmp/rec.mcap: prints
#                            SID's ledger; fail unless it lists 0 lost states
#                            and the file ended properly
# Their wall-clock limits (60-120 s) only end a hung test.

fleet_lab_begin() {
  local prefix=$1
  "$lab" check || exit $?
  if ! command -v etcd >/dev/null; then echo "SKIP: no etcd (apt-get install etcd-server)" >&2; exit 77; fi
  name="$prefix$$"
  tmp=$(mktemp -d "/tmp/groundsim-$prefix-XXXXXX")
  # GROUNDSIM_KEEP_FAILED=DIR keeps a failed test's files (logs, recordings) in DIR
  trap 'rc=$?; [ $rc -eq 0 ] || [ $rc -eq 77 ] || echo "exit $rc; the last command that failed: ${last_failed:-none}" >&2
    "$lab" down "$name" || true; if [ $rc -ne 0 ] && [ -n "${GROUNDSIM_KEEP_FAILED:-}" ]; then
    mkdir -p "$GROUNDSIM_KEEP_FAILED" && cp -r "$tmp" "$GROUNDSIM_KEEP_FAILED/"; fi; rm -rf "$tmp"' EXIT
  trap 'exit 130' INT TERM
  # under set -e a failing command ends the test with no FAIL line of its
  # own: the exit names the last one (CI keeps only the output)
  last_failed=""
  trap 'last_failed="$(basename "$0") line $LINENO: $BASH_COMMAND"' ERR
  local old
  for old in $(ip netns list | awk '{print $1}' | sed -n "s/^gs-$prefix\([0-9]\{1,\}\)-sw\$/\1/p"); do
    kill -0 "$old" 2>/dev/null || "$lab" down "$prefix$old" || true
  done
  "$lab" up "$name" 7
  url='udpm://239.255.76.67:7667?ttl=1'
  endpoints=$("$lab" etcd-up "$name" "$tmp" 5 6 7)
}

fleet_wait_joined() {
  local i
  for i in 1 2 3; do
    for _ in $(seq 600); do grep -q "^fleet: server s$i joined" "$tmp/s$i.log" && break; sleep 0.1; done
    grep -q "^fleet: server s$i joined" "$tmp/s$i.log" || fail "server s$i did not join the fleet"
  done
}

fleet_start_servers() {
  local i
  for i in 1 2 3; do
    "$lab" exec "$name" "$i" "$server" --lcm-url "$url" --etcd "$endpoints" --server-id "s$i" \
      --address "$("$lab" addr "$i")" --workers 1 "$@" >"$tmp/s$i.log" 2>&1 &
    pid[$i]=$!
  done
  fleet_wait_joined
}

fleet_start_servers_via_relays() {
  local kind=$1 direct=$endpoints i
  shift
  for i in 1 2 3; do
    "$lab" exec "$name" "$i" python3 "$(dirname "${BASH_SOURCE[0]}")/answer_loss_relay.py" 23790 "$direct" /groundsim \
      "$kind" >"$tmp/relay$i.log" 2>&1 &
    for _ in $(seq 300); do grep -qs "relay: listening" "$tmp/relay$i.log" && break; sleep 0.1; done
    grep -qs "relay: listening" "$tmp/relay$i.log" || fail "the relay of host $i did not start: $(cat "$tmp/relay$i.log")"
  done
  endpoints="http://127.0.0.1:23790,$direct"
  fleet_start_servers "$@"
  endpoints=$direct
}

# waits until every server's registration in etcd carries the capacity of
# its first heartbeat (workers and load beside the counts it registered
# with): placement reads them
fleet_wait_capacities() {
  local n=0
  for _ in $(seq 600); do
    n=$("$lab" exec "$name" 4 etcdctl --endpoints "$endpoints" get --prefix /groundsim/servers/ --print-value-only \
        2>/dev/null | grep -c '"workers"') || true
    [ "${n:-0}" -ge 3 ] && return 0
    sleep 0.1
  done
  fail "the servers' registrations carry no heartbeat's capacity (${n:-0} of 3)"
}

fleet_dump() {
  local i
  for i in 1 2 3; do echo "--- server s$i (last lines)" >&2; tail -n 8 "$tmp/s$i.log" >&2 || true; done
  echo "--- $1 (last lines)" >&2; tail -n "${3:-8}" "$2" >&2 || true
}

fleet_record() {
  "$lab" exec "$name" 4 "$client" record --create "$1" --session-duration 12 --publish-rate 200 \
    --out "$tmp/rec.mcap" --lcm-url "$url" --timeout 10 >"$tmp/rec.out" 2>"$tmp/rec.err" &
  recorder=$!
  for _ in $(seq 600); do [ -s "$tmp/rec.out" ] && break; sleep 0.1; done
  sid=$(tail -n 1 "$tmp/rec.out")
  [ -n "$sid" ] || fail "no session was created"
}

fleet_recording_complete() {
  "$client" inspect "$tmp/rec.mcap" >"$tmp/inspect.txt"
  local ledger
  ledger=$(grep "^ledger/$1" "$tmp/inspect.txt" || true)
  echo "$ledger"
  echo "$ledger" | grep -q "state_lost_count 0" || fail "the ledger lists lost states: $ledger"
  grep -q "^end *complete" "$tmp/inspect.txt" || fail "the recording did not end properly"
}

fleet_owner_of() {
  "$lab" exec "$name" 4 "$client" list --lcm-url "$url" --timeout 2 2>/dev/null |
    awk -v s="$1" '$1 == s { print $(NF-2), $(NF-1) }'
}

# the simulated time of session $1 in `groundsim list` (empty: not listed)
fleet_session_t() {
  "$lab" exec "$name" 4 "$client" list --lcm-url "$url" --timeout 2 2>/dev/null | awk -v s="$1" '$1 == s { print $5 }'
}

# waits until session $1 has run $2 s of simulated time (ceiling: 10 minutes
# of tries, only for a hung session), however long a loaded machine takes
fleet_wait_session_t() {
  local t=""
  for _ in $(seq 1200); do
    t=$(fleet_session_t "$1") || true
    [ -n "$t" ] && awk -v t="$t" -v w="$2" 'BEGIN { exit !(t >= w) }' && return 0
    sleep 0.2
  done
  fail "session $1 did not reach $2 s of simulated time (listed at '${t}')"
}

fleet_wait_owner() {
  owner=""
  for _ in $(seq 300); do read -r owner epoch < <(fleet_owner_of "$1") || true; [ -n "$owner" ] && break; sleep 0.2; done
  [ -n "$owner" ] || fail "session $1 is listed by no server"
}

fleet_wait_new_owner() {
  new=""
  for _ in $(seq 1200); do
    read -r new epoch < <(fleet_owner_of "$1") || true
    [ -n "$new" ] && [ "$new" != "$2" ] && break
    new=""
    sleep 0.1
  done
  [ -n "$new" ] || fail "no server took session $1 over within 120 s${3:-}"
}
