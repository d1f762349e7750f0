#!/usr/bin/env python3
"""The cost of rendering one environment of a batch every step.

    PYTHONPATH=build/python python3 bench/python_render_bench.py [--task ...] [--envs 256] [--size 160 120]

Steps num_envs environments (one thread) with and without render([0])
after each step, and prints both step times and the rendering's share.
The issue's target: rendering one of 256 environments every step costs at
most 10% of the step."""

import argparse
import os
import pathlib
import statistics
import time

import numpy as np

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--task", nargs="+", default=[str(ROOT / "configs" / "tasks" / t) for t in
                                                 ("fast_car.json", "goal.json", "speed.json")])
    p.add_argument("--envs", type=int, default=256)
    p.add_argument("--size", type=int, nargs=2, default=[128, 96])
    p.add_argument("--steps", type=int, default=50)
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    for task in args.task:
        env = groundsim.make_vec(task, args.envs, 1, render_mode="rgb_array", render_size=tuple(args.size))
        rng = np.random.default_rng(0)
        acts = rng.uniform(env.single_action_space.low, env.single_action_space.high,
                           (16, env.num_envs, env.layout.action_size)).astype(np.float32)
        env.reset(seed=0)
        plain, rendered, frame = [], [], []
        for _ in range(args.rounds):
            t0 = time.perf_counter()
            for k in range(args.steps):
                env.step(acts[k % 16])
            plain.append((time.perf_counter() - t0) / args.steps)
            t0, spent = time.perf_counter(), 0.0
            for k in range(args.steps):
                env.step(acts[k % 16])
                t1 = time.perf_counter()
                env.render([0])
                spent += time.perf_counter() - t1
            rendered.append((time.perf_counter() - t0) / args.steps)
            frame.append(spent / args.steps)
        step, f = statistics.median(plain), statistics.median(frame)
        print(f"{pathlib.Path(task).name}: {args.envs} envs, step {step * 1e3:.2f} ms; one {args.size[0]}x"
              f"{args.size[1]} frame {f * 1e6:.0f} us = {100 * f / step:.1f}% of the step "
              f"(step + frame {statistics.median(rendered) * 1e3:.2f} ms; median of {args.rounds} rounds of "
              f"{args.steps})")


if __name__ == "__main__":
    main()
