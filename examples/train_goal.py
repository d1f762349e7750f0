#!/usr/bin/env python3
"""Learns to drive the sedan to the goal of configs/tasks/goal.json with the
cross-entropy method on a linear policy, in numpy alone, and plots the
learning curve (matplotlib, Agg) into a PNG.

    PYTHONPATH=build/python python3 examples/train_goal.py [--threads 2] [--out out/train_goal.png]

The policy is a = W (obs - mean) / std + b, clipped to the action space by
the environment (throttle, brake in [0, 1], steer in [-1, 1]); mean and std
are those of every observation seen so far.
Each generation evaluates `population` candidates on `episodes` starts each
(the same starts for every candidate), keeps the best `elite` and refits a
diagonal Gaussian over the parameters; the distribution's mean is evaluated
on held-out starts in the same batch, and an episode counts as a success when
it ends within the task's goal radius. All of it runs as one vector env."""

import argparse
import json
import pathlib
import sys
import time

import numpy as np

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--task", default=str(ROOT / "configs" / "tasks" / "goal.json"))
    p.add_argument("--generations", type=int, default=40, help="at most this many")
    p.add_argument("--population", type=int, default=32)
    p.add_argument("--elite", type=int, default=6)
    p.add_argument("--episodes", type=int, default=3, help="starts per candidate")
    p.add_argument("--eval-episodes", type=int, default=32, help="held-out starts for the mean policy")
    p.add_argument("--hidden", type=int, default=0, help="tanh units of a hidden layer; 0: a linear policy")
    p.add_argument("--sigma", type=float, default=0.3, help="initial spread of the parameters")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--target", type=float, default=0.9,
                   help="stop once the mean policy reaches this success rate twice in a row")
    p.add_argument("--out", default="out/train_goal.png")
    p.add_argument("--results", default=None, help="JSON of the learning curve (default: next to --out)")
    return p.parse_args()


class Policy:
    """Linear (hidden = 0), or one tanh layer of `hidden` units; its
    parameters are one flat vector per env."""

    def __init__(self, obs_size, act_size, hidden):
        sizes = [obs_size, hidden, act_size] if hidden else [obs_size, act_size]
        self.shapes = list(zip(sizes[:-1], sizes[1:]))
        self.size = sum(i * o + o for i, o in self.shapes)

    def layers(self, params):
        out, at = [], 0
        for i, o in self.shapes:
            W = params[:, at: at + i * o].reshape(-1, i, o)
            b = params[:, at + i * o: at + i * o + o]
            out.append((W, b))
            at += i * o + o
        return out

    def act(self, layers, x):
        for k, (W, b) in enumerate(layers):
            x = np.einsum("ni,nij->nj", x, W) + b
            if k + 1 < len(layers):
                x = np.tanh(x)
        return x


class Rollouts:
    """One vector env: population x episodes candidate envs, then the
    held-out envs of the mean policy; one episode each per generation."""

    def __init__(self, args):
        self.args = args
        self.n_cand = args.population * args.episodes
        self.n = self.n_cand + args.eval_episodes
        self.env = groundsim.make_vec(args.task, self.n, args.threads)
        layout = self.env.layout
        self.obs_size, self.act_size = layout.obs_size, layout.action_size
        self.goal_distance = layout.observation.index("goal_distance")
        task = json.loads(pathlib.Path(args.task).read_text())["task"]
        self.goal_radius = task["termination"]["goal_radius"]
        self.max_steps = int(round(layout.time_limit / (layout.dt * layout.control_period))) + 1
        self.obs_count, self.obs_mean, self.obs_var = 0, np.zeros(self.obs_size), np.ones(self.obs_size)
        self.obs_std = np.ones(self.obs_size)

    def update_normalisation(self, seen):
        """Running mean and std of every observation seen so far (as in
        Mania et al. 2018, ARS V2): the policy's inputs stay of order 1 over
        the states it actually visits, which a first random rollout does not
        cover (the car barely moves)."""
        seen = np.concatenate(seen)
        n0, n1 = self.obs_count, len(seen)
        mean1, var1 = seen.mean(axis=0), seen.var(axis=0)
        mean = (n0 * self.obs_mean + n1 * mean1) / (n0 + n1)
        m2 = n0 * self.obs_var + n1 * var1 + n0 * n1 / (n0 + n1) * (self.obs_mean - mean1) ** 2
        self.obs_count, self.obs_mean, self.obs_var = n0 + n1, mean, m2 / (n0 + n1)
        self.obs_std = np.maximum(np.sqrt(self.obs_var), 1e-2)

    def run(self, params, generation):
        """params: (n, obs_size * act_size + act_size), one row per env.
        Returns each env's episode return and whether it reached the goal."""
        policy = Policy(self.obs_size, self.act_size, self.args.hidden)
        layers = policy.layers(params)
        starts = 1000 * generation
        # every candidate sees the same starts; the held-out starts never change
        seeds = [starts + j for _ in range(self.args.population) for j in range(self.args.episodes)]
        seeds += [2**40 + j for j in range(self.args.eval_episodes)]
        obs, _ = self.env.reset(seed=seeds)
        returns = np.zeros(self.n)
        reached = np.zeros(self.n, bool)
        running = np.ones(self.n, bool)
        seen = []
        for k in range(self.max_steps):
            if k % 5 == 0:
                seen.append(obs[running].copy())
            x = (obs - self.obs_mean) / self.obs_std
            actions = policy.act(layers, x)
            obs, rewards, terminated, truncated, _ = self.env.step(actions)
            returns += np.where(running, rewards, 0.0)
            ended = running & (terminated | truncated)
            reached |= ended & terminated & (obs[:, self.goal_distance] <= self.goal_radius)
            running &= ~ended
            if not running.any():
                break
        self.update_normalisation(seen)
        return returns, reached


