#!/bin/sh
# The compose logger: waits until the server answers, creates a real time
# session that runs until stopped (SCENARIO, default the plain scene) and
# records it to logs/<session>.csv. On SIGTERM/SIGINT (container stop) it
# ends the log cleanly and stops its session, so no session outlives it.
set -u
scenario=${SCENARIO:-/usr/local/share/groundsim/configs/plain.json}
tries=${READY_TRIES:-30}

# readiness: the server answers `list` (each try waits up to 1 s for the reply)
n=0
until groundsim list --timeout 1 >/dev/null 2>&1; do
  n=$((n + 1))
  if [ "$n" -ge "$tries" ]; then
    echo "groundsim-logger: no answer from groundsim-server after $tries tries" >&2
    exit 1
  fi
  sleep 1
done

id=$(groundsim create "$scenario" --duration -1 | tail -n 1) || exit 1
echo "groundsim-logger: session $id -> logs/$id.csv"

log_pid=""
finish() {
  [ -n "$log_pid" ] && kill -TERM "$log_pid" 2>/dev/null && wait "$log_pid"
  if groundsim stop "$id" >/dev/null 2>&1; then
    echo "groundsim-logger: stopped session $id"
  else
    echo "groundsim-logger: could not stop session $id" >&2
  fi
}
trap 'finish; exit 0' TERM INT

groundsim log "$id" --csv "logs/$id.csv" &
log_pid=$!
wait "$log_pid"
rc=$?
# the log ended by itself (a signal interrupts `wait` and runs the trap instead)
log_pid=""
finish
exit "$rc"
