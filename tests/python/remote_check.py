"""make_remote_vec against make_vec: the same seed and actions give the same
bits, over a real groundsim-server. Run by CTest inside a private network
namespace (tests/integration/netns_run.sh) as python.remote; not collected
by the plain pytest run (it needs the namespace's multicast route)."""

import os
import subprocess
import time

import numpy as np
import pytest

import groundsim
from conftest import GOAL, TASKS, actions

URL = "udpm://239.255.76.67:7667?ttl=0"
SPEED = TASKS / "speed.json"


@pytest.fixture()
def server():
    # as the README starts it: no --terrain-dir; the files a task names travel with it
    p = subprocess.Popen([os.environ["GROUNDSIM_SERVER"], "--lcm-url", URL, "--workers", "2", "--quiet"],
                         stdout=subprocess.PIPE, text=True)
    line = p.stdout.readline()  # the ready line comes first
    assert "groundsim-server ready" in line, line
    yield p
    if p.poll() is None:
        p.terminate()
        p.wait(30)


def steps(env, seq, seed):
    out = [tuple(np.copy(a) for a in env.reset(seed=seed)[:1])]
    for a in seq:
        obs, rew, term, trunc, infos = env.step(a)
        out.append((obs.copy(), rew.copy(), term.copy(), trunc.copy(), infos["episode_index"].copy()))
    return out


def test_remote_is_bit_identical_to_in_process(server):
    local = groundsim.make_vec(SPEED, 8, num_threads=2)
    remote = groundsim.make_remote_vec(SPEED, 8, lcm_url=URL)
    assert remote.single_observation_space.shape == local.single_observation_space.shape
    assert list(remote.layout.action) == list(local.layout.action)
    assert remote.layout.dt == local.layout.dt
    seq = actions(local, 60)
    a, b = steps(local, seq, 11), steps(remote, seq, 11)
    for x, y in zip(a, b):
        for u, v in zip(x, y):
            assert u.tobytes() == v.tobytes()
    remote.close()
    local.close()


def test_goal_on_its_heightfield_is_the_same_remote_and_in_process(server):
    """configs/tasks/goal.json names ../terrain/hills.png: sent with the create."""
    local = groundsim.make_vec(GOAL, 16, num_threads=2)
    remote = groundsim.make_remote_vec(GOAL, 16, lcm_url=URL)
    seq = actions(local, 40)
    a, b = steps(local, seq, 3), steps(remote, seq, 3)
    for x, y in zip(a, b):
        for u, v in zip(x, y):
            assert u.tobytes() == v.tobytes()
    remote.close()
    local.close()


@pytest.mark.parametrize("task", sorted(p.name for p in TASKS.glob("*.json")))
def test_every_shipped_task_runs_remotely(server, task):
    remote = groundsim.make_remote_vec(TASKS / task, 4, lcm_url=URL)
    obs, _ = remote.reset(seed=1)
    assert np.all(np.isfinite(obs))
    for a in actions(remote, 5):
        obs, rew, *_ = remote.step(a)
        assert np.all(np.isfinite(obs)) and np.all(np.isfinite(rew))
    remote.close()


def test_a_dict_sends_its_files_from_files_dir(server, goal_doc):
    remote = groundsim.make_remote_vec(goal_doc, 2, lcm_url=URL, files_dir=TASKS)
    remote.reset(seed=0)
    remote.close()
    # without files_dir the file cannot go: the error says which and why
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make_remote_vec(goal_doc, 2, lcm_url=URL)
    assert "../terrain/hills.png" in str(e.value) and "not sent" in str(e.value)


def test_remote_errors_name_the_field_and_a_dead_server_is_reported(server):
    remote = groundsim.make_remote_vec(SPEED, 2, lcm_url=URL)
    remote.reset(seed=0)
    bad = np.zeros((2, remote.single_action_space.shape[0]), np.float32)
    bad[1, 0] = np.nan
    with pytest.raises(groundsim.ExperimentError) as e:
        remote.step(bad)
    assert e.value.field == "actions[1][0]"
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make_remote_vec(SPEED, 100000, lcm_url=URL)
    assert e.value.field == "num_envs"
    server.kill()
    server.wait(30)
    time.sleep(0.1)
    with pytest.raises(groundsim.RemoteError, match="no heartbeat from groundsim-server"):
        remote.step(np.zeros_like(bad))


def test_same_step_and_a_curriculum_are_the_same_remote_and_in_process(server):
    local = groundsim.make_vec(SPEED, 4, num_threads=1, autoreset_mode="same_step", drawn_in_infos=True)
    remote = groundsim.make_remote_vec(SPEED, 4, lcm_url=URL, autoreset_mode="same_step", drawn_in_infos=True)
    assert list(remote.layout.drawn) == list(local.layout.drawn) == ["x", "y", "yaw", "speed", "ground.amplitude"]
    curriculum = {"speed": [1, 3], "parameters": [{"path": "ground.amplitude", "range": [0.1, 0.12]}]}
    for env in (local, remote):
        env.reset(seed=2)
        env.set_randomization(curriculum, envs=[0, 2])
    seq = actions(local, 5)
    for env in (local, remote):
        env._out_run = [env.reset(seed=2)[1]["drawn"]]
        for a in seq:
            env._out_run.append(env.step(a)[0])
    for u, v in zip(local._out_run, remote._out_run):
        assert u.tobytes() == v.tobytes()
    assert (local.drawn()[[0, 2], 4] >= 0.1).all() and (local.drawn()[[1, 3], 4] <= 0.08).all()
    with pytest.raises(groundsim.ExperimentError) as e:
        remote.set_randomization({"x": [2, 1]})
    assert e.value.field == "randomize/x"
    remote.close()
    local.close()


def test_two_agents_are_the_same_remote_and_in_process(server):
    race = TASKS / "race.json"
    local = groundsim.make_vec(race, 3, num_threads=1, autoreset_mode="same_step")
    remote = groundsim.make_remote_vec(race, 3, lcm_url=URL, autoreset_mode="same_step")
    assert remote.num_envs == local.num_envs == 6 and list(remote.layout.agents) == ["red", "blue"]
    rng = np.random.default_rng(4)
    seq = [rng.uniform([0, 0, -1], [1, 1, 1], (6, 3)).astype(np.float32) for _ in range(30)]
    out = {}
    for name, env in (("local", local), ("remote", remote)):
        obs, infos = env.reset(seed=8)
        run = [obs, infos["active"]]
        for a in seq:
            obs, rew, term, trunc, infos = env.step(a)
            run += [obs, rew, term, trunc, infos["active"], infos["episode_return"]]
        run.append(env.restore(1, env.snapshot(1)))
        out[name] = run
    for u, v in zip(out["local"], out["remote"]):
        assert u.tobytes() == v.tobytes()
    remote.close()
    local.close()
