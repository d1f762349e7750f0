"""Stable-Baselines3's VecEnv contract (docs/guide/vec_envs.md), written as
tests since SB3 is not installable here: reset() returns observations only,
infos are a list of dicts, an ended episode's last observation is
infos[i]["terminal_observation"] and the returned one is the next
episode's first, TimeLimit.truncated tells a time limit from a
termination, seed(s) seeds env i with s + i at the next reset."""

import numpy as np
import pytest

import groundsim
from groundsim.sb3 import SB3VecEnv
from conftest import actions, make_goal


def short(goal_doc, n=2, steps=3, **task):
    dt, period = goal_doc["physics"]["dt"], goal_doc["task"]["control_period"]
    return make_goal(goal_doc, n, time_limit=steps * period * dt, **task)


def test_reset_returns_observations_and_keeps_infos_aside(goal_doc):
    venv = SB3VecEnv(short(goal_doc, autoreset_mode="same_step"))
    assert venv.seed(5) == [5, 6]
    obs = venv.reset()
    ref, _ = short(goal_doc).reset(seed=5)
    assert isinstance(obs, np.ndarray) and obs.tobytes() == ref.tobytes()
    assert isinstance(venv.reset_infos, list) and len(venv.reset_infos) == 2
    assert venv.reset_infos[0]["episode_index"] == 1
    assert venv.observation_space.shape == obs.shape[1:] and venv.num_envs == 2


def test_a_time_limit_end_gives_the_terminal_observation(goal_doc):
    venv = SB3VecEnv(short(goal_doc, autoreset_mode="same_step"))
    ref = short(goal_doc)
    seq = actions(ref, 4)
    venv.seed(9)
    venv.reset()
    ref.reset(seed=9)
    for k in range(3):
        obs, rewards, dones, infos = venv.step(seq[k])
        robs, rrew, *_ = ref.step(seq[k])
        assert rewards.dtype == np.float32 and dones.dtype == np.bool_
        assert isinstance(infos, list) and all(isinstance(i, dict) for i in infos)
    assert dones.all()
    for i in range(2):
        assert infos[i]["terminal_observation"].tobytes() == robs[i].tobytes()
        assert infos[i]["TimeLimit.truncated"] is True
        assert infos[i]["episode"]["l"] == 3
        assert infos[i]["episode_steps"] == 3  # the ended episode's counters
    np.testing.assert_allclose(rewards, rrew.astype(np.float32))
    # the returned observation is the next episode's first (NEXT_STEP's reset step)
    assert obs.tobytes() == ref.step(seq[3])[0].tobytes()


def test_a_termination_is_not_a_time_limit(goal_doc):
    # the goal within its radius of every drawn start: the first step terminates
    venv = SB3VecEnv(make_goal(goal_doc, 2, autoreset_mode="same_step", goal=[0.0, 0.0]))
    venv.seed(0)
    venv.reset()
    _, _, dones, infos = venv.step(np.zeros((2, venv.action_space.shape[0]), np.float32))
    assert dones.all()
    assert all(i["TimeLimit.truncated"] is False for i in infos)
    assert all("terminal_observation" in i for i in infos)


def test_only_a_same_step_env_fits_the_contract(goal_doc):
    with pytest.raises(groundsim.ExperimentError) as e:
        SB3VecEnv(make_goal(goal_doc, 1))
    assert e.value.field == "autoreset_mode"


def test_helpers_of_the_contract(goal_doc):
    venv = groundsim.sb3.make_sb3_vec("groundsim/Goal-v0", 3, 1)
    assert venv.env_is_wrapped(object) == [False] * 3
    assert venv.get_attr("num_envs") == [3] * 3
    with pytest.raises(groundsim.ExperimentError):
        venv.step_wait()
    with pytest.raises(groundsim.ExperimentError):
        venv.get_images()
    venv.close()
