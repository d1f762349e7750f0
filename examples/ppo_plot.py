#!/usr/bin/env python3
"""Gathers the per-seed runs of examples/ppo.py into one JSON and one PNG:
return and success against environment steps and against wall time, the
mean over seeds and the band between the lowest and highest seed.

    /usr/bin/python3 examples/ppo_plot.py docs/experiments/runs/ppo_goal_seed*.json --out docs/experiments/ppo_goal

writes ppo_goal.json (`seeds`: one entry per run with its held-out success,
env steps and wall time; the command, budget, hardware) and ppo_goal.png.
Each seed's curve is interpolated (in env steps, or in wall time onto a
common grid) between the points where it has a value, e.g. the training
return of iterations in which episodes ended; the mean and band are drawn
where every seed has a value; a seed that has finished holds its last value."""

import argparse
import json
import pathlib

import numpy as np


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("runs", nargs="+", help="per-seed JSONs written by examples/ppo.py")
    p.add_argument("--out", required=True, help="output path without extension (.json and .png are added)")
    p.add_argument("--target", type=float, default=0.9, help="held-out success rate a seed must reach")
    p.add_argument("--note", default=None, help="a sentence on the conditions of the runs")
    return p.parse_args(argv)


def interpolated(runs, key, xkey, grid):
    """Each run's points that have key, interpolated in xkey onto grid (NaN
    before a run's first point; a finished run holds its last value)."""
    ys = []
    for run in runs:
        pts = [(r[xkey], r[key]) for r in run["curve"] if r.get(key) is not None]
        x, y = np.array([p[0] for p in pts], float), np.array([p[1] for p in pts], float)
        ys.append(np.interp(grid, x, y, left=np.nan, right=y[-1]))
    return grid, np.stack(ys)


def series(runs, key):
    """Against environment steps: every run has the same iterations."""
    grid = np.array([r["env_steps"] for r in runs[0]["curve"]], float)
    return interpolated(runs, key, "env_steps", grid)


def wall_series(runs, key, points=300):
    """Against wall time, on a common grid."""
    grid = np.geomspace(min(run["curve"][0]["wall_s"] for run in runs),
                        max(run["curve"][-1]["wall_s"] for run in runs), points)
    return interpolated(runs, key, "wall_s", grid)


def band(ax, x, ys, label, colour, scale=1.0):
    """The mean over runs and the band between the lowest and the highest,
    where every run has a value."""
    mean, lo, hi = ys.mean(0), ys.min(0), ys.max(0)
    ax.plot(x, scale * mean, color=colour, label=label)
    ax.fill_between(x, scale * lo, scale * hi, color=colour, alpha=0.2)


def plot(runs, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    for col, (xlabel, getter) in enumerate([("environment steps", series), ("wall time (s)", wall_series)]):
        ax_r, ax_s = axes[0, col], axes[1, col]
        x, y = getter(runs, "return")
        band(ax_r, x, y, "training episodes (sampled actions)", "tab:blue")
        x, y = getter(runs, "heldout_return")
        band(ax_r, x, y, "64 held-out starts (mean action)", "tab:orange")
        x, y = getter(runs, "success")
        band(ax_s, x, y, "training episodes (sampled actions)", "tab:blue", 100)
        x, y = getter(runs, "heldout_success")
        band(ax_s, x, y, "64 held-out starts (mean action)", "tab:orange", 100)
        ax_s.axhline(90, color="grey", ls=":", lw=1)
        ax_r.set_ylabel("episode return")
        ax_s.set_ylabel("success (%)")
        ax_s.set_ylim(-3, 103)
        for ax in (ax_r, ax_s):
            ax.set_xscale("log")  # the learning happens early; the rest shows that it lasts
            ax.set_xlabel(xlabel + " (log scale)")
            ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="lower right", fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main(argv=None):
    args = parse_args(argv)
    runs = [json.loads(pathlib.Path(p).read_text()) for p in args.runs]
    runs.sort(key=lambda r: r["seed"])
    first = runs[0]
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    seeds = [{"seed": r["seed"], "heldout_success": r["heldout_success"], "heldout_return": r["heldout"]["return"],
              "reached_target": r["heldout_success"] >= args.target,
              "env_steps_to_90pct_heldout": r["env_steps_to_90pct_heldout"],
              "env_steps": r["env_steps"], "wall_s": round(r["wall_s"], 1), "train_s": round(r["train_s"], 1),
              "sps": round(r["sps"]), "command": r["command"], "run": pathlib.Path(p).name}
             for r, p in zip(runs, sorted(args.runs, key=lambda p: json.loads(pathlib.Path(p).read_text())["seed"]))]
    reached = sum(s["reached_target"] for s in seeds)
    hp = {k: v for k, v in first["args"].items() if k not in ("seed", "out_dir", "name", "quiet", "save_model")}
    summary = {
        "algorithm": "PPO (examples/ppo.py, after CleanRL ppo_continuous_action)",
        "task": first["task"], "task_file": first["task_file"],
        "budget_env_steps": first["env_steps"],
        "success_definition": first["success_definition"], "success_return": first["success_return"],
        "heldout": {k: first["heldout"][k] for k in ("episodes", "reset_seeds", "policy")},
        "target": f"held-out success >= {args.target:g} for at least 4 of {len(seeds)} seeds",
        "seeds_reaching_target": reached,
        "target_met": reached >= min(4, len(seeds)),
        "heldout_success_mean": float(np.mean([s["heldout_success"] for s in seeds])),
        "wall_s_max": max(s["wall_s"] for s in seeds),
        "hyperparameters": hp,
        "hardware": first["hardware"],
        "note": args.note,
        "seeds": seeds,
    }
    out.with_suffix(".json").write_text(json.dumps(summary, indent=1))
    title = (f"PPO on {first['task_file']}: {len(seeds)} seeds, mean and min-max band; "
             f"{reached}/{len(seeds)} reach {100 * args.target:.0f}% held-out")
    plot(runs, out.with_suffix(".png"), title)
    for s in seeds:
        print(f"seed {s['seed']}: held-out success {100 * s['heldout_success']:5.1f}%  return "
              f"{s['heldout_return']:8.2f}  {s['env_steps']} env steps  {s['wall_s']:.0f} s  {s['sps']} steps/s")
    print(f"{reached}/{len(seeds)} seeds reach {100 * args.target:.0f}%; {out.with_suffix('.json')}, "
          f"{out.with_suffix('.png')}")
    return summary


if __name__ == "__main__":
    main()
