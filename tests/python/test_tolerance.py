"""make_vec(..., tolerance=...): one pilot chooses the settings of every
environment (docs/accuracy.md, "Accuracy on demand"); bad tolerances are
refused naming the field."""

import numpy as np
import pytest

import groundsim
from conftest import GOAL, actions


def test_a_tolerance_runs_and_is_reproducible():
    env = groundsim.make_vec(str(GOAL), 2, 1, tolerance=0.05)
    twin = groundsim.make_vec(str(GOAL), 2, 1, tolerance=0.05)
    seq = actions(env, 5)
    env.reset(seed=1)
    twin.reset(seed=1)
    for a in seq:
        o1 = env.step(a)[0]
        o2 = twin.step(a)[0]
        assert np.all(np.isfinite(o1))
        np.testing.assert_array_equal(o1, o2)
    env.close()
    twin.close()


@pytest.mark.parametrize("bad", [0, 2.0, -0.1])
def test_a_tolerance_out_of_range_names_the_field(bad):
    with pytest.raises(groundsim.ScenarioError) as e:
        groundsim.make_vec(str(GOAL), 1, tolerance=bad)
    assert "/accuracy/tolerance" in str(e.value)


@pytest.mark.parametrize("bad", ["1%", float("nan"), True, None.__class__])
def test_a_tolerance_that_is_not_a_number_is_refused(bad):
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make_vec(str(GOAL), 1, tolerance=bad)
    assert e.value.field == "tolerance"
