"""Bad input gets a ValueError (groundsim.ExperimentError or ScenarioError)
naming what is wrong, and the env keeps working."""

import copy

import numpy as np
import pytest

import groundsim
from conftest import TASKS, actions, make_goal


@pytest.fixture
def env(goal_doc):
    e = make_goal(goal_doc, 3)
    e.reset(seed=0)
    yield e
    e.close()


@pytest.mark.parametrize("shape", [(3,), (3, 2), (2, 3), (4, 3), (3, 3, 1)])
def test_wrong_action_shape_names_actions_and_both_shapes(env, shape):
    with pytest.raises(ValueError) as e:
        env.step(np.zeros(shape))
    assert isinstance(e.value, groundsim.ExperimentError) and e.value.field == "actions"
    assert "actions" in str(e.value) and str((3, env.layout.action_size)) in str(e.value) and str(shape) in str(e.value)


def test_actions_that_are_not_numbers_are_refused(env):
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step([["a", "b", "c"]] * 3)
    assert e.value.field == "actions"


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, 1e39])  # 1e39 is inf as float32
def test_non_finite_actions_are_refused_naming_the_component_and_nothing_is_stepped(goal_doc, env, bad):
    seq = actions(env, 2)
    twin = make_goal(goal_doc, 3)
    twin.reset(seed=0)
    a = seq[0].astype(np.float64)
    a[2, 1] = bad
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step(a)
    assert e.value.field == "actions[2][1]"
    # the refused call changed nothing: both continue alike
    for s in seq:
        assert env.step(s)[0].tobytes() == twin.step(s)[0].tobytes()


def test_lists_and_float64_are_accepted_as_actions(env):
    a = actions(env, 1)[0]
    twin = copy.copy(a)
    obs_list = env.step(a.astype(np.float64).tolist())[0].copy()
    env.reset(seed=0)
    assert env.step(twin)[0].tobytes() == obs_list.tobytes()


@pytest.mark.parametrize("seed", [-1, 2**63, 2**64 + 5, "1", 1.5])
def test_bad_seeds_are_refused(env, seed):
    with pytest.raises(groundsim.ExperimentError) as e:
        env.reset(seed=seed)
    assert e.value.field == "seed"


def test_seed_plus_env_index_must_stay_in_range(env):
    with pytest.raises(groundsim.ExperimentError) as e:
        env.reset(seed=2**63 - 2)  # env 2 would get 2^63
    assert e.value.field == "seed"
    env.reset(seed=2**63 - 3)  # the largest allowed for 3 envs


def test_the_binding_checks_seeds_itself(env):
    obs = np.zeros((3, env.layout.obs_size), np.float32)
    for seed in (-1, 2**63, "x"):
        with pytest.raises(groundsim.ExperimentError) as e:
            env._core.reset(seed, obs)
        assert e.value.field == "seed"


@pytest.mark.parametrize("options", [{"env": 3}, {"env": -1}, {"env": [0, 5]}, {"envs": 0},
                                     {"reset_mask": [True, False, True]}, {"reset_mask": np.ones(2, bool)},
                                     {"env": 0, "reset_mask": np.ones(3, bool)}, "env"])
def test_bad_reset_options_are_refused(env, options):
    with pytest.raises(groundsim.ExperimentError) as e:
        env.reset(options=options)
    assert e.value.field.startswith("options")


def test_an_unknown_feature_is_a_scenario_error_naming_its_path(goal_doc):
    doc = copy.deepcopy(goal_doc)
    doc["task"]["observation"] = doc["task"]["observation"] + ["velocty_body"]
    with pytest.raises(groundsim.ScenarioError) as e:
        groundsim.make_vec(doc, 2, 1, files_dir=TASKS)
    path = f"/task/observation/{len(doc['task']['observation']) - 1}"
    assert isinstance(e.value, ValueError)
    assert [i.path for i in e.value.issues] == [path]
    assert "velocty_body" in e.value.issues[0].message and path in str(e.value)


def test_a_scenario_without_a_task_is_refused(goal_doc):
    doc = copy.deepcopy(goal_doc)
    del doc["task"]
    with pytest.raises(ValueError):
        groundsim.make_vec(doc, 1, 1, files_dir=TASKS)


