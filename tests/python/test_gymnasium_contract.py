"""Gymnasium 1.x's documented vector-env behaviour, written as tests since
gymnasium is not installable here (docs/experiments.md "Python"): the three
autoreset modes, episode statistics in RecordEpisodeStatistics' format,
and the project's own counters under names that collide with none of
Gymnasium's keys."""

import numpy as np
import pytest

import groundsim
from conftest import actions, make_goal

GYMNASIUM_KEYS = {"episode", "_episode", "final_obs", "_final_obs", "final_info", "_final_info"}
OWN_KEYS = ("episode_index", "episode_steps", "episode_return", "diverged")


def short(goal_doc, steps=3, n=2, **options):
    """The goal task cut to `steps` actions by its time limit."""
    dt, period = goal_doc["physics"]["dt"], goal_doc["task"]["control_period"]
    return make_goal(goal_doc, n, time_limit=steps * period * dt, **options)


def trajectory(env, seq, seed):
    obs, infos = env.reset(seed=seed)
    out = [(obs, None, None, None, infos)]
    for a in seq:
        out.append(env.step(a))
    return out


@pytest.mark.parametrize("mode", ["next_step", "same_step", "disabled", "NextStep", "SameStep", "Disabled",
                                  groundsim.AutoresetMode.SAME_STEP])
def test_the_mode_is_declared_in_metadata(goal_doc, mode):
    env = make_goal(goal_doc, 1, autoreset_mode=mode)
    assert isinstance(env.metadata["autoreset_mode"], groundsim.AutoresetMode)
    name = mode.value if isinstance(mode, groundsim.AutoresetMode) else mode
    assert env.metadata["autoreset_mode"].value.lower() == name.replace("_", "").lower()


@pytest.mark.parametrize("mode", ["nextstep ", "same step", "", None, 3, "auto"])
def test_an_unknown_mode_is_refused_naming_the_field(goal_doc, mode):
    with pytest.raises(groundsim.ExperimentError) as e:
        make_goal(goal_doc, 1, autoreset_mode=mode)
    assert e.value.field == "autoreset_mode" and "same_step" in str(e.value)


def test_same_step_is_next_step_without_the_reset_steps(goal_doc):
    """SAME_STEP returns at the ending step what NEXT_STEP returns one step
    later (the next episode's first observation), and the ending step's own
    observation in final_obs; the rest of the two runs is the same."""
    nxt, same = short(goal_doc), short(goal_doc, autoreset_mode="same_step")
    seq = actions(nxt, 7)
    # NEXT_STEP: steps 1-3, the reset step 4 (action ignored), 5-7
    a = trajectory(nxt, seq, seed=4)
    # SAME_STEP skips the reset step: its steps 1-6 take actions 0, 1, 2, 4, 5, 6
    b = trajectory(same, [seq[0], seq[1], seq[2], seq[4], seq[5], seq[6]], seed=4)
    for k in (1, 2):
        for x, y in zip(a[k][:4], b[k][:4]):
            assert x.tobytes() == y.tobytes()
        assert "final_obs" not in b[k][4]
    obs, rew, term, trunc, infos = b[3]
    assert trunc.all() and not term.any()
    assert rew.tobytes() == a[3][1].tobytes()
    assert infos["final_obs"].tobytes() == a[3][0].tobytes() and infos["_final_obs"].all()
    assert obs.tobytes() == a[4][0].tobytes()  # already the next episode's first
    final = infos["final_info"]
    assert final["episode_index"].tolist() == [1, 1] and final["episode_steps"].tolist() == [3, 3]
    np.testing.assert_array_equal(final["episode_return"], a[3][4]["episode_return"])
    assert final["_episode_steps"].all() and infos["_final_info"].all()
    # the counters of the returned step are the new episode's
    assert infos["episode_index"].tolist() == [2, 2] and infos["episode_steps"].tolist() == [0, 0]
    for k in (4, 5):
        for x, y in zip(a[k + 1][:4], b[k][:4]):
            assert x.tobytes() == y.tobytes()
    # the second episode ends too: the same sequence again
    for x, y in zip(a[7][1:4], b[6][1:4]):
        assert x.tobytes() == y.tobytes()
    assert b[6][4]["final_obs"].tobytes() == a[7][0].tobytes()


