"""No copies: the C++ environments write into numpy arrays allocated once by
the wrapper; every call returns read-only views of those same arrays."""

import numpy as np

from conftest import actions, make_goal


def test_every_step_returns_views_of_the_same_buffers(goal_doc):
    env = make_goal(goal_doc, 4)
    obs0, infos0 = env.reset(seed=0)
    seq = actions(env, 3)
    first = env.step(seq[0])
    second = env.step(seq[1])
    for a, b in zip(first[:4], second[:4]):
        assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
        assert not a.flags.writeable and not a.flags.owndata
    assert obs0.__array_interface__["data"][0] == first[0].__array_interface__["data"][0]
    for key in ("episode", "episode_steps", "episode_return", "diverged"):
        assert np.shares_memory(first[4][key], second[4][key]) and not first[4][key].flags.writeable
    # the contents are the new ones: a kept reference sees the next step
    kept = first[0]
    third = env.step(seq[2])[0].copy()
    np.testing.assert_array_equal(kept, third)


def test_the_core_writes_into_the_callers_arrays(goal_doc):
    env = make_goal(goal_doc, 2)
    core, layout = env._core, env.layout
    obs = np.full((2, layout.obs_size), np.nan, np.float32)
    address = obs.__array_interface__["data"][0]
    core.reset(9, obs)
    assert np.isfinite(obs).all() and obs.__array_interface__["data"][0] == address
    rewards = np.full(2, np.nan)
    term, trunc = np.ones(2, bool), np.ones(2, bool)
    core.step(np.zeros((2, layout.action_size), np.float32), obs, rewards, term, trunc)
    assert np.isfinite(rewards).all() and not term.any() and not trunc.any()
    episode, steps = np.full(2, -1, np.int64), np.full(2, -1, np.int64)
    ret, div = np.full(2, np.nan), np.ones(2, bool)
    core.fill_infos(episode, steps, ret, div)
    assert episode.tolist() == [1, 1] and steps.tolist() == [1, 1]
    np.testing.assert_array_equal(ret, rewards)
    assert not div.any()


def test_infos_dicts_are_fresh_but_their_arrays_are_shared(goal_doc):
    env = make_goal(goal_doc, 2)
    _, infos = env.reset(seed=0)
    infos["episode"] = "changed by a wrapper"
    _, _, _, _, infos2 = env.step(actions(env, 1)[0])
    assert infos2["episode"].tolist() == [1, 1]
