"""Several agents in one environment: PettingZoo's parallel API
(make_parallel), the batched rows of make_vec with the active mask, the
agents_body feature, agents leaving when done, and bad input."""

import copy
import json
import math

import numpy as np
import pytest

import groundsim
from conftest import TASKS

RACE = TASKS / "race.json"


@pytest.fixture(scope="module")
def race_doc():
    return json.loads(RACE.read_text())


def race(doc=None, **task):
    doc = copy.deepcopy(doc or json.loads(RACE.read_text()))
    doc["task"].update(task)
    return doc


def column(env, name):
    return list(env.layout.observation).index(name)


def test_the_parallel_api(race_doc):
    env = groundsim.make_parallel("groundsim/Race-v0")
    assert env.possible_agents == ["red", "blue"] and env.agents == []
    obs, infos = env.reset(seed=3)
    assert env.agents == ["red", "blue"] and set(obs) == set(infos) == {"red", "blue"}
    for agent in env.agents:
        assert env.observation_space(agent).shape == obs[agent].shape
        assert env.action_space(agent).shape == (3,)
    # same seed, same start; obs differ between the two cars
    obs2, _ = groundsim.make_parallel("race").reset(seed=3)
    assert obs["red"].tobytes() == obs2["red"].tobytes() and obs["red"].tobytes() != obs["blue"].tobytes()
    full = {a: np.array([1.0, 0.0, 0.0], np.float32) for a in env.agents}
    for _ in range(5):
        obs, rew, term, trunc, infos = env.step(full)
        assert set(obs) == set(rew) == set(term) == set(trunc) == set(infos) == {"red", "blue"}
        assert all(type(r) is float for r in rew.values()) and all(type(t) is bool for t in term.values())
    # both accelerate towards the goal 60 m ahead: each closes on it
    assert rew["red"] > 0 and rew["blue"] > 0
    assert env.state().shape == (2 * obs["red"].size,)


def test_each_agent_sees_the_other_at_the_same_distance(race_doc):
    """agents_body = R_me^T (p_other - p_me): the two views are the same
    vector rotated into each car's frame, so their lengths agree, and on the
    start grid (y = +-5, offsets up to 0.5 m, yaw within 5 deg) blue is to red's right."""
    env = groundsim.make_parallel(race(race_doc), files_dir=TASKS)
    obs, _ = env.reset(seed=11)
    x, y = column(env, "agents_body.0.x"), column(env, "agents_body.0.y")
    red, blue = obs["red"][[x, y]], obs["blue"][[x, y]]
    assert math.hypot(*red) == pytest.approx(math.hypot(*blue), rel=1e-5)
    assert 10 - 1.5 < math.hypot(*red) < 10 + 1.5
    assert red[1] < 0 < blue[1]


def test_an_agent_that_reaches_the_goal_leaves_and_the_episode_goes_on(race_doc):
    # the goal on red's start (radius 3) and blue 10 m from it, no randomisation:
    # red terminates at the first step, blue drives on until the time limit
    doc = race(race_doc, goal=[0.0, 5.0], randomize={}, time_limit=3 * 10 * 0.004)
    doc["task"]["reward"] = {"goal": 10.0, "progress_to_goal": 1.0}
    env = groundsim.make_parallel(doc)
    env.reset(seed=0)
    zero = np.zeros(3, np.float32)
    obs, rew, term, trunc, _ = env.step({"red": zero, "blue": zero})
    assert term == {"red": True, "blue": False} and rew["red"] >= 10.0
    assert env.agents == ["blue"]
    with pytest.raises(groundsim.ExperimentError) as e:
        env.step({"red": zero, "blue": zero})
    assert e.value.field == "actions['red']" and "done" in str(e.value)
    obs, rew, term, trunc, _ = env.step({"blue": zero})
    assert set(obs) == {"blue"} and not term["blue"] and not trunc["blue"]
    obs, rew, term, trunc, _ = env.step({"blue": zero})
    assert trunc == {"blue": True} and env.agents == []
    with pytest.raises(groundsim.ExperimentError, match="reset"):
        env.step({})
    env.reset()
    assert env.agents == ["red", "blue"]


