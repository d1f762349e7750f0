#!/bin/sh
# mcap_py_check.py (MCAP's own Python library) on files of our McapWriter,
# and that it catches what it must: a sample written by mcap_sample passes;
# the same file cut (as a killed recorder leaves it) passes with
# --expect-cut, naming the cut, and fails without it; a byte flipped in
# the data section, or in the summary, fails; without the mcap package
# (an interpreter without site-packages) it exits 77 saying SKIP.
#   mcap_py_selftest.sh VENV MCAP_SAMPLE     (CTest: recording.PythonMcapLibraryChecksOurFiles)
set -eu
venv=$1; sample=$2; here=$(cd "$(dirname "$0")" && pwd); check=$here/mcap_py_check.py
py=$venv/bin/python
if [ ! -x "$py" ]; then
  echo "SKIP: no Python venv at $venv: MCAP's Python library is not installed (scripts/setup-python.sh)"; exit 77
fi
dir=$(mktemp -d); trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# rc CMD...: the exit code of CMD in $_rc (its stdout to $dir/out.json, its
# summary line and first FAIL shown)
rc() {
  _rc=0; "$@" > "$dir/out.json" 2> "$dir/err.txt" || _rc=$?
  grep -m1 "^mcap_py_check\|^SKIP" "$dir/err.txt" || true; grep -m1 "^FAIL" "$dir/err.txt" || true
}
field() { python3 -c 'import json, sys; print(eval(sys.argv[2], {}, json.load(open(sys.argv[1]))))' "$dir/out.json" "$1"; }

# the library, missing: 77, SKIP
rc /usr/bin/python3 -S "$check" "$dir/none.mcap"
[ $_rc = 77 ] && grep -q "^SKIP: .*scripts/setup-python.sh" "$dir/err.txt" || fail "without the mcap package: exit $_rc, not 77 with SKIP"

"$sample" write "$dir/s.mcap" 4 4000 3 > /dev/null
rc "$py" "$check" "$dir/s.mcap"
[ $_rc = 0 ] || fail "our writer's sample: exit $_rc"
[ "$(field messages)" = 16000 ] && [ "$(field 'len(topics)')" = 4 ] && [ "$(field decoded)" = 16000 ] ||
  fail "not every message read and decoded: $(field messages) messages, $(field decoded) decoded"
[ "$(field chunks)" -ge 8 ] || fail "$(field chunks) chunks: too few to test the cut inside the data"

size=$(stat -c %s "$dir/s.mcap")
head -c $((size * 6 / 10)) "$dir/s.mcap" > "$dir/cut.mcap"
rc "$py" "$check" "$dir/cut.mcap" --expect-cut
[ $_rc = 0 ] || fail "the cut file with --expect-cut: exit $_rc"
case $(field end) in cut:*"cut by the end of the file"*) ;; *) fail "the cut is not named: $(field end)" ;; esac
n=$(field messages)
[ "$n" -gt 0 ] && [ "$n" -lt 16000 ] || fail "the cut file: $n messages"
case $(field indexed_reader) in refused*) ;; *) fail "the indexed reader did not refuse the cut file" ;; esac
rc "$py" "$check" "$dir/cut.mcap"
[ $_rc = 1 ] || fail "the cut file without --expect-cut: exit $_rc, not 1"
rc "$py" "$check" "$dir/s.mcap" --expect-cut
[ $_rc = 1 ] || fail "the complete file with --expect-cut: exit $_rc, not 1"

# a byte flipped: in the data section (a chunk), in the summary
flip() {  # flip FILE OFFSET OUT
  python3 -c 'import sys; b = bytearray(open(sys.argv[1], "rb").read()); b[int(sys.argv[2])] ^= 0x20; open(sys.argv[3], "wb").write(b)' "$@"
}
for at in $((size / 3)) $((size / 2)) $((size - 60)); do
  flip "$dir/s.mcap" $at "$dir/bad.mcap"
  rc "$py" "$check" "$dir/bad.mcap"
  [ $_rc = 1 ] || fail "a byte flipped at $at of $size: exit $_rc, not 1"
done
# ... and in the data section of the cut file
flip "$dir/cut.mcap" $((size / 4)) "$dir/badcut.mcap"
rc "$py" "$check" "$dir/badcut.mcap" --expect-cut
[ $_rc = 1 ] || fail "the cut file with a byte flipped, --expect-cut: exit $_rc, not 1"
echo PASS
