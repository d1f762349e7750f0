# Sourced by build.sh, test.sh and fuzz.sh: configures and builds one build
# directory, through ccache when it is installed (scripts/setup.sh installs
# it). JOBS (default 2): the Eigen-heavy units need ~1 GB each and the CI
# machine has 2 cores.
#
# ccache: one cache for every checkout of the same user, so CI's fresh clone
# (another directory, right after the session that built the same commit)
# compiles from the cache instead of from scratch:
#   CCACHE_DIR      default $HOME/.cache/ccache (ccache's own default when
#                   XDG_CACHE_HOME is unset; fixed here so that a CI
#                   environment with another XDG_CACHE_HOME shares it);
#                   set CCACHE_DIR to use another
#   CCACHE_BASEDIR  this checkout's root: ccache rewrites the absolute paths
#                   CMake passes (sources, -I) to paths relative to the build
#                   directory, the same in every clone
#   CCACHE_NOHASHDIR=1  the sanitizer builds compile with -g1, and ccache
#                   would hash the working directory into every debug build's
#                   key (the debug info then names the directory of the
#                   checkout that filled the cache: reports still give
#                   file:line)
#   CCACHE_MAXSIZE  default 5G (the Release, ASan and TSan builds of one
#                   commit take about 1 GB; five commits' worth)
#   the compiler check is ccache's default (mtime of the compiler binary:
#   the compilers are Debian's, replaced only by an upgrade)
# Objects whose command line holds a checkout's absolute path (the tests'
# -DGROUNDSIM_SOURCE_DIR=... and -DGROUNDSIM_CONFIG_DIR=...) still miss in
# another checkout: basedir rewrites paths, not macro values.
groundsim_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd -P)
if command -v ccache >/dev/null; then
  export CCACHE_DIR="${CCACHE_DIR:-${HOME:-$(getent passwd "$(id -u)" | cut -d: -f6)}/.cache/ccache}"
  export CCACHE_BASEDIR="$groundsim_root"
  export CCACHE_NOHASHDIR=1
  export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-5G}"
fi

# ccache_counts: "<hits> <misses>" so far in CCACHE_DIR (every build using it counts)
ccache_counts() {
  ccache --print-stats 2>/dev/null | awk -F'\t' '
    $1 == "direct_cache_hit" || $1 == "preprocessed_cache_hit" { h += $2 }
    $1 == "cache_miss" { m += $2 }
    END { print h + 0, m + 0 }'
}

# build_dir <dir> "<targets, empty for all>" <cmake args...>
build_dir() {
  local dir=$1 targets=$2
  shift 2
  # an empty launcher clears one a directory was configured with before ccache went away
  local launcher=-DCMAKE_CXX_COMPILER_LAUNCHER=
  local before=""
  if command -v ccache >/dev/null; then
    launcher=-DCMAKE_CXX_COMPILER_LAUNCHER=ccache
    before=$(ccache_counts)
  fi
  cmake -S . -B "$dir" -G Ninja "$launcher" "$@" >/dev/null
  # shellcheck disable=SC2086  # targets is a word list
  ninja -C "$dir" -j "${JOBS:-2}" $targets
  if [ -n "$before" ]; then
    local after h0 m0 h1 m1
    after=$(ccache_counts)
    read -r h0 m0 <<<"$before"
    read -r h1 m1 <<<"$after"
    echo "build_dir: $dir: ccache $((h1 - h0)) hits, $((m1 - m0)) misses (counts every build sharing $CCACHE_DIR meanwhile)"
  fi
}
