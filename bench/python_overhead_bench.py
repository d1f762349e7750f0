#!/usr/bin/env python3
"""Python's own cost of VecEnv.step, the C++ batch taken out.

    PYTHONPATH=build/python python3 bench/python_overhead_bench.py [--envs 256] [--copy 1]

The env's core is wrapped so that step() and fill_infos() only write
"not done" flags: what remains is the wrapper (action checks, fresh
arrays or views, the infos dict) and the binding's argument checks are
not counted (they run inside the core). Prints CPU microseconds per step,
the median of --rounds rounds. bench/python_step_bench.py has the whole
step."""

import argparse
import pathlib
import statistics
import time

import numpy as np

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


class NoPhysics:
    """A BatchEnv whose step writes no observation, only that nothing ended."""

    def __init__(self, core):
        self.core = core

    def step(self, actions, obs, rewards, terminations, truncations):
        terminations[:] = False
        truncations[:] = False

    def fill_infos(self, *arrays):
        pass

    def __getattr__(self, name):
        return getattr(self.core, name)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--task", default=str(ROOT / "configs" / "tasks" / "fast_car.json"))
    p.add_argument("--envs", type=int, default=256)
    p.add_argument("--copy", type=int, default=1)
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args()
    env = groundsim.make_vec(args.task, args.envs, 1, copy=bool(args.copy))
    env.reset(seed=0)
    env._core = NoPhysics(env._core)
    actions = np.zeros(env.action_space.shape, np.float32)
    for _ in range(200):
        env.step(actions)
    per_step = []
    for _ in range(args.rounds):
        t = time.thread_time()
        for _ in range(args.steps):
            env.step(actions)
        per_step.append((time.thread_time() - t) / args.steps * 1e6)
    print(f"{args.envs} envs, copy={bool(args.copy)}: Python's part of VecEnv.step {statistics.median(per_step):.2f} us "
          f"CPU per step (median of {args.rounds} rounds of {args.steps}; {min(per_step):.2f}-{max(per_step):.2f})")


if __name__ == "__main__":
    main()
