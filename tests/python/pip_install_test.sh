#!/usr/bin/env bash
# `pip install` as a researcher does it: a wheel built from the checkout by
# pyproject.toml's backend (scikit-build-core, pybind11 from PyPI), installed
# into a fresh venv with nothing else in it (numpy from PyPI), then imported
# and stepped from outside the source tree; pip lists it and uninstalls it.
#   pip_install_test.sh PYTHON SOURCE_DIR WORK_DIR
# Exit 77 (SKIP) when PyPI cannot be reached: the backend comes from there.
set -euo pipefail
python=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
if ! "$python" -m pip download --no-deps -q -d "$work/probe" scikit-build-core==1.1.2 >/dev/null 2>&1; then
  echo "SKIP: PyPI unreachable (pip download scikit-build-core failed): the build backend comes from there"
  exit 77
fi
# ccache as scripts/build.sh uses it, so the wheel's objects come from build/'s
. "$src/scripts/lib/build_dir.sh"
command -v ccache >/dev/null && export CMAKE_CXX_COMPILER_LAUNCHER=ccache
"$python" -m venv "$work/venv"
py=$work/venv/bin/python
cd "$src"
start=$(date +%s)
"$py" -m pip wheel --no-deps -q -w "$work/wheelhouse" .
echo "wheel built in $(( $(date +%s) - start )) s: $(cd "$work/wheelhouse" && ls)"
wheel=$(ls "$work"/wheelhouse/groundsim-*.whl)
"$py" -m pip install -q "$wheel"
# the wheel holds the module, the package and its tasks
listing=$("$py" -m zipfile -l "$wheel")
grep -q 'groundsim/_core\.' <<<"$listing"
grep -q 'groundsim/data/tasks/goal.json' <<<"$listing"
cd "$work"
unset PYTHONPATH
"$py" - "$work/venv" <<'PY'
import os, sys
import numpy as np
import groundsim
venv = sys.argv[1]
where = os.path.realpath(groundsim.__file__)
assert where.startswith(os.path.realpath(venv) + os.sep), where
# a shipped task by id, from the package's own data
env = groundsim.make_vec("groundsim/Goal-v0", 2, 1)
obs, _ = env.reset(seed=0)
obs, rew, term, trunc, _ = env.step(np.zeros(env.action_space.shape, np.float32))
assert obs.shape == (2, env.layout.obs_size) and np.isfinite(obs).all()
print("groundsim", groundsim.__version__, "imported from", where, "with numpy", np.__version__)
PY
shown=$("$py" -m pip show groundsim)
grep -q '^Name: groundsim' <<<"$shown"
"$py" -m pip uninstall -y -q groundsim
! "$py" -c 'import groundsim' 2>/dev/null
echo "pip install, import, step and uninstall: OK"