@pytest.mark.parametrize("scenario", ["{not json", 42, {"x": float("nan")}])
def test_unreadable_scenarios_are_refused(scenario):
    with pytest.raises(ValueError):
        groundsim.make_vec(scenario, 1, 1)


def test_a_missing_file_is_file_not_found():
    with pytest.raises(FileNotFoundError):
        groundsim.make_vec(TASKS / "no_such_task.json", 1, 1)


@pytest.mark.parametrize("num_envs,field", [(0, "num_envs"), (-3, "num_envs"), (2**40, "num_envs"),
                                            ("2", "num_envs")])
def test_bad_env_counts_are_refused(goal_doc, num_envs, field):
    with pytest.raises(groundsim.ExperimentError) as e:
        make_goal(goal_doc, num_envs)
    assert e.value.field == field


def corrupt(snapshot, at):
    b = bytearray(snapshot)
    b[at] ^= 0x40
    return bytes(b)


def test_corrupted_snapshots_are_refused_and_the_env_is_untouched(goal_doc, env):
    snap = env.snapshot(1)
    before = env.snapshot(1)
    for bad in [b"", snap[:-1], snap[: len(snap) // 2], corrupt(snap, 0), corrupt(snap, len(snap) // 2),
                corrupt(snap, len(snap) - 1), snap + b"\0"]:
        with pytest.raises(groundsim.ExperimentError) as e:
            env.restore(1, bad)
        assert e.value.field == "snapshot"
        assert env.snapshot(1) == before
    with pytest.raises(groundsim.ExperimentError) as e:
        env.restore(1, "not bytes")
    assert e.value.field == "snapshot"


def test_a_snapshot_of_another_scenario_is_refused(goal_doc, env):
    other = make_goal(goal_doc, 1, time_limit=5.0)
    other.reset(seed=0)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.restore(0, other.snapshot(0))
    assert e.value.field == "snapshot"


@pytest.mark.parametrize("index", [-1, 3, 2**40])
def test_env_indices_out_of_range_are_refused(env, index):
    for call in (lambda: env.snapshot(index), lambda: env.restore(index, env.snapshot(0))):
        with pytest.raises(groundsim.ExperimentError) as e:
            call()
        assert e.value.field == "env"


def _read_only(array):
    array.flags.writeable = False
    return array


def test_the_binding_checks_every_buffer(env):
    n, o, a = 3, env.layout.obs_size, env.layout.action_size
    good = dict(actions=np.zeros((n, a), np.float32), obs=np.zeros((n, o), np.float32),
                rewards=np.zeros(n), terminations=np.zeros(n, bool), truncations=np.zeros(n, bool))
    wrong = {
        "actions": [np.zeros((n, a)), np.zeros((n, a + 1), np.float32), np.zeros((a, n), np.float32).T, [[0.0] * a] * n],
        "obs": [np.zeros((n, o)), np.zeros((n, o + 1), np.float32), np.zeros((n, 2 * o), np.float32)[:, ::2],
                np.zeros((n, o), np.float32, order="F") if o > 1 and n > 1 else np.zeros(1),
                _read_only(np.zeros((n, o), np.float32))],  # as the wrapper returns with copy=False
        "rewards": [np.zeros(n, np.float32), np.zeros(n + 1)],
        "terminations": [np.zeros(n, np.uint8), np.zeros((n, 1), bool)],
        "truncations": [np.zeros(n, np.int64)],
    }
    for name, values in wrong.items():
        for value in values:
            args = dict(good, **{name: value})
            with pytest.raises(ValueError) as e:
                env._core.step(**args)
            assert e.value.field == name and name in str(e.value)
    with pytest.raises(ValueError) as e:
        env._core.step(**dict(good, obs=np.zeros((n, o))))
    assert f"({n}, {o})" in str(e.value) and "float32" in str(e.value)


def test_closed_envs_refuse_calls(goal_doc):
    e = make_goal(goal_doc, 2)
    e.reset(seed=0)
    e.close()
    e.close()  # twice is fine
    with pytest.raises(groundsim.ExperimentError) as err:
        e.step(np.zeros((2, e.layout.action_size)))
    assert err.value.field == "env"
