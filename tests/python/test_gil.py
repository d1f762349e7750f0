"""The GIL is released while the C++ environments run: another Python
thread makes progress during a step. Shown with a test double whose step
blocks until its gate is opened (groundsim._core._make_gate_env), wrapped
by the same binding and VecEnv as the real environments: this thread sees
the step waiting, counts while it waits, then opens the gate. Had step()
kept the GIL, this thread could not run until the step gave up (30 s, then
ExperimentError with field "gate") and would never see it waiting."""

import threading

import numpy as np

import groundsim
from groundsim import _core


def test_another_thread_counts_while_a_step_runs():
    core, gate = _core._make_gate_env(2)
    env = groundsim.VecEnv(core, "gate")
    env.reset(seed=0)
    result = {}

    def stepper():
        try:
            result["obs"] = env.step(np.zeros((2, 1)))[0].copy()
        except Exception as e:  # reported below
            result["error"] = e

    thread = threading.Thread(target=stepper)
    thread.start()
    while thread.is_alive() and not gate.waiting():
        pass
    counted = 0
    while gate.waiting() and counted < 1000:
        counted += 1  # Python running here while the other thread is inside step()
    gate.open()
    thread.join()
    assert "error" not in result, result.get("error")
    assert counted == 1000
    assert result["obs"].tolist() == [[1.0], [1.0]]