def test_same_step_masks_only_the_envs_that_ended(goal_doc):
    env = short(goal_doc, autoreset_mode="same_step", n=3)
    seq = actions(env, 3)
    env.reset(seed=8)
    env.step(seq[0])
    # env 1 starts over, so it ends one step after the others
    env.reset(options={"env": 1})
    env.step(seq[1])
    obs, _, term, trunc, infos = env.step(seq[2])
    ended = trunc | term
    assert ended.tolist() == [True, False, True]
    assert infos["_final_obs"].tolist() == [True, False, True]
    assert not infos["final_obs"][1].any()  # zeros where nothing ended, as Gymnasium stacks it
    assert infos["episode_steps"].tolist() == [0, 2, 0]


def test_disabled_refuses_an_ended_env_until_it_is_reset(goal_doc):
    env = short(goal_doc, autoreset_mode="disabled")
    seq = actions(env, 5)
    env.reset(seed=2)
    for k in range(3):
        obs, rew, term, trunc, infos = env.step(seq[k])
    assert trunc.all()
    before = obs.copy()
    snapshot = env.snapshot(0)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step(seq[3])
    assert e.value.field == "actions" and "env 0" in str(e.value) and "reset_mask" in str(e.value)
    assert env.snapshot(0) == snapshot  # nothing was stepped
    # resetting env 0 alone is not enough: env 1 ended too
    env.reset(options={"reset_mask": np.array([True, False])})
    with pytest.raises(groundsim.ExperimentError, match="env 1"):
        env.step(seq[3])
    obs, infos = env.reset(options={"reset_mask": np.array([False, True])})
    assert infos["episode_index"].tolist() == [2, 2] and not np.array_equal(obs[0], before[0])
    obs, rew, term, trunc, infos = env.step(seq[3])
    assert infos["episode_steps"].tolist() == [1, 1] and not (term | trunc).any()


@pytest.mark.parametrize("mode", ["next_step", "same_step", "disabled"])
def test_episode_statistics_in_record_episode_statistics_format(goal_doc, mode):
    env = short(goal_doc, steps=4, autoreset_mode=mode)
    seq = actions(env, 4)
    env.reset(seed=6)
    total = np.zeros(2)
    for k in range(4):
        obs, rew, term, trunc, infos = env.step(seq[k])
        total += rew
        if k < 3:
            assert "episode" not in infos and "_episode" not in infos
    assert set(infos["episode"]) == {"r", "l", "t"}
    assert infos["_episode"].tolist() == [True, True] and infos["_episode"].dtype == np.bool_
    np.testing.assert_allclose(infos["episode"]["r"], total, rtol=1e-12)
    assert infos["episode"]["l"].tolist() == [4, 4]
    assert (infos["episode"]["t"] >= 0).all() and (infos["episode"]["t"] < 60).all()
    if mode == "next_step":
        # the reset step ends nothing and adds nothing
        infos = env.step(seq[0])[4]
        assert "episode" not in infos


def test_without_episode_statistics_a_wrapper_can_add_them(goal_doc):
    """gymnasium.wrappers.vector.RecordEpisodeStatistics raises ValueError
    when infos already hold 'episode' or '_episode' at an episode end."""
    env = short(goal_doc, steps=2, episode_statistics=False)
    env.reset(seed=1)
    seen = set()
    for a in actions(env, 5):
        *_, infos = env.step(a)
        seen |= set(infos)
    assert not seen & {"episode", "_episode"}


def test_own_counters_collide_with_no_gymnasium_key(goal_doc):
    env = short(goal_doc, autoreset_mode="same_step")
    _, infos = env.reset(seed=0)
    assert set(infos) == set(OWN_KEYS) | {"_" + k for k in OWN_KEYS}
    assert not set(infos) & GYMNASIUM_KEYS
