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

. "$(dirname "$0")/lib/install_missing.sh"
install_missing setup-web "${packages[@]}"
