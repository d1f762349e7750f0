#!/usr/bin/env bash
# Installs the Debian (bookworm) packages groundsim needs, if any are missing.
# Idempotent; needs root or sudo only when something is missing.
#   scripts/setup.sh               everything: build, tests, sanitizers, fuzzing, benchmarks, tools
#   scripts/setup.sh --build-only  only what `groundsim-server` and `groundsim` need to build
#                                  (-DGROUNDSIM_BUILD_TESTS=OFF -DGROUNDSIM_BUILD_BENCH=OFF; docker/Dockerfile)
set -euo pipefail

build=(
  build-essential cmake ninja-build pkg-config   # C++20 toolchain and build
  ccache                                         # compiler cache (scripts/lib/build_dir.sh): a fresh clone (CI's)
                                                 # reuses what a build of the same sources compiled before
  libeigen3-dev                                  # physics core: vectors, rotations, small solves
  liblcm-dev liblcm-bin                          # LCM transport and lcm-gen for the message types
  nlohmann-json3-dev                             # scenario files
  libmuparser-dev                                # ground given as an expression H(x,y,z)
  libpng-dev                                     # heightfields and friction maps as grayscale PNG
  zlib1g-dev                                     # gzip of groundsim-web's large HTTP answers
  libssl-dev                                     # SHA-256 (OpenSSL libcrypto): files sent with a scenario are content-addressed
  libcli11-dev                                   # command lines
  libboost-dev                                   # Boost.Beast + Asio (header-only): groundsim-web's HTTP and WebSocket
  libzstd-dev                                    # MCAP recordings: zstd-compressed chunks (server/recording)
)
rest=(
  liblcm-java default-jdk-headless               # lcm.jar + javac: our types for lcm-spy
  googletest libgtest-dev libgmock-dev           # tests
  libbenchmark-dev                               # benchmarks
  libmujoco-dev libbullet-dev                    # the peers of ../shared/peers/compare.sh (docs/performance.md)
  gnuplot-nox                                    # speed plots, accuracy plots
  iproute2 util-linux                            # ip + unshare: tests in private network namespaces
  prometheus                                     # promtool: scrapes checked by integration.MetricsServerAndBridge
  nftables                                       # frame loss between namespaced "hosts" (record.LossyLinkEndsComplete)
  etcd-server etcd-client                        # a fleet's membership and ownership (server/fleet; fleet tests, scripts/fleet_lab.sh)
  curl                                           # fleet tests ask a namespaced server's /health
  clang-14 libclang-rt-14-dev llvm-14            # libFuzzer targets (scripts/fuzz.sh), llvm-symbolizer
  python3-dev pybind11-dev python3-pybind11      # the Python package groundsim (its C++ module groundsim._core)
  python3-numpy python3-pytest python3-venv      # its arrays, its tests (pytest through ctest), the venv install test
  python3-matplotlib                             # examples/train_goal.py's learning curve, examples/ppo_plot.py
  python3-torch                                  # examples/ppo.py (PPO) and its smoke test
  ffmpeg                                         # groundsim.record_video: frames to H.264 MP4
  emscripten                                     # the page's predictor: the physics core in WebAssembly (web/wasm)
)

case "${1:-}" in
  "") packages=("${build[@]}" "${rest[@]}")
      # the page's bundle (Node.js, npm) and its browser tests (Chromium)
      "$(dirname "$0")/setup-web.sh" ;;
  --build-only) packages=("${build[@]}") ;;
  *) echo "usage: scripts/setup.sh [--build-only]" >&2; exit 2 ;;
esac

. "$(dirname "$0")/lib/install_missing.sh"
install_missing setup "${packages[@]}"
# the real Python libraries the tests run against, from PyPI (python/requirements.txt)
[ -z "${1:-}" ] && "$(dirname "$0")/setup-python.sh"
exit 0
