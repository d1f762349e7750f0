#!/usr/bin/env python3
"""Throughput through Python, and Python's share of a batched step.

    PYTHONPATH=build/python python3 bench/python_step_bench.py [--envs 256] [--threads 1 2] [--copy 1 0]
    ... --task configs/tasks/race.json    # two agents per env: agent-steps/s too

For each thread count, steps of the fast-preset car task (8 physics steps
per action) taken through VecEnv.step (Gymnasium's API), with the time
inside the C++ step measured within the same calls: Python's share is
(time of VecEnv.step - time inside the C++ step) / time of VecEnv.step,
so a change of machine load during the run does not bias it; Python's CPU
time (time.thread_time outside the C++ step) does not grow with the load. What counts
as Python: the wrapper (action check, the infos, the returned views and
dict), the binding's buffer checks, and the timing probe itself (so the
share is overstated a little), and with --copy 1 (the default env) the
copies of the returned arrays, which --copy 0 (views) leaves out. The C++
figure without Python is bench/experiments_bench (docs/experiments.md)."""

import argparse
import os
import pathlib
import statistics
import time

import numpy as np

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


class TimedCore:
    """The env's groundsim._core.BatchEnv with its step() timed."""

    def __init__(self, core):
        self.core, self.inside, self.inside_cpu = core, 0.0, 0.0

    def step(self, *args):
        t0, c0 = time.perf_counter(), time.thread_time()
        self.core.step(*args)
        self.inside += time.perf_counter() - t0
        self.inside_cpu += time.thread_time() - c0

    def __getattr__(self, name):
        return getattr(self.core, name)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--task", default=str(ROOT / "configs" / "tasks" / "fast_car.json"))
    p.add_argument("--envs", type=int, default=256)
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    p.add_argument("--steps", type=int, default=100, help="steps per round")
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--copy", type=int, nargs="+", default=[1, 0], help="1: fresh arrays (default env), 0: views")
    args = p.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")

    for threads, copy in [(t, c) for t in args.threads for c in args.copy]:
        env = groundsim.make_vec(args.task, args.envs, threads, copy=bool(copy))
        layout = env.layout
        rng = np.random.default_rng(0)
        acts = [rng.uniform(env.single_action_space.low, env.single_action_space.high,
                            (env.num_envs, layout.action_size)).astype(np.float32) for _ in range(16)]
        env.reset(seed=0)
        for a in acts:  # warm-up: threads started, caches filled
            env.step(a)
        timed = env._core = TimedCore(env._core)
        totals, shares, python_cpu = [], [], []
        for _ in range(args.rounds):
            timed.inside = timed.inside_cpu = 0.0
            t0, c0 = time.perf_counter(), time.thread_time()
            for k in range(args.steps):
                env.step(acts[k % 16])
            total, cpu = time.perf_counter() - t0, time.thread_time() - c0
            totals.append(total / args.steps)
            shares.append((total - timed.inside) / total)
            python_cpu.append((cpu - timed.inside_cpu) / args.steps)
        step, share = statistics.median(totals), statistics.median(shares)
        agents = f" x {env.num_agents} agents ({env.num_envs / step:,.0f} agent-steps/s)" if env.num_agents > 1 else ""
        print(f"{args.envs} envs{agents}, {threads} thread(s), copy={bool(copy)}, control period {layout.control_period}: "
              f"{args.envs / step:,.0f} env-steps/s ({args.envs * layout.control_period / step:,.0f} physics "
              f"steps/s) through VecEnv.step; {step * 1e6:.0f} us per step, Python {share * step * 1e6:.1f} us "
              f"= {100 * share:.2f}%, Python's CPU time {statistics.median(python_cpu) * 1e6:.1f} us "
              f"(median of {args.rounds} rounds of {args.steps}; shares "
              f"{100 * min(shares):.2f}-{100 * max(shares):.2f}%)")
        env.close()


if __name__ == "__main__":
    main()
