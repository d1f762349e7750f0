# Sourced by build.sh, test.sh and fuzz.sh: configures and builds one build
# directory. ccache is used when it is installed (CI has none: a clean build).
# JOBS (default 2): the Eigen-heavy units need ~1 GB each and the CI machine
# has 2 cores.

# build_dir <dir> "<targets, empty for all>" <cmake args...>
build_dir() {
  local dir=$1 targets=$2
  shift 2
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S . -B "$dir" -G Ninja "${launcher[@]}" "$@" >/dev/null
  # shellcheck disable=SC2086  # targets is a word list
  ninja -C "$dir" -j "${JOBS:-2}" $targets
}
