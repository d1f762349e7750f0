#!/usr/bin/env bash
# Installs what is missing, builds, and runs the tests (unit, CLI and the LCM
# integration tests, each in its own network namespace). Extra arguments go
# to ctest (e.g. -R physics).
#   scripts/test.sh                             every test, Release build in build/
#   scripts/test.sh --sanitize=address,undefined  the in-process suites and the CLI tests
#                                               (ctest -L 'unit|cli') under ASan + UBSan, in
#                                               build-asan/ (clang; the build scripts/fuzz.sh
#                                               uses too, so its targets are built here too)
#   scripts/test.sh --sanitize=thread           the integration tests (the multi-threaded
#                                               server and clients) and the session tests
#                                               under TSan, in build-tsan/
# The browser (web), Python and layer tests run in the plain build only; the
# integration tests in the plain build and under TSan (docs/reliability.md, CI).
# A sanitizer report makes the process exit non-zero, so the test fails;
# the report is in the test's output.
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize=""
if [[ "${1:-}" == --sanitize=* ]]; then
  sanitize=${1#--sanitize=}
  shift
fi

scripts/setup.sh
. scripts/lib/build_dir.sh
ctest_args=(--output-on-failure -j "${JOBS:-2}" --timeout 600)

# A sanitized suite is 2-15x slower, and tests that wait on the wall clock
# (a client's start-up, a heartbeat, a page's first frame) can miss on a
# loaded machine: a failed test is run again, up to REPEAT runs in all, but a
# sanitizer report (REPORT, a grep -E pattern) in any run, passed or failed,
# fails the stage. The output of every run is kept in LOG.
#   sanitized_ctest NAME LOG REPEAT REPORT COMMAND...   (COMMAND: ctest and its arguments)
sanitized_ctest() {
  local name=$1 log=$2 repeat=$3 report=$4 rc=0
  shift 4
  "$@" -V --repeat "until-pass:$repeat" >"$log" 2>&1 || rc=$?
  # ctest's verdicts only (the layer probes' expected compile failures print FAILED too)
  grep -E '^[0-9]+% tests passed|\*\*\*Failed|^The following tests FAILED|^[[:space:]]+[0-9]+ - .*\((Failed|Skipped|Timeout)\)' "$log" || true
  if grep -qE "$report" "$log"; then
    echo "test.sh: $name reports (in $log):" >&2
    grep -E -A30 "$report" "$log" | head -n 120 >&2
    exit 1
  fi
  [ $rc -eq 0 ] || { echo "test.sh: $name run failed (log: $log)" >&2; tail -n 60 "$log" >&2; }
  exit $rc
}

# skipped_report DIR OUTPUT: the tests the ctest run whose output is in
# OUTPUT skipped (its "did not run" list), each with the reason it printed
# (the first SKIP or "skipped" line of its block in DIR's LastTest.log)
skipped_report() {
  local log=$1/Testing/Temporary/LastTest.log names
  names=$(sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Skipped)$/\1/p' "$2")
  if [ -z "$names" ]; then
    echo "test.sh: nothing skipped"
    return 0
  fi
  echo "test.sh: $(wc -l <<<"$names") skipped:"
  local name reason
  while read -r name; do
    reason=$(awk -v t="$name" '
      /^[0-9]+\/[0-9]+ Testing: / { inside = ($3 == t) }
      inside && !/^Command:/ && (/SKIP/ || /skipped/) { print; exit }' "$log" 2>/dev/null)
    echo "  $name: ${reason:-(no reason printed)}"
  done <<<"$names"
}

case "$sanitize" in
  "")
    scripts/build.sh
    rc=0
    ctest --test-dir build "${ctest_args[@]}" "$@" 2>&1 | tee build/ctest-output.log || rc=$?
    skipped_report build build/ctest-output.log
    exit $rc
    ;;
  address,undefined | undefined,address)
    . scripts/lib/asan_build.sh
    # only what its tests run, and the fuzz targets (the next gate) in the same ninja run
    asan_build "$asan_test_targets $asan_fuzz_targets"
    asan_check_built
    dir=$asan_build_dir
    # leaks are errors too; a UBSan report stops the process (-fno-sanitize-recover)
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=1:strict_string_checks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
    # the one-process tests: unit (the GoogleTest suites) and cli (groundsim run
    # on files); not web, python, integration (multi-process; TSan's) or layers
    # (build probes, nothing runs). Five long physics runs are left out: 150-250 s
    # each under ASan (half the stage's test time, 2026-12-02), seconds of the
    # report's car at dt 5e-5 through code the shorter contact, ground, tyre and
    # heightfield tests run under ASan too; they run in the plain suite. So are
    # five pilots of whole scenes (accuracy.*: 42-130 s each under ASan,
    # 2026-12-03, 7.5 of the stage's 17 CPU minutes): the pilot's code runs
    # under ASan in the shorter accuracy tests (the slalom, the lone wheel).
    # Of the stability check over every shipped scene (accuracy.Shipped/
    # StableChoice), the scenes whose pilot runs longest under ASan (23-212 s
    # each, 2026-12-06: 1,450 of the stage's 1,830 CPU seconds) run in the plain
    # suite only; the same chooser runs under ASan on the others (plain,
    # sedan_hills, sedan_skidpad, the lone wheel, ...).
    sanitized_ctest ASan "$dir/asan-ctest.log" 2 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:' \
      ctest --test-dir "$dir" "${ctest_args[@]}" -L '^(unit|cli)$' \
      -E '^(physics\.Contact\.(SignFrictionOfTheReportCreepsWhereStickSlipHolds|ParkedCarOnTwentyDegreesDoesNotCreep)|physics\.ReportExperiments\.CosineCarFailsToClimbTheCrestAndSettlesInTheValley|physics\.DeformableTyres\.CarryTheCarOnAFlattenedPatchAndTransmitDriveTorque|terrain\.HeightfieldRolling\.ReportCarOnASampledCosineFollowsTheAnalyticRun|accuracy\.Chooser\.(MeetsTheToleranceOnTheReportsDownhill|MeetsTheToleranceAcrossAnImpact|PilotsTheWholeSceneAndFallsBackWithinTheBudget)|accuracy\.LiveEstimate\.WithinAFactorOfThreeOnTheDownhill|accuracy\.ModelChoice\.TakesTheCircleOnlyWhereItsDifferenceFitsTheTolerance|accuracy\.Shipped/StableChoice\.NoChosenSettingDrawsAStabilityWarning/(contact_|race_|accuracy_deformable_tyres|accuracy_eight_cars|hills|cosine|cone|expression|parabola|bumps|uphill|downhill).*)$' \
      "$@"
    ;;
  thread)
    dir=build-tsan
    # only the multi-threaded code's tests: the server, the clients and every
    # integration suite (ctest -L integration), and the session layer in process
    # (session_tests: scheduler workers, LCM's receive thread); the other suites
    # are single-threaded
    build_dir "$dir" "groundsim-server groundsim service_integration_tests lifecycle_integration_tests
      hostile_integration_tests controls_integration_tests vec_integration_tests assets_integration_tests session_tests" \
      -DCMAKE_BUILD_TYPE=Release -DGROUNDSIM_SANITIZE=thread -DGROUNDSIM_BUILD_BENCH=OFF
    # the suppressions name uninstrumented libraries only (glib under LCM)
    export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/support/tsan.supp${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
    # TSan's shadow memory needs the classic address layout: no ASLR (a
    # personality flag, inherited by the test processes through unshare and exec)
    # Two tests are left out: they assert that a real-time session keeps
    # pace with the wall clock (torque in force for 0.5 s of wall time,
    # 0.5 s simulated within a wall-time window), which TSan's 5-15x
    # slowdown breaks on 2 cores. They run in the plain suite.
    # integration.MetricsServerAndBridge needs groundsim-web, which is not
    # built here (the bridge's tests run in the plain build only).
    # The other integration tests run, up to 3 times each (sanitized_ctest).
    sanitized_ctest ThreadSanitizer "$dir/tsan-ctest.log" 3 'WARNING: ThreadSanitizer' \
      setarch "$(uname -m)" -R ctest --test-dir "$dir" "${ctest_args[@]}" \
      -R '^(integration|session)\.' \
      -E '^integration\.(lifecycle\.(CommandTimeoutReleasesTheTorque|PauseFreezesSimulatedTime)|MetricsServerAndBridge)$' \
      "$@"
    ;;
  *)
    echo "test.sh: --sanitize takes address,undefined or thread, got '$sanitize'" >&2
    exit 2
    ;;
esac
