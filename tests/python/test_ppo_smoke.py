"""examples/ppo.py for a tiny budget: it writes its results JSON with finite
numbers, and a rerun of the same seed reproduces the curve exactly."""

import importlib.util
import json
import math

import pytest

from conftest import SOURCE_DIR, TASKS

torch = pytest.importorskip("torch", reason="examples/ppo.py needs PyTorch (apt-get install python3-torch)")


def load_ppo():
    spec = importlib.util.spec_from_file_location("ppo_example", SOURCE_DIR / "examples" / "ppo.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def tiny_run(ppo, out_dir, task="goal.json", seed=3):
    return ppo.main(["--task", str(TASKS / task), "--seed", str(seed), "--total-timesteps", str(2 * 8 * 32),
                     "--num-envs", "8", "--num-steps", "32", "--num-minibatches", "4", "--update-epochs", "2",
                     "--eval-episodes", "4", "--eval-every", "1", "--out-dir", str(out_dir), "--quiet"])


# the curve's keys that must repeat bit for bit (the wall times may not)
EXACT = ("iteration", "env_steps", "episodes", "return", "success", "v_loss", "pg_loss", "approx_kl", "clipfrac",
         "std", "heldout_return", "heldout_success")


def test_ppo_writes_finite_results_and_a_rerun_repeats_the_curve(tmp_path):
    ppo = load_ppo()
    first = tiny_run(ppo, tmp_path / "a")
    written = json.loads((tmp_path / "a" / "ppo_goal_seed3.json").read_text())
    for key in ("seed", "heldout_success", "env_steps", "wall_s", "sps", "curve", "success_definition", "command"):
        assert key in written, key
    assert written["env_steps"] == 2 * 8 * 32 and len(written["curve"]) == 2
    assert 0.0 <= written["heldout_success"] <= 1.0 and len(written["heldout"]["per_start"]) == 4
    for row in written["curve"]:
        assert row["env_steps"] > 0 and "heldout_success" in row
        for key in ("v_loss", "pg_loss", "approx_kl", "std", "wall_s", "sps", "heldout_return"):
            assert math.isfinite(row[key]), (key, row)

    again = tiny_run(ppo, tmp_path / "b")
    assert [{k: r.get(k) for k in EXACT} for r in again["curve"]] == \
        [{k: r.get(k) for k in EXACT} for r in first["curve"]]
    other = tiny_run(ppo, tmp_path / "c", seed=4)
    assert [r["v_loss"] for r in other["curve"]] != [r["v_loss"] for r in first["curve"]]


def test_ppo_on_a_task_without_a_goal_counts_success_by_return(tmp_path):
    ppo = load_ppo()
    result = tiny_run(ppo, tmp_path, task="speed.json", seed=0)
    assert result["success_return"] == pytest.approx(0.6 * 500)
    assert 0.0 <= result["heldout_success"] <= 1.0
