#!/usr/bin/env bash
# The venv of the real Python libraries the tests run against (Gymnasium,
# Stable-Baselines3, PettingZoo, mcap, CleanRL's tyro and tensorboard), every
# version pinned in python/requirements.txt, installed from PyPI. The venv is
# Debian's /usr/bin/python3's (the interpreter groundsim._core is built for)
# and sees Debian's packages. One venv per user, shared by every checkout (a
# fresh clone, CI's, finds it ready):
#   GROUNDSIM_VENV   default $HOME/.cache/groundsim/venv (CMake's default too)
# Idempotent: nothing is done when the venv already holds this requirements
# file's pins (a stamp with its SHA-256). scripts/setup.sh calls it.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
venv=${GROUNDSIM_VENV:-${HOME:-$(getent passwd "$(id -u)" | cut -d: -f6)}/.cache/groundsim/venv}
requirements=$here/python/requirements.txt
want=$(sha256sum "$requirements" | cut -d' ' -f1)
stamp=$venv/.groundsim-requirements
if [[ -x $venv/bin/python && -f $stamp && $(cat "$stamp") == "$want" ]]; then
  exit 0
fi
echo "setup-python: installing python/requirements.txt into $venv (PyPI; about 5 GB with PyTorch's CUDA libraries)" >&2
[[ -x $venv/bin/python ]] || /usr/bin/python3 -m venv --system-site-packages "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$requirements"
echo "$want" > "$stamp"
