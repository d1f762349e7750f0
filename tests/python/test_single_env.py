"""groundsim.make(task): Gymnasium's single-env API over a vector env of
one (reset/step/render/close, spaces, np_random), the shipped tasks by id,
and their registration with Gymnasium (entry points resolved and called
the way gymnasium.make and make_vec call them)."""

import importlib
import math
import sys
import types

import numpy as np
import pytest

import groundsim
from conftest import GOAL, TASKS


def test_a_shipped_task_by_id_is_the_same_env_as_its_file():
    single = groundsim.make("groundsim/Goal-v0")
    vec = groundsim.make_vec(GOAL, 1, 1)
    obs, info = single.reset(seed=5)
    vobs, _ = vec.reset(seed=5)
    assert obs.shape == single.observation_space.shape and obs.dtype == np.float32
    assert obs.tobytes() == vobs[0].tobytes()
    rng = np.random.default_rng(0)
    for _ in range(20):
        a = rng.uniform(single.action_space.low, single.action_space.high).astype(np.float32)
        obs, rew, term, trunc, info = single.step(a)
        vobs, vrew, *_ = vec.step(a[None, :])
        assert obs.tobytes() == vobs[0].tobytes() and rew == vrew[0]
    assert type(rew) is float and type(term) is bool and type(trunc) is bool
    assert info == {"episode_index": 1, "episode_steps": 20, "episode_return": info["episode_return"],
                    "diverged": False}
    assert isinstance(info["episode_return"], float)


def test_short_names_and_ids():
    assert set(groundsim.task_ids()) == {"groundsim/Goal-v0", "groundsim/Speed-v0", "groundsim/FastCar-v0",
                                         "groundsim/Race-v0", "groundsim/GridRace-v0"}
    for name in ("goal", "speed", "fast_car", "groundsim/Speed-v0"):
        env = groundsim.make(name)
        obs, _ = env.reset(seed=0)
        assert obs.shape == env.observation_space.shape and np.isfinite(obs).all()
        env.close()
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make("groundsim/Nope-v0")
    assert e.value.field == "task" and "groundsim/Goal-v0" in str(e.value)


def test_np_random_is_seeded_by_reset():
    a, b = groundsim.make("goal"), groundsim.make("goal")
    a.reset(seed=3)
    b.reset(seed=3)
    assert a.np_random.integers(1 << 30) == b.np_random.integers(1 << 30)


def test_an_ended_episode_needs_a_reset():
    dt = 0.004 * 10
    env = groundsim.make({**_goal_doc(), "task": {**_goal_doc()["task"], "time_limit": 2 * dt}}, files_dir=TASKS)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step(np.zeros(env.action_space.shape, np.float32))
    assert e.value.field == "step"
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, np.float32)
    assert env.step(zero)[3] is False
    _, _, term, trunc, info = env.step(zero)
    assert trunc and not term and info["episode_steps"] == 2
    with pytest.raises(groundsim.ExperimentError, match="reset"):
        env.step(zero)
    env.reset()
    env.step(zero)


def test_bad_actions_and_rendering_are_refused_naming_the_field():
    env = groundsim.make("goal")
    env.reset(seed=0)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step(np.zeros(2, np.float32))
    assert e.value.field == "action" and "shape" in str(e.value)
    bad = np.zeros(env.action_space.shape, np.float32)
    bad[1] = np.nan
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step(bad)
    assert e.value.field == "action[1]"
    with pytest.raises(groundsim.ExperimentError) as e:
        env.render()
    assert e.value.field == "render_mode"
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make("goal", render_mode="human")
    assert e.value.field == "render_mode"
    with pytest.raises(groundsim.ExperimentError) as e:
        env.reset(options={"reset_mask": [True]})
    assert e.value.field == "options"
    # the env still works
    env.step(np.zeros(env.action_space.shape, np.float32))


def test_episode_statistics_on_request():
    doc = _goal_doc()
    doc["task"]["time_limit"] = 0.04
    env = groundsim.make(doc, files_dir=TASKS, episode_statistics=True)
    env.reset(seed=0)
    _, rew, _, trunc, info = env.step(np.zeros(env.action_space.shape, np.float32))
    assert trunc and info["episode"]["l"] == 1 and info["episode"]["r"] == rew


def _goal_doc():
    import json
    return json.loads(GOAL.read_text())


def _load(entry_point):
    """gymnasium.envs.registration.load_env_creator: "module:attr"."""
    module, attr = entry_point.split(":")
    return getattr(importlib.import_module(module), attr)


def test_register_envs_registers_entry_points_gymnasium_can_call(monkeypatch):
    calls = {}
    fake = types.ModuleType("gymnasium")
    fake.registry = {}

    def register(id, entry_point=None, vector_entry_point=None, kwargs=None, **rest):
        calls[id] = (entry_point, vector_entry_point, kwargs, rest)
        fake.registry[id] = object()

    fake.register = register
    monkeypatch.setitem(sys.modules, "gymnasium", fake)
    monkeypatch.setattr(groundsim.registration, "HAVE_GYMNASIUM", True)
    single = [i for i in groundsim.task_ids() if "Race" not in i]  # several agents: make_parallel
    assert groundsim.register_envs() == single
    assert set(calls) == set(single)
    groundsim.register_envs()  # twice: nothing registered again
    assert len(calls) == 3
    entry, vector_entry, kwargs, _ = calls["groundsim/Goal-v0"]
    # gymnasium.make: entry_point(**kwargs); make_vec(vector_entry_point): creator(num_envs=n, **kwargs)
    env = _load(entry)(**kwargs)
    vec = _load(vector_entry)(num_envs=3, **kwargs)
    assert isinstance(env, groundsim.Env) and vec.num_envs == 3
    assert vec.metadata["autoreset_mode"] is groundsim.AutoresetMode.NEXT_STEP
    vec_same = _load(vector_entry)(num_envs=2, autoreset_mode="same_step", **kwargs)
    assert vec_same.metadata["autoreset_mode"] is groundsim.AutoresetMode.SAME_STEP
    with pytest.raises(groundsim.ExperimentError) as e:
        _load(vector_entry)(num_envs=2, max_episode_steps=100, **kwargs)
    assert e.value.field == "max_episode_steps"
    assert math.isclose(env.metadata["render_fps"], 25.0)
