# Sourced by test.sh and fuzz.sh (after build_dir.sh): the one clang build
# that both the ASan + UBSan test suite and the libFuzzer targets use, so CI
# compiles the tree once for the two gates. GROUNDSIM_FUZZ=ON instruments
# every target with -fsanitize=fuzzer-no-link,address,undefined (top-level
# CMakeLists.txt): the tests run with the fuzzers' coverage counters too,
# which cost a little time and change nothing they check.
#   asan_build "<targets, empty for all>"
asan_build_dir=build-asan
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
