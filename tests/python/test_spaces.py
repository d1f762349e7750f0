"""Shapes, dtypes and spaces of the vector env, its layout, and the two
ways the package is built: on Gymnasium's classes or on its own."""

import os
import subprocess
import sys

import numpy as np
import pytest

import groundsim
from conftest import GOAL, make_goal


def test_spaces_and_buffers_have_the_layouts_shapes(goal_doc):
    env = make_goal(goal_doc, 5)
    layout = env.layout
    n, o, a = 5, layout.obs_size, layout.action_size
    assert env.num_envs == layout.num_envs == n
    assert o == len(layout.observation) > 0 and a == len(layout.action) > 0
    assert env.single_observation_space.shape == (o,) and env.observation_space.shape == (n, o)
    assert env.single_action_space.shape == (a,) and env.action_space.shape == (n, a)
    for space in (env.single_observation_space, env.observation_space, env.single_action_space, env.action_space):
        assert space.dtype == np.float32
    np.testing.assert_array_equal(env.single_action_space.low, np.asarray(layout.action_low, np.float32))
    np.testing.assert_array_equal(env.single_action_space.high, np.asarray(layout.action_high, np.float32))
    np.testing.assert_array_equal(env.observation_space.low[3], env.single_observation_space.low)
    assert env.metadata["autoreset_mode"] == groundsim.AutoresetMode.NEXT_STEP

    obs, infos = env.reset(seed=0)
    assert obs.shape == (n, o) and obs.dtype == np.float32
    obs, rew, term, trunc, infos = env.step(env.action_space.sample())
    assert obs.shape == (n, o) and obs.dtype == np.float32
    assert rew.shape == (n,) and rew.dtype == np.float64
    assert term.shape == trunc.shape == (n,) and term.dtype == trunc.dtype == np.bool_
    assert infos["episode_index"].dtype == infos["episode_steps"].dtype == np.int64
    assert infos["episode_return"].dtype == np.float64 and infos["diverged"].dtype == np.bool_
    for key in ("episode_index", "episode_steps", "episode_return", "diverged"):
        assert infos[key].shape == (n,) and infos["_" + key].all()
    env.close()


def test_layout_names_the_goal_tasks_components(goal_doc):
    env = make_goal(goal_doc, 1)
    layout = env.layout
    assert layout.dt == goal_doc["physics"]["dt"]
    assert layout.control_period == goal_doc["task"]["control_period"]
    assert layout.time_limit == goal_doc["task"]["time_limit"]
    assert layout.wheel_counts == [4]  # one sedan
    assert layout.action[:3] == ["throttle", "brake", "steer"]
    assert len(set(layout.observation)) == len(layout.observation)
    assert any(name.startswith("goal_body") for name in layout.observation)
    env.close()


def test_a_file_a_json_string_and_a_dict_give_the_same_env(goal_doc):
    by_file = groundsim.make_vec(GOAL, 2, 1)
    by_str = groundsim.make_vec(str(GOAL), 2, 1)
    by_dict = make_goal(goal_doc, 2)
    obs = [e.reset(seed=11)[0].copy() for e in (by_file, by_str, by_dict)]
    assert obs[0].tobytes() == obs[1].tobytes() == obs[2].tobytes()
    assert by_file.layout.scenario_hash == by_dict.layout.scenario_hash


def test_a_json_string_naming_a_file_needs_files_dir(goal_doc):
    import json
    with pytest.raises(groundsim.ScenarioError):
        groundsim.make_vec(json.dumps(goal_doc), 1, 1)


def test_fallback_box_samples_inside_its_bounds():
    from groundsim.spaces import Box, batch_space
    box = Box(np.array([-1, 0, -np.inf], np.float32), np.array([1, 2, np.inf], np.float32), seed=0)
    batch = batch_space(box, 4)
    assert batch.shape == (4, 3) and batch.dtype == np.float32
    for _ in range(100):
        x = batch.sample()
        assert batch.contains(x) and x.dtype == np.float32
    assert not box.contains(np.array([2, 0, 0], np.float32))


CHECK = """
import numpy as np, groundsim
env = groundsim.make_vec({goal!r}, 2, 1)
obs, infos = env.reset(seed=1)
obs, *_ = env.step(env.action_space.sample())
print(groundsim.HAVE_GYMNASIUM, type(env.single_action_space).__module__, env.metadata["autoreset_mode"].value)
"""


def run_check(prelude):
    env = dict(os.environ)
    out = subprocess.run([sys.executable, "-c", prelude + CHECK.format(goal=str(GOAL))], env=env,
                         capture_output=True, text=True, check=True)
    return out.stdout.split()


def test_without_gymnasium_the_package_uses_its_own_classes():
    # sys.modules[name] = None makes `import gymnasium` raise ImportError
    have, module, mode = run_check("import sys; sys.modules['gymnasium'] = None\n")
    assert have == "False" and module == "groundsim.spaces" and mode == "NextStep"


def test_with_gymnasium_the_env_is_a_gymnasium_vector_env():
    gymnasium = pytest.importorskip("gymnasium")
    from gymnasium.vector import AutoresetMode, VectorEnv
    env = groundsim.make_vec(GOAL, 2, 1)
    assert groundsim.HAVE_GYMNASIUM
    assert isinstance(env, VectorEnv)
    assert isinstance(env.single_observation_space, gymnasium.spaces.Box)
    assert isinstance(env.action_space, gymnasium.spaces.Box)
    assert env.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP
    have, module, mode = run_check("")
    assert have == "True" and module.startswith("gymnasium.spaces") and mode == "NextStep"
