"""PettingZoo itself (python/requirements.txt's version) against every
multi-agent task the package ships: its parallel API test and its seed
test."""

import pytest

from pettingzoo.test import parallel_api_test, parallel_seed_test

import groundsim
from groundsim.registration import _MULTI_AGENT

NEEDS = ("pettingzoo",)


@pytest.mark.parametrize("task", sorted(_MULTI_AGENT))
def test_parallel_api_test_passes(task):
    env = groundsim.make_parallel(task)
    assert env.max_num_agents >= 2
    parallel_api_test(env, num_cycles=400)
    env.close()


@pytest.mark.parametrize("task", sorted(_MULTI_AGENT))
def test_parallel_seed_test_passes(task):
    parallel_seed_test(lambda: groundsim.make_parallel(task), num_cycles=50)