def plot(curve, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    g = [c["generation"] for c in curve]
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(g, [c["eval_return"] for c in curve], "o-", label="mean policy, held-out starts")
    ax.plot(g, [c["elite_return"] for c in curve], "s--", label="elite candidates")
    ax.set_xlabel("generation")
    ax.set_ylabel("episode return")
    ax2 = ax.twinx()
    ax2.plot(g, [100 * c["success"] for c in curve], "g^:", label="success (held-out)")
    ax2.set_ylabel("success rate (%)")
    ax2.set_ylim(-5, 105)
    lines = ax.get_legend_handles_labels()[0] + ax2.get_legend_handles_labels()[0]
    labels = ax.get_legend_handles_labels()[1] + ax2.get_legend_handles_labels()[1]
    ax.legend(lines, labels, loc="center right")
    ax.set_title("goal.json: cross-entropy method, linear policy")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)


def main():
    args = parse_args()
    rng = np.random.default_rng(args.seed)
    ro = Rollouts(args)
    dim = Policy(ro.obs_size, ro.act_size, args.hidden).size
    mu, sigma = np.zeros(dim), np.full(dim, args.sigma)
    curve, hits, t0 = [], 0, time.perf_counter()
    print(f"{ro.n} envs on {args.threads} threads, {dim} parameters, episodes of at most {ro.max_steps} actions")
    for gen in range(args.generations):
        cand = mu + sigma * rng.standard_normal((args.population, dim))
        params = np.concatenate([np.repeat(cand, args.episodes, axis=0), np.tile(mu, (args.eval_episodes, 1))])
        returns, reached = ro.run(params, gen)
        fitness = returns[: ro.n_cand].reshape(args.population, args.episodes).mean(axis=1)
        elite = np.argsort(fitness)[-args.elite:]
        # the refit, with extra noise that shrinks over the generations
        # (Szita and Lorincz 2006) so the search does not collapse early
        mu = cand[elite].mean(axis=0)
        sigma = cand[elite].std(axis=0) + max(0.01, 0.1 * (1 - gen / 20))
        row = {"generation": gen, "eval_return": float(returns[ro.n_cand:].mean()),
               "success": float(reached[ro.n_cand:].mean()), "elite_return": float(fitness[elite].mean()),
               "candidate_success": float(reached[: ro.n_cand].mean()), "wall_s": time.perf_counter() - t0}
        curve.append(row)
        print(f"gen {gen:2d}  mean policy: return {row['eval_return']:7.2f} success {100 * row['success']:5.1f}%  "
              f"elite return {row['elite_return']:7.2f}  candidates reaching the goal "
              f"{100 * row['candidate_success']:5.1f}%  {row['wall_s']:6.1f} s", flush=True)
        hits = hits + 1 if row["success"] >= args.target else 0
        if hits >= 2:
            break
    out = pathlib.Path(args.out)
    plot(curve, out)
    results = pathlib.Path(args.results) if args.results else out.with_suffix(".json")
    results.write_text(json.dumps({"args": vars(args), "curve": curve, "policy": {
        "mu": mu.tolist(), "obs_mean": ro.obs_mean.tolist(), "obs_std": ro.obs_std.tolist()}}, indent=1))
    ro.env.close()
    solved = curve[-1]["success"] >= args.target
    print(f"{'solved' if solved else 'not solved'}: success {100 * curve[-1]['success']:.0f}% on "
          f"{args.eval_episodes} held-out starts after {len(curve)} generations, "
          f"{curve[-1]['wall_s']:.0f} s; curve in {out}, results in {results}")
    return 0 if solved else 1


if __name__ == "__main__":
    sys.exit(main())
