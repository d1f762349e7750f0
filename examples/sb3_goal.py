#!/usr/bin/env python3
"""Stable-Baselines3's PPO, as a researcher would use it, on a groundsim task
(default configs/tasks/goal.json), judged on held-out starts.

    PYTHONPATH=build/python ~/.cache/groundsim/venv/bin/python examples/sb3_goal.py --seed 0 \\
        --total-timesteps 1000000 --out docs/experiments/sb3/goal_seed0.json

Training: groundsim.sb3.make_sb3_vec (one C++ batch, SB3's VecEnv contract)
under SB3's VecNormalize (observations and rewards), PPO("MlpPolicy") with
the hyperparameters below, CPU, one torch thread. Every --eval-every steps
and at the end, the policy's deterministic action drives 64 held-out starts
(reset seeds 10^9 + i, never used in training), one episode each; success:
the episode terminated within the task's goal_radius of the goal (the final
goal_distance observation), as examples/ppo.py counts it."""

import argparse
import json
import pathlib
import time

import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.vec_env import VecNormalize

import groundsim
from groundsim.sb3 import make_sb3_vec

HELDOUT_SEED = 10**9


def evaluate(model, normalizer, task_path, episodes=64):
    env = groundsim.make_vec(task_path, episodes, 1)  # next_step: an ended env restarts, its rows are masked
    layout = env.layout
    doc = json.loads(pathlib.Path(task_path).read_text())
    radius = float(doc["task"]["termination"]["goal_radius"])
    distance = list(layout.observation).index("goal_distance")
    obs, _ = env.reset(seed=HELDOUT_SEED)
    returns = np.zeros(episodes)
    success = np.zeros(episodes, bool)
    running = np.ones(episodes, bool)
    limit = int(np.ceil(doc["task"]["time_limit"] / (layout.dt * layout.control_period))) + 1
    for _ in range(limit):
        action, _ = model.predict(normalizer.normalize_obs(obs), deterministic=True)
        obs, rew, term, trunc, _ = env.step(action.astype(np.float32))
        returns += np.where(running, rew, 0.0)
        ended = running & (term | trunc)
        success |= ended & term & (obs[:, distance] <= radius)
        running &= ~ended
        if not running.any():
            break
    env.close()
    return float(returns.mean()), float(success.mean())


class Evaluations(BaseCallback):
    def __init__(self, every, task_path, curve):
        super().__init__()
        self.every, self.task_path, self.curve, self.next = every, task_path, curve, every
        self.start = time.time()

    def _on_step(self):
        if self.num_timesteps >= self.next:
            self.next += self.every
            ret, succ = evaluate(self.model, self.training_env, self.task_path)
            self.curve.append({"env_steps": self.num_timesteps, "wall_s": round(time.time() - self.start, 1),
                               "heldout_return": ret, "heldout_success": succ})
            print(f"steps {self.num_timesteps}: held-out return {ret:.2f}, success {succ:.0%}", flush=True)
        return True


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--task", default=str(pathlib.Path(__file__).resolve().parents[1] / "configs/tasks/goal.json"))
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--total-timesteps", type=int, default=1_000_000)
    p.add_argument("--num-envs", type=int, default=32)
    p.add_argument("--eval-every", type=int, default=100_000)
    p.add_argument("--out", default=None)
    a = p.parse_args()
    torch.set_num_threads(1)
    venv = VecNormalize(make_sb3_vec(a.task, a.num_envs, 1), gamma=0.99)
    hyper = dict(n_steps=256, batch_size=1024, n_epochs=10, learning_rate=3e-4, gamma=0.99, gae_lambda=0.95,
                 clip_range=0.2, ent_coef=0.0)
    model = PPO("MlpPolicy", venv, seed=a.seed, device="cpu", verbose=0, **hyper)
    curve = []
    start = time.time()
    model.learn(total_timesteps=a.total_timesteps, callback=Evaluations(a.eval_every, a.task, curve))
    wall = time.time() - start
    venv.training = False
    ret, succ = evaluate(model, venv, a.task)
    print(f"final: held-out return {ret:.2f}, success {succ:.0%}, {model.num_timesteps} steps in {wall:.0f} s")
    if a.out:
        import stable_baselines3
        out = {"task": pathlib.Path(a.task).name, "seed": a.seed, "env_steps": model.num_timesteps,
               "wall_s": round(wall, 1), "heldout_return": ret, "heldout_success": succ, "curve": curve,
               "hyperparameters": hyper, "num_envs": a.num_envs, "stable_baselines3": stable_baselines3.__version__,
               "torch": torch.__version__, "gymnasium": __import__("gymnasium").__version__}
        pathlib.Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        pathlib.Path(a.out).write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
