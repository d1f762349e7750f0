#!/usr/bin/env bash
# Installs the Debian (bookworm) packages groundsim needs, if any are missing.
# Idempotent; needs root or sudo only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config   # C++20 toolchain and build
  libeigen3-dev                                  # physics core: vectors, rotations, small solves
  liblcm-dev liblcm-bin                          # LCM transport and lcm-gen for the message types
  liblcm-java default-jdk-headless               # lcm.jar + javac: our types for lcm-spy
  nlohmann-json3-dev                             # scenario files
  libmuparser-dev                                # ground given as an expression H(x,y,z)
  libpng-dev                                     # heightfields and friction maps as grayscale PNG
  libcli11-dev                                   # command lines
  googletest libgtest-dev libgmock-dev           # tests
  libbenchmark-dev                               # benchmarks
  gnuplot-nox                                    # speed plots, accuracy plots
  iproute2 util-linux                            # ip + unshare: tests in private network namespaces
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
