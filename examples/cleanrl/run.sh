#!/usr/bin/env bash
# CleanRL's single-file PPO for continuous actions on a groundsim task:
# CleanRL's own ppo_continuous_action.py, patched only where it makes the
# environment (and where gymnasium 1.x's vector info format differs from
# the 0.29 it was written for): ppo_continuous_action.patch, beside this.
#   examples/cleanrl/run.sh PPO_FILE [CleanRL's flags ...]
# PPO_FILE: cleanrl/ppo_continuous_action.py of CleanRL's repository
# (github.com/vwxyzjn/cleanrl, tried at fe8d8a03c41a, 2026-04-20); it is not
# in this repository. Runs with the venv of python/requirements.txt
# (scripts/setup-python.sh: gymnasium, torch, tyro, tensorboard) and the
# package of build/ (ninja -C build groundsim_python). Example:
#   examples/cleanrl/run.sh ~/cleanrl/cleanrl/ppo_continuous_action.py \
#     --env-id groundsim/Goal-v0 --total-timesteps 300000 --num-envs 8 --seed 1
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
file=${1:?usage: examples/cleanrl/run.sh PPO_FILE [flags...]}
shift
venv=${GROUNDSIM_VENV:-$HOME/.cache/groundsim/venv}
work=${CLEANRL_WORK:-$(mktemp -d)}
cp "$file" "$work/ppo_continuous_action.py"
patch -s -d "$work" -p2 < "$here/ppo_continuous_action.patch"
cd "$work"
echo "cleanrl: running in $work (runs/ holds the tensorboard logs)" >&2
PYTHONPATH=$root/build/python exec "$venv/bin/python" ppo_continuous_action.py "$@"
