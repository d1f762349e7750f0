#!/usr/bin/env bash
# Installs the Debian (bookworm) packages of the browser front end, if
# missing: Boost.Beast for groundsim-web, Node.js and npm to bundle the page
# (three.js, esbuild from the npm registry, pinned by web/package-lock.json),
# and Chromium for the browser tests (playwright-core drives it).
# scripts/setup.sh can call it; idempotent.
set -euo pipefail

packages=(
  libboost-dev                                   # Boost.Beast + Asio (header-only): HTTP and WebSocket
  chromium                                       # browser tests: WebGL 2 headless through SwiftShader
)
# Node may come from elsewhere (nodesource bundles npm): only when absent
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup-web: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup-web: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