def test_the_batched_rows_mask_agents_that_left(race_doc):
    doc = race(race_doc, goal=[0.0, 5.0], randomize={}, time_limit=3 * 10 * 0.004)
    vec = groundsim.make_vec(doc, 2, 1, autoreset_mode="same_step")
    assert vec.num_envs == 4 and vec.num_worlds == 2 and vec.num_agents == 2
    assert list(vec.layout.agents) == ["red", "blue"]
    obs, infos = vec.reset(seed=5)
    assert obs.shape[0] == 4 and infos["active"].all()
    zero = np.zeros((4, 3), np.float32)
    obs, rew, term, trunc, infos = vec.step(zero)
    assert term.tolist() == [True, False, True, False]
    assert infos["active"].all()  # all four took part in this step
    obs, rew, term, trunc, infos = vec.step(zero)
    assert infos["active"].tolist() == [False, True, False, True]
    assert rew[[0, 2]].tolist() == [0.0, 0.0] and not (term | trunc)[[0, 2]].any()
    # the third step ends blue by the time limit: both worlds end and start over (same step)
    obs, rew, term, trunc, infos = vec.step(zero)
    assert trunc.tolist() == [False, True, False, True]
    assert infos["_final_obs"].tolist() == [False, True, False, True]
    assert infos["episode_index"].tolist() == [2, 2, 2, 2] and infos["active"].all()


def test_a_multi_agent_task_is_refused_as_a_single_env():
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make("groundsim/Race-v0")
    assert e.value.field == "task" and "make_parallel" in str(e.value)


def test_bad_actions_name_the_agent(race_doc):
    env = groundsim.make_parallel("race")
    env.reset(seed=0)
    zero = np.zeros(3, np.float32)
    cases = [({"red": zero}, "actions"), ({"red": zero, "blue": zero, "green": zero}, "actions"),
             ({"red": zero, "blue": np.zeros(2)}, "actions['blue']"),
             ({"red": np.array([np.nan, 0, 0]), "blue": zero}, "actions['red']"), ([zero, zero], "actions")]
    for actions, field in cases:
        with pytest.raises(groundsim.ExperimentError) as e:
            env.step(actions)
        assert e.value.field == field, str(e.value)
    env.step({"red": zero, "blue": zero})  # still works


@pytest.mark.parametrize("agents, pointer", [
    (["red", "green"], "/task/agents/1"),
    (["red", "red"], "/task/agents/1"),
    ([], "/task/agents"),
    ("red", "/task/agents"),
])
def test_bad_agent_lists_name_the_field(race_doc, agents, pointer):
    with pytest.raises(groundsim.ScenarioError) as e:
        groundsim.make_vec(race(race_doc, agents=agents), 1)
    assert pointer in [i.path for i in e.value.issues], e.value.issues


def test_vehicle_and_agents_together_are_refused(race_doc):
    with pytest.raises(groundsim.ScenarioError) as e:
        groundsim.make_vec(race(race_doc, vehicle="red"), 1)
    assert "/task/agents" in [i.path for i in e.value.issues]


def test_rows_do_not_depend_on_threads_and_snapshots_restore_both_agents():
    seq = [np.random.default_rng(k).uniform([0, 0, -1], [1, 1, 1], (6, 3)).astype(np.float32) for k in range(20)]
    out = []
    for threads in (1, 2):
        vec = groundsim.make_vec(RACE, 3, threads)
        run = [vec.reset(seed=9)[0]]
        for a in seq:
            run.extend(vec.step(a)[:4])
        out.append(run)
        vec.close()
    for x, y in zip(*out):
        assert x.tobytes() == y.tobytes()
    # an environment's snapshot holds both agents; restored elsewhere it continues the same
    a, b = groundsim.make_vec(RACE, 1, 1), groundsim.make_vec(RACE, 1, 1)
    a.reset(seed=1)
    b.reset(seed=2)
    for k in range(5):
        a.step(seq[k][:2])
    b.restore(0, a.snapshot(0))
    for k in range(5, 15):
        ra, rb = a.step(seq[k][:2]), b.step(seq[k][:2])
        for x, y in zip(ra[:4], rb[:4]):
            assert x.tobytes() == y.tobytes()


def test_starts_that_could_be_drawn_into_each_other_are_refused(race_doc):
    # 10 m apart side by side, each may move 4.4 m across: their footprint
    # rectangles (a sedan is 1.8 m wide) may meet; 3.2 m each (3.6 m between
    # centres) is a valid start since starts are kept apart by rectangles
    ok = race(race_doc, randomize={"y": [-3.2, 3.2]})
    groundsim.make_vec(ok, 1)
    doc = race(race_doc, randomize={"y": [-4.4, 4.4]})
    with pytest.raises(groundsim.ScenarioError) as e:
        groundsim.make_vec(doc, 1)
    assert e.value.issues[0].path == "/task/randomize" and "red" in e.value.issues[0].message
    env = groundsim.make_vec(RACE, 1)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.set_randomization({"x": [-2.5, 2.5], "y": [-4.5, 4.5]})
    assert e.value.field == "randomize"
