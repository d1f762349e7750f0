#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-asan/
# (the build of scripts/test.sh --sanitize=address,undefined) and runs
# each one in turn, starting from its seed corpus (configs/, tests/cli/data/,
# encoded messages) and the corpus earlier runs left in build-asan/corpus/.
# Fails on any crash, leak, sanitizer report, timeout (-timeout) or
# allocation beyond the limits; the input that did it is saved in
# build-asan/artifacts/ and replays with `build-asan/fuzz/<target> <file>`.
#   scripts/fuzz.sh                  60 s per target
#   scripts/fuzz.sh --seconds 300    300 s per target
#   scripts/fuzz.sh --runs 5000000   5 million executions per target
#   scripts/fuzz.sh ... scenario_fuzz      one target only
# Prints, per target: executions, executions per second, coverage (cov:
# edges, ft: features) and corpus size.
set -euo pipefail
cd "$(dirname "$0")/.."

limit=(-max_total_time=60)
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    scenario_fuzz | datagram_fuzz) targets+=("$1"); shift ;;
    *) echo "usage: scripts/fuzz.sh [--seconds N | --runs N] [scenario_fuzz] [datagram_fuzz]" >&2; exit 2 ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(scenario_fuzz datagram_fuzz)

scripts/setup.sh
. scripts/lib/build_dir.sh
. scripts/lib/asan_build.sh
asan_build "${targets[*]} fuzz_seeds"
dir=$asan_build_dir
export ASAN_OPTIONS="detect_leaks=1:detect_stack_use_after_return=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

mkdir -p "$dir/artifacts" "$dir/logs"
failed=()
summary=()
for t in "${targets[@]}"; do
  corpus="$dir/corpus/$t"
  mkdir -p "$corpus"
  extra=()
  [ "$t" = scenario_fuzz ] && extra+=(-dict=fuzz/scenario.dict)
  log="$dir/logs/$t.log"
  echo "fuzz: $t ${limit[*]} (log: $log)"
  # -timeout: one input may take 10 s at most; -rss_limit_mb/-malloc_limit_mb:
  # a scenario that asks for more than 2 GB is a finding (the model budget)
  rc=0
  "$dir/fuzz/$t" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=16384 \
    -print_final_stats=1 -artifact_prefix="$dir/artifacts/$t-" "${extra[@]}" \
    "$corpus" "$dir/fuzz/seeds/${t%_fuzz}" </dev/null >"$log" 2>&1 || rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n1)
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9]+[a-zA-Z]*' "$log" | tail -n1 || true)
  line="$t: ${execs:-?} executions, ${speed:-?}/s, ${cov:-no coverage line}, corpus $(ls "$corpus" | wc -l) files"
  summary+=("$line")
  if [ $rc -ne 0 ]; then
    failed+=("$t")
    echo "fuzz: $t FAILED (exit $rc); the report:" >&2
    grep -m1 -B2 -A30 -E '==[0-9]+==ERROR|runtime error|deadly signal|Test unit written|uncaught exception|out-of-memory|timeout' "$log" >&2 || tail -n 40 "$log" >&2
  fi
done
printf 'fuzz: %s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $dir/artifacts/, logs in $dir/logs/)" >&2
  exit 1
fi
