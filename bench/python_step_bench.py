#!/usr/bin/env python3
"""Throughput through Python, and Python's share of a batched step.

    PYTHONPATH=build/python python3 bench/python_step_bench.py [--envs 256] [--threads 1 2]

For each thread count, three ways to take the same steps, alternated in
rounds so a change of machine load hits all three alike:
  wrapper  VecEnv.step(actions): Gymnasium's API (shape check, the C++
           step, the infos, the returned views and dict)
  core     the C++ step alone through the binding (groundsim._core), with
           the wrapper's buffers: the buffer checks and the GIL release are
           all that Python adds
  Python's share = (wrapper - core) / wrapper, per step.
The C++ figure without Python is bench/experiments_bench (docs/experiments.md)."""

import argparse
import pathlib
import statistics
import time

import numpy as np

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--task", default=str(ROOT / "configs" / "tasks" / "fast_car.json"))
    p.add_argument("--envs", type=int, default=256)
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    p.add_argument("--steps", type=int, default=100, help="steps per round and way")
    p.add_argument("--rounds", type=int, default=7)
    args = p.parse_args()

    for threads in args.threads:
        env = groundsim.make_vec(args.task, args.envs, threads)
        layout = env.layout
        rng = np.random.default_rng(0)
        acts = [rng.uniform(env.single_action_space.low, env.single_action_space.high,
                            (args.envs, layout.action_size)).astype(np.float32) for _ in range(16)]
        core = env._core
        bufs = (env._obs, env._rewards, env._terminations, env._truncations)
        env.reset(seed=0)
        for a in acts:  # warm-up: threads started, caches filled
            env.step(a)

        def wrapper():
            for k in range(args.steps):
                env.step(acts[k % 16])

        def core_only():
            for k in range(args.steps):
                core.step(acts[k % 16], *bufs)

        times = {"wrapper": [], "core": []}
        for _ in range(args.rounds):
            for name, fn in (("wrapper", wrapper), ("core", core_only)):
                t0 = time.perf_counter()
                fn()
                times[name].append((time.perf_counter() - t0) / args.steps)
        w, c = statistics.median(times["wrapper"]), statistics.median(times["core"])
        physics = layout.control_period
        print(f"{args.envs} envs, {threads} thread(s), control period {physics}: "
              f"wrapper {args.envs / w:,.0f} env-steps/s ({args.envs * physics / w:,.0f} physics steps/s), "
              f"core {args.envs / c:,.0f} env-steps/s; per step {w * 1e6:.0f} us, of which Python "
              f"{(w - c) * 1e6:.1f} us = {100 * (w - c) / w:.1f}%")
        env.close()


if __name__ == "__main__":
    main()
