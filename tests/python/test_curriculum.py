"""Curriculum and domain randomisation at run time: set_randomization (or
reset(options={"randomize": ...})) changes what the next resets of chosen
envs draw; drawn() reports what each reset drew; refusals name the field
and change nothing; the ranges travel in snapshots."""

import json
import math

import numpy as np
import pytest

import groundsim
from conftest import GOAL, TASKS, actions, make_goal

SPEED = TASKS / "speed.json"


def goal_distance(env, obs):
    return obs[:, env.layout.observation.index("goal_distance")]


def test_new_ranges_apply_to_the_chosen_envs_at_their_next_reset(goal_doc):
    env = make_goal(goal_doc, 3)
    assert env.layout.drawn == ["x", "y", "yaw", "speed"]
    env.reset(seed=1)
    before = env.drawn()
    env.set_randomization({"x": [5, 5], "y": [-3, -3], "yaw_deg": [90, 90]}, envs=[1])
    np.testing.assert_array_equal(env.drawn(), before)  # nothing until a reset
    obs, _ = env.reset(seed=1)
    drawn = env.drawn()
    assert drawn[1].tolist() == [5.0, -3.0, math.pi / 2, 0.0]
    np.testing.assert_array_equal(drawn[[0, 2]], before[[0, 2]])  # the same seeds, the task's ranges
    # the same start as a task written with those ranges (env 1 is seeded with 1 + 1)
    fixed = make_goal(goal_doc, 1, randomize={"x": [5, 5], "y": [-3, -3], "yaw_deg": [90, 90]})
    assert obs[1].tobytes() == fixed.reset(seed=2)[0][0].tobytes()
    # about 35 m and 23 m from the goal at (40, 20) (the body centre is not the placement point)
    assert goal_distance(env, obs)[1] == pytest.approx(math.hypot(35.0, 23.0), abs=0.5)
    # and keeps the new ranges at later resets
    env.reset(seed=99)
    assert env.drawn()[1].tolist() == [5.0, -3.0, math.pi / 2, 0.0]
    lo, hi = goal_doc["task"]["randomize"]["x"]
    assert lo <= env.drawn()[0][0] <= hi


def test_reset_options_randomize_applies_before_that_reset(goal_doc):
    env = make_goal(goal_doc, 2)
    env.reset(seed=0)
    env.reset(options={"randomize": {"x": [1.5, 1.5]}, "env": 0})
    assert env.drawn()[0][0] == 1.5
    assert env.drawn()[1][0] != 1.5
    mask = np.array([False, True])
    env.reset(options={"randomize": {"speed": [2, 2]}, "reset_mask": mask})
    assert env.drawn()[1][3] == 2.0 and env.drawn()[0][3] == 0.0


def test_parameters_change_their_range_and_are_reported_in_infos():
    env = groundsim.make_vec(SPEED, 2, 1, drawn_in_infos=True)
    assert env.layout.drawn == ["x", "y", "yaw", "speed", "ground.amplitude"]
    _, infos = env.reset(seed=3)
    assert infos["drawn"].shape == (2, 5) and infos["_drawn"].all()
    assert ((0.02 <= infos["drawn"][:, 4]) & (infos["drawn"][:, 4] <= 0.08)).all()
    env.set_randomization({"parameters": [{"path": "ground.amplitude", "range": [0.15, 0.15]}]})
    _, infos = env.reset()
    assert infos["drawn"][:, 4].tolist() == [0.15, 0.15]
    *_, infos = env.step(np.zeros((2, env.layout.action_size), np.float32))
    assert infos["drawn"][:, 4].tolist() == [0.15, 0.15]


@pytest.mark.parametrize("ranges, field", [
    ({"x": [3, 1]}, "randomize/x"),
    ({"x": [0, 1e9]}, "randomize/x/1"),
    ({"yaw_deg": [0, 720]}, "randomize/yaw_deg/1"),
    ({"x": [0]}, "randomize/x"),
    ({"x": "wide"}, "randomize/x"),
    ({"z": [0, 1]}, "randomize/z"),
    ({"x": [float("nan"), 1]}, "randomize"),
    ({"parameters": [{"path": "vehicle.mass", "range": [1, 2]}]}, "randomize/parameters/0/path"),
    ({"parameters": [{"path": "ground.amplitude", "range": [-0.01, 0.05]}]}, "randomize/parameters/0/range"),
    ({"parameters": [{"path": "ground.amplitude"}]}, "randomize/parameters/0/range"),
    ([0, 1], "randomize"),
])
def test_bad_ranges_are_refused_naming_the_field_and_change_nothing(ranges, field):
    env = groundsim.make_vec(SPEED, 2, 1)
    twin = groundsim.make_vec(SPEED, 2, 1)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.set_randomization(ranges)
    assert e.value.field == field, str(e.value)
    env.reset(seed=5)
    twin.reset(seed=5)
    np.testing.assert_array_equal(env.drawn(), twin.drawn())


def test_bad_env_choices_are_refused(goal_doc):
    env = make_goal(goal_doc, 2)
    for envs in (2, [0, 5], np.array([True]), -1):
        with pytest.raises(groundsim.ExperimentError) as e:
            env.set_randomization({"x": [0, 0]}, envs=envs)
        assert e.value.field == "envs"


def test_snapshots_carry_the_ranges(goal_doc):
    env = make_goal(goal_doc, 1)
    env.reset(seed=4)
    env.set_randomization({"x": [7, 8]})
    data = env.snapshot(0)
    fresh = make_goal(goal_doc, 1)
    fresh.reset(seed=123)
    fresh.restore(0, data)
    env.reset()
    fresh.reset()
    assert 7 <= env.drawn()[0][0] <= 8
    np.testing.assert_array_equal(env.drawn(), fresh.drawn())


def test_the_single_env_takes_a_curriculum():
    env = groundsim.make("goal")
    env.reset(seed=0, options={"randomize": {"x": [2, 2], "y": [1, 1]}})
    assert env.drawn()[:2].tolist() == [2.0, 1.0]
    env.set_randomization({"y": [-1, -1]})
    env.reset()
    assert env.drawn()[:2].tolist() == [2.0, -1.0]
