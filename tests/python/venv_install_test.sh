#!/usr/bin/env bash
# scripts/python-install.sh into a new venv, then the package imported and
# stepped from outside the source tree, from the venv and not from build/.
#   venv_install_test.sh PYTHON VENV BUILD_PYTHON_DIR SOURCE_DIR
set -euo pipefail
python=$1 venv=$2 build_python=$3 source_dir=$4
rm -rf "$venv"
PYTHON=$python "$source_dir/scripts/python-install.sh" "$venv" "$build_python"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
unset PYTHONPATH
"$venv/bin/python" - "$venv" "$source_dir/configs/tasks/goal.json" <<'PY'
import os, sys
import numpy as np
import groundsim
venv, goal = sys.argv[1:]
where = os.path.realpath(groundsim.__file__)
assert where.startswith(os.path.realpath(venv) + os.sep), where
env = groundsim.make_vec(goal, 2, 1)
obs, _ = env.reset(seed=0)
obs, rew, term, trunc, _ = env.step(np.zeros(env.action_space.shape))
assert obs.shape == (2, env.layout.obs_size) and np.isfinite(obs).all()
print("imported from", where)
PY
# pip sees it (when the venv's Python has pip through the system packages)
if "$venv/bin/python" -m pip --version >/dev/null 2>&1; then
  "$venv/bin/python" -m pip show groundsim > "$work/pip-show"
  grep -q '^Name: groundsim' "$work/pip-show"
fi
