"""Buffers: by default (copy=True, as Gymnasium's vector envs) every call
returns fresh, writable arrays; with copy=False the C++ environments write
into numpy arrays allocated once by the wrapper and every call returns
read-only views of those same arrays."""

import numpy as np

from conftest import actions, make_goal


def test_by_default_every_call_returns_fresh_arrays(goal_doc):
    env = make_goal(goal_doc, 4)
    obs0, infos0 = env.reset(seed=0)
    seq = actions(env, 2)
    first = env.step(seq[0])
    kept = [a.copy() for a in first[:4]]
    second = env.step(seq[1])
    for a, b, k in zip(first[:4], second[:4], kept):
        assert not np.shares_memory(a, b) and a.flags.writeable
        # a kept array is not overwritten by the next step (the replay-buffer bug)
        np.testing.assert_array_equal(a, k)
    assert obs0 is not first[0] and not np.shares_memory(obs0, first[0])
    assert not np.array_equal(first[0], second[0])
    for key in ("episode_index", "episode_steps", "episode_return", "diverged"):
        assert not np.shares_memory(first[4][key], second[4][key]) and first[4][key].flags.writeable
    # writing into a returned array changes nothing the env holds
    first[0][:] = np.nan
    assert np.isfinite(env.step(seq[0])[0]).all()


def test_copy_false_returns_views_of_the_same_buffers(goal_doc):
    env = make_goal(goal_doc, 4, copy=False)
    obs0, infos0 = env.reset(seed=0)
    seq = actions(env, 3)
    first = env.step(seq[0])
    second = env.step(seq[1])
    for a, b in zip(first[:4], second[:4]):
        assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
        assert not a.flags.writeable and not a.flags.owndata
    assert obs0.__array_interface__["data"][0] == first[0].__array_interface__["data"][0]
    for key in ("episode_index", "episode_steps", "episode_return", "diverged"):
        assert np.shares_memory(first[4][key], second[4][key]) and not first[4][key].flags.writeable
    # the contents are the new ones: a kept reference sees the next step
    kept = first[0]
    third = env.step(seq[2])[0].copy()
    np.testing.assert_array_equal(kept, third)


def test_copies_and_views_hold_the_same_values(goal_doc):
    seq = None
    out = {}
    for copy in (True, False):
        env = make_goal(goal_doc, 3, copy=copy)
        seq = seq or actions(env, 5)
        obs, _ = env.reset(seed=11)
        run = [obs.copy()]
        for a in seq:
            run += [x.copy() for x in env.step(a)[:4]]
        out[copy] = run
    for x, y in zip(out[True], out[False]):
        assert x.tobytes() == y.tobytes()


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


def test_infos_dicts_are_fresh_but_their_arrays_are_shared_without_copies(goal_doc):
    env = make_goal(goal_doc, 2, copy=False)
    _, infos = env.reset(seed=0)
    infos["episode_index"] = "changed by a wrapper"
    _, _, _, _, infos2 = env.step(actions(env, 1)[0])
    assert infos2["episode_index"].tolist() == [1, 1]


def test_fresh_arrays_are_the_ones_the_batch_wrote_and_stay_unchanged(goal_doc):
    """copy=True without copies: the arrays a call returns are those the C++
    batch wrote into; a partial reset or a restore carries the other rows
    over into new arrays and never writes one returned before."""
    env = make_goal(goal_doc, 4)
    env.reset(seed=3)
    seq = actions(env, 3)
    obs, rewards, term, trunc, infos = env.step(seq[0])
    assert obs is env._obs and rewards is env._rewards and infos["episode_steps"] is env._info_arrays["episode_steps"]
    kept = obs.copy()
    snap = env.snapshot(1)
    env.step(seq[1])
    before_reset = env.step(seq[2])[0]
    kept_before_reset = before_reset.copy()
    partial, _ = env.reset(seed=5, options={"env": [2]})
    np.testing.assert_array_equal(obs, kept)
    np.testing.assert_array_equal(before_reset, kept_before_reset)
    assert not np.shares_memory(partial, before_reset)
    np.testing.assert_array_equal(np.delete(partial, 2, axis=0), np.delete(before_reset, 2, axis=0))
    restored = env.restore(1, snap)
    np.testing.assert_array_equal(restored, kept[1])
    np.testing.assert_array_equal(np.delete(env._obs, 1, axis=0), np.delete(partial, 1, axis=0))
    np.testing.assert_array_equal(before_reset, kept_before_reset)
