"""Exact properties: the same seed and actions give the same bits, on any
number of threads; autoreset follows NEXT_STEP; a snapshot restored
continues bit for bit."""

import numpy as np
import pytest

from conftest import actions, assert_identical, make_goal, run


def test_reset_with_a_seed_is_reproducible_and_seeds_differ(goal_doc):
    env = make_goal(goal_doc, 4)
    first = env.reset(seed=5)[0].copy()
    env.step(actions(env, 1)[0])
    again = env.reset(seed=5)[0].copy()
    other = env.reset(seed=6)[0].copy()
    assert first.tobytes() == again.tobytes()
    # the start is drawn at random (task.randomize): envs and seeds differ
    assert not np.array_equal(first[0], first[1])
    assert not np.array_equal(first, other)
    # env i is seeded with seed + i
    np.testing.assert_array_equal(first[1:], env.reset(seed=6)[0][:3])


def test_a_partial_reset_gives_what_a_full_reset_gives_that_env(goal_doc):
    env = make_goal(goal_doc, 3)
    full = env.reset(seed=20)[0].copy()
    for a in actions(env, 3):
        env.step(a)
    moved = env.step(actions(env, 1, seed=1)[0])[0].copy()
    obs, infos = env.reset(seed=20, options={"env": 1})
    np.testing.assert_array_equal(obs[1], full[1])
    np.testing.assert_array_equal(obs[[0, 2]], moved[[0, 2]])  # the others keep their state
    assert infos["episode_steps"][1] == 0 and infos["episode_steps"][0] == 4
    mask = np.array([True, False, True])
    obs, _ = env.reset(seed=20, options={"reset_mask": mask})
    np.testing.assert_array_equal(obs, full)


@pytest.mark.parametrize("threads", [2, 3])
def test_results_do_not_depend_on_the_number_of_threads(goal_doc, threads):
    seq = actions(make_goal(goal_doc, 7), 12)
    one = run(make_goal(goal_doc, 7, 1), seq)
    many = run(make_goal(goal_doc, 7, threads), seq)
    assert_identical(one, many)


def short_episodes(goal_doc, n=2, steps=3):
    """The goal task cut to `steps` actions by its time limit."""
    dt, period = goal_doc["physics"]["dt"], goal_doc["task"]["control_period"]
    return make_goal(goal_doc, n, time_limit=steps * period * dt)


def test_autoreset_next_step(goal_doc):
    env = short_episodes(goal_doc, steps=3)
    env.reset(seed=1)
    seq = actions(env, 4)
    for k in range(3):
        obs, rew, term, trunc, info = env.step(seq[k])
        assert info["episode_index"].tolist() == [1, 1] and info["episode_steps"].tolist() == [k + 1] * 2
        assert not term.any()
        assert trunc.tolist() == [k == 2] * 2
    # the step after the episode ended resets: first observation of the next
    # episode, reward 0, both flags false, the action ignored
    twin = short_episodes(goal_doc, steps=3)
    twin.reset(seed=99)
    for i in range(2):
        twin.restore(i, env.snapshot(i))
    obs, rew, term, trunc, info = env.step(seq[3])
    obs = obs.copy()
    assert rew.tolist() == [0.0, 0.0] and not term.any() and not trunc.any()
    assert info["episode_index"].tolist() == [2, 2] and info["episode_steps"].tolist() == [0, 0]
    assert info["episode_return"].tolist() == [0.0, 0.0]
    other = twin.step(-seq[3])[0]
    np.testing.assert_array_equal(obs, other)


def test_snapshot_restore_continues_bit_for_bit(goal_doc):
    env = make_goal(goal_doc, 3)
    env.reset(seed=2)
    for a in actions(env, 5):
        env.step(a)
    snaps = [env.snapshot(i) for i in range(3)]
    assert all(isinstance(s, bytes) for s in snaps)
    seq = actions(env, 8, seed=8)

    def continue_(e):
        out = []
        for a in seq:
            obs, rew, term, trunc, info = e.step(a)
            out += [obs.copy(), rew.copy(), term.copy(), trunc.copy(), info["episode_return"].copy()]
        return out

    original = continue_(env)
    fresh = make_goal(goal_doc, 3, 2)
    fresh.reset(seed=1234)
    for i in range(3):
        row = fresh.restore(i, snaps[i])
        assert row.shape == (env.layout.obs_size,)
    assert_identical(original, continue_(fresh))
    # and back into the env they came from
    for i in range(3):
        env.restore(i, snaps[i])
    assert_identical(original, continue_(env))


def test_an_env_restored_into_another_slot_continues_like_the_original(goal_doc):
    env = make_goal(goal_doc, 2)
    env.reset(seed=4)
    env.restore(1, env.snapshot(0))
    obs = env.step(np.repeat(actions(env, 1)[0][:1], 2, axis=0))[0]
    np.testing.assert_array_equal(obs[0], obs[1])
