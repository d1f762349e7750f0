# Sourced by test.sh and fuzz.sh (after build_dir.sh): the one clang build
# that both the ASan + UBSan test suite and the libFuzzer targets use, so CI
# compiles the sanitized code once for the two gates. GROUNDSIM_FUZZ=ON
# instruments every target with -fsanitize=fuzzer-no-link,address,undefined
# (top-level CMakeLists.txt): the tests run with the fuzzers' coverage
# counters too, which cost a little time and change nothing they check.
# Only the targets below are built: not the web bridge, the Python module
# (off in any sanitized build), the integration suites or groundsim-server,
# whose tests run in the plain build (and the integration ones under TSan).
#   asan_build "<targets, empty for all>"

asan_build_dir=build-asan
# the ASan + UBSan suite's executables (ctest -L '^(unit|cli)$'): the
# in-process suites and the groundsim binary the CLI tests run
asan_test_targets="physics_tests physics_shared_model_tests vehicle_tests scenario_tests accuracy_tests terrain_tests
  experiments_tests experiments_alloc_tests session_tests contact_tests kernel_tests record_tests recording_tests
  race_tests race_session_tests drivers_tests mcap_sample groundsim"
# scripts/fuzz.sh's: the libFuzzer targets and their seed corpora
asan_fuzz_targets="scenario_fuzz datagram_fuzz fuzz_seeds"

asan_build() {
  # a build-asan/ configured with another compiler (gcc, before the gates
  # shared one build) cannot be reconfigured in place
  if [ -f "$asan_build_dir/CMakeCache.txt" ] &&
     ! grep -q '^CMAKE_CXX_COMPILER:.*clang++-14' "$asan_build_dir/CMakeCache.txt"; then
    rm -rf "$asan_build_dir"
  fi
  build_dir "$asan_build_dir" "$1" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
    -DGROUNDSIM_FUZZ=ON -DGROUNDSIM_BUILD_TESTS=ON -DGROUNDSIM_BUILD_BENCH=OFF
  local symbolizer=/usr/lib/llvm-14/bin/llvm-symbolizer
  if [ -x "$symbolizer" ]; then export ASAN_SYMBOLIZER_PATH="$symbolizer"; fi
}

# asan_check_built: fails when a GoogleTest executable that is not built
# here would hold tests (ctest lists it as <target>_NOT_BUILT, without
# labels, so -L would leave its tests out silently): a new in-process suite
# belongs in asan_test_targets. web_bridge_tests and web_foxglove_tests (the
# bridge's) run in the plain build only.
asan_check_built() {
  local missing
  missing=$(ctest --test-dir "$asan_build_dir" -N 2>/dev/null |
    sed -n 's/^ *Test *#[0-9]*: \(.*\)_NOT_BUILT$/\1/p' | grep -vx -e 'web_bridge_tests' -e 'web_foxglove_tests' || true)
  if [ -n "$missing" ]; then
    echo "asan_build: not built in $asan_build_dir, so not run under ASan: $(tr "\n" " " <<<"$missing")" >&2
    echo "asan_build: add it to asan_test_targets (scripts/lib/asan_build.sh), or to the exceptions in asan_check_built" >&2
    return 1
  fi
}
