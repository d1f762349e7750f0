# A recording read by MCAP implementations other than ours, for the record
# tests (sourced, POSIX sh; needs $src, the source tree, and $build):
#   - MCAP's own Python library (PyPI mcap, with jsonschema), through
#     tests/recording/mcap_py_check.py in the venv of scripts/setup-python.sh
#     (env GROUNDSIM_VENV, default $HOME/.cache/groundsim/venv; CMake passes it);
#   - npm's @mcap/core, through tests/recording/mcap_read.mjs (node_modules of
#     web/, or of the build's web page: npm install in web/).
# A reader that is not installed is never a pass: the test goes on with its
# other checks, and mcap_checks_done ends it with 77 (CTest: skipped),
# naming what could not run. A reader that finds a problem fails the test.
#
#   mcap_py FILE REPORT.json [--expect-cut]   0: checked, sound; 1: not installed (noted)
#   mcap_node FILE REPORT.json [--topics T]   0: read; 1: not installed (noted)
#   mcap_py_ledgers REPORT.json...            the messages the library read are
#       exactly the ledgers' received + repaired, stream by stream (the
#       reports of a split recording's parts, oldest first: their messages
#       together against the last part's ledgers)
#   mcap_checks_done                          PASS, or SKIP (exit 77) naming what was not checked
# Both print their summary; a problem found prints it and exits 1. Call them
# as `if mcap_py ...; then ...; fi` (set -e does not stop inside them).
mcap_skipped=""
mcap_note_skip() {  # each reason once
  case "; $mcap_skipped;" in *"; $*;"*) ;; *) mcap_skipped="${mcap_skipped:+$mcap_skipped; }$*" ;; esac
}

mcap_py() {
  _f=$1; _out=$2; shift 2
  _venv=${GROUNDSIM_VENV:-${HOME:-/root}/.cache/groundsim/venv}
  if [ ! -x "$_venv/bin/python" ]; then
    mcap_note_skip "no Python venv at $_venv: MCAP's Python library did not read the recording (scripts/setup-python.sh)"
    return 1
  fi
  _rc=0
  "$_venv/bin/python" "$src/tests/recording/mcap_py_check.py" "$_f" "$@" > "$_out" 2> "$_out.err" || _rc=$?
  cat "$_out.err"
  case $_rc in
    0) return 0 ;;
    77) mcap_note_skip "$(grep -m1 '^SKIP' "$_out.err" | sed 's/^SKIP: //')"; return 1 ;;
    *) echo "FAIL: MCAP's Python library (mcap_py_check.py, exit $_rc) on $(basename "$_f")"; exit 1 ;;
  esac
}

mcap_py_ledgers() {
  python3 - "$@" <<'PY' || { echo "FAIL: MCAP's Python library read other messages than the ledgers hold"; exit 1; }
import json, sys
reports = [json.load(open(p)) for p in sys.argv[1:]]
def seqs(text):
    out = set()
    for part in filter(None, text.split(",")):
        a, _, z = part.partition("-")
        out.update(range(int(a), int(z or a) + 1))
    return out
read, repeated = {}, {}
for r in reports:
    for topic, text in r["sequences"].items():
        s = seqs(text)
        repeated[topic] = repeated.get(topic, 0) + r["repeated_sequences"].get(topic, 0) + len(read.get(topic, set()) & s)
        read[topic] = read.get(topic, set()) | s
ledgers = reports[-1]["metadataRecords"]
bad, said = [], {}
streams = [("ledger/events", "event_", [t for t in read if t == "/events" or t.endswith("/events")])]
for name in ledgers:
    if name.startswith("ledger/") and name != "ledger/events":
        sid = name[len("ledger/"):]
        for prefix, kind in (("state_", "state"), ("car_state_", "car_state"), ("contact_", "contact"), ("applied_", "applied")):
            streams.append((name, prefix, [f"/{sid}/{kind}"]))
if len(streams) == 1: bad.append("no session ledger in the file")
for name, prefix, topics in streams:
    l = ledgers.get(name, {})
    if prefix + "received" not in l:
        if any(read.get(t) for t in topics): bad.append(f"{topics}: messages, but {name} has no {prefix}ledger")
        continue
    want = seqs(l[prefix + "received"]) | seqs(l[prefix + "repaired"])
    got = set().union(*(read.get(t, set()) for t in topics))
    n = sum(repeated.get(t, 0) for t in topics)
    said[prefix[:-1]] = said.get(prefix[:-1], 0) + len(got)
    if got != want or n:
        bad.append(f"{name} {prefix}: the file holds {len(got)} seqs ({n} repeated), the ledger {len(want)} received + repaired; "
                   f"only in the file {sorted(got - want)[:5]}, only in the ledger {sorted(want - got)[:5]}")
if not bad:
    print("MCAP's Python library against the ledgers: " + ", ".join(f"{n} {k}" for k, n in said.items()) +
          " seqs, each once, the ledgers' received + repaired")
for b in bad: print("FAIL:", b)
sys.exit(1 if bad else 0)
PY
}

mcap_node() {
  _f=$1; _out=$2; shift 2
  _modules=""
  for _m in "$src/web/node_modules" "$build/web/node_modules"; do
    [ -d "$_m/@mcap/core" ] && _modules=$_m && break
  done
  if [ -z "$_modules" ] || ! command -v node > /dev/null; then
    mcap_note_skip "no node with @mcap/core in web/node_modules or the build's: npm's reader did not read the recording (npm install in web/)"
    return 1
  fi
  GROUNDSIM_MCAP_NODE_MODULES=$_modules node "$src/tests/recording/mcap_read.mjs" "$_f" "$@" > "$_out" ||
    { echo "FAIL: @mcap/core could not read $(basename "$_f")"; exit 1; }
  return 0
}

mcap_checks_done() {
  if [ -n "$mcap_skipped" ]; then
    echo "SKIP: every other check passed, but not checked: $mcap_skipped"
    exit 77
  fi
  echo PASS
}
