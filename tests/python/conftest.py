"""Shared fixtures: the goal task (configs/tasks/goal.json), as a file or as
a dict to vary, and a seeded stream of actions."""

import copy
import json
import os
import pathlib

import numpy as np
import pytest

import groundsim

SOURCE_DIR = pathlib.Path(os.environ.get("GROUNDSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
TASKS = SOURCE_DIR / "configs" / "tasks"
GOAL = TASKS / "goal.json"


@pytest.fixture(scope="session")
def goal_doc():
    return json.loads(GOAL.read_text())


ENV_OPTIONS = ("copy", "autoreset_mode", "episode_statistics")


def make_goal(doc, num_envs, num_threads=1, **task):
    """The goal task with some task fields replaced (heightfields are read
    next to configs/tasks/goal.json); copy, autoreset_mode and
    episode_statistics go to make_vec."""
    options = {key: task.pop(key) for key in ENV_OPTIONS if key in task}
    doc = copy.deepcopy(doc)
    doc["task"].update(task)
    return groundsim.make_vec(doc, num_envs, num_threads, files_dir=TASKS, **options)


def actions(env, steps, seed=7):
    """A reproducible stream of actions inside the action space."""
    rng = np.random.default_rng(seed)
    low, high = env.single_action_space.low, env.single_action_space.high
    return [rng.uniform(low, high, size=(env.num_envs, low.size)).astype(np.float32) for _ in range(steps)]


def run(env, seq, seed=3):
    """Resets with seed, takes the actions; copies of everything returned."""
    obs, _ = env.reset(seed=seed)
    out = [obs.copy()]
    for a in seq:
        obs, rew, term, trunc, info = env.step(a)
        out += [obs.copy(), rew.copy(), term.copy(), trunc.copy(), info["episode_steps"].copy()]
    return out


def assert_identical(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        # bit for bit: compare the bytes, so that NaN or -0.0 cannot hide a difference
        assert x.dtype == y.dtype and x.shape == y.shape
        assert x.tobytes() == y.tobytes()
