"""Gymnasium itself (python/requirements.txt's version) against the package:
its environment checker on every shipped single-agent task, its registry
(gymnasium.make, gymnasium.make_vec through the vector entry point) and
its common wrappers, single and vector, with the results their contracts
promise."""

import warnings

import numpy as np
import pytest

import gymnasium
from gymnasium.utils.env_checker import check_env
from gymnasium.wrappers import ClipAction, NormalizeObservation, RecordEpisodeStatistics, TimeLimit
from gymnasium.wrappers import vector as vector_wrappers

import groundsim

NEEDS = ("gymnasium",)
SINGLE = [t for t in groundsim.task_ids() if t not in groundsim.registration._MULTI_AGENT]


def test_the_real_gymnasium_is_the_one_in_use():
    assert groundsim.HAVE_GYMNASIUM
    assert gymnasium.__version__.startswith("1.")
    env = groundsim.make("groundsim/Goal-v0")
    assert isinstance(env, gymnasium.Env)
    assert isinstance(env.observation_space, gymnasium.spaces.Box)
    assert isinstance(groundsim.make_vec("groundsim/Goal-v0", 2), gymnasium.vector.VectorEnv)


@pytest.mark.parametrize("task", SINGLE)
def test_check_env_passes_on_every_shipped_task(task):
    env = groundsim.make(task)
    # the checker reports what it finds as warnings: none is allowed
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, skip_render_check=True)
    env.close()
    # observations such as speeds have no bound: an infinite Box, which the
    # checker warns about (as it does for MuJoCo's environments); nothing else
    inherent = ("observation space minimum value is -infinity", "observation space maximum value is infinity")
    found = [str(w.message) for w in caught if not any(i in str(w.message) for i in inherent)]
    assert not found


def test_registry_make_and_make_vec():
    ids = groundsim.register_envs()
    assert set(ids) == set(SINGLE)
    for task in SINGLE:
        assert task in gymnasium.registry
    env = gymnasium.make("groundsim/Goal-v0")
    obs, info = env.reset(seed=1)
    assert env.observation_space.contains(obs)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert np.isfinite(reward) and isinstance(terminated, bool) and isinstance(truncated, bool)
    env.close()
    venv = gymnasium.make_vec("groundsim/Goal-v0", num_envs=8, vectorization_mode="vector_entry_point")
    # one C++ batch, not SyncVectorEnv over eight envs
    assert isinstance(venv.unwrapped, groundsim.VecEnv) and venv.num_envs == 8
    obs, _ = venv.reset(seed=2)
    assert obs.shape == (8,) + venv.single_observation_space.shape
    obs, rewards, terms, truncs, infos = venv.step(venv.action_space.sample())
    assert rewards.shape == (8,) and terms.dtype == np.bool_
    venv.close()


def test_single_env_wrappers_keep_their_contracts():
    env = groundsim.make("groundsim/Goal-v0")
    period = env.layout.dt * env.layout.control_period
    limit = 5
    wrapped = RecordEpisodeStatistics(TimeLimit(ClipAction(NormalizeObservation(env)), max_episode_steps=limit))
    wrapped.reset(seed=3)
    total, steps = 0.0, 0
    while True:
        # actions far outside the box: ClipAction brings them to its bounds
        action = np.full(env.action_space.shape, 10.0, np.float32)
        obs, reward, terminated, truncated, info = wrapped.step(action)
        total += reward
        steps += 1
        if terminated or truncated:
            break
    assert steps == limit and truncated and not terminated
    # RecordEpisodeStatistics: the return and length of the episode just ended
    assert info["episode"]["l"] == limit
    assert info["episode"]["r"] == pytest.approx(total, rel=1e-6, abs=1e-9)
    assert np.isfinite(obs).all()
    # the same clipped actions on a bare env give the same rewards
    bare = groundsim.make("groundsim/Goal-v0")
    bare.reset(seed=3)
    high = bare.action_space.high
    bare_total = sum(bare.step(high)[1] for _ in range(limit))
    assert bare_total == pytest.approx(total, rel=1e-6, abs=1e-9)
    assert period > 0


def test_normalize_observation_standardises_what_it_saw():
    env = NormalizeObservation(groundsim.make("groundsim/Goal-v0"))
    env.reset(seed=4)
    rng = np.random.default_rng(0)
    seen = []
    for _ in range(200):
        obs, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
        seen.append(obs)
        if terminated or truncated:
            env.reset()
    seen = np.array(seen[50:])
    # running statistics: the later observations are of order one
    assert np.abs(seen.mean(axis=0)).max() < 3.0
    assert seen.std(axis=0).max() < 3.0


def test_vector_wrappers_on_the_batch():
    # the wrapper refuses an env that reports episode statistics itself (docs/experiments.md)
    venv = groundsim.make_vec("groundsim/Goal-v0", 4, autoreset_mode="next_step", episode_statistics=False)
    period = venv.layout.dt * venv.layout.control_period
    wrapped = vector_wrappers.RecordEpisodeStatistics(
        vector_wrappers.ClipAction(vector_wrappers.NormalizeObservation(venv)))
    wrapped.reset(seed=5)
    returns = np.zeros(4)
    ended = None
    for _ in range(100000):
        obs, rewards, terms, truncs, infos = wrapped.step(np.full((4, venv.single_action_space.shape[0]), 5.0, np.float32))
        returns += rewards
        done = terms | truncs
        if done.any():
            ended = done
            break
    assert ended is not None, "no episode ended"
    # the wrapper's episode return is the sum of the rewards, and groundsim's own counter agrees
    for i in np.flatnonzero(ended):
        assert infos["episode"]["r"][i] == pytest.approx(returns[i], rel=1e-5)
        assert infos["episode"]["l"][i] == infos["episode_steps"][i]
        assert infos["episode"]["r"][i] == pytest.approx(infos["episode_return"][i], rel=1e-5)

    assert np.isfinite(obs).all()
    assert period > 0
