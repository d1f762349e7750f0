#!/usr/bin/env python3
"""Videos of a trained PPO policy (examples/ppo.py --save-model FILE):
the policy's mean action on held-out starts, rendered behind the car
(groundsim's rgb_array frames) into H.264 MP4 files with ffmpeg.

    PYTHONPATH=build/python /usr/bin/python3 examples/ppo_video.py --task configs/tasks/goal.json \\
        --model out/ppo/goal_seed0.pt --out docs/experiments/videos/ppo_goal --starts 2

Each start is one episode from reset seed 10^9 + i (examples/ppo.py's
held-out starts); prints each video's frames and return."""

import argparse
import importlib.util
import pathlib

import numpy as np
import torch

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]


def load_ppo():
    spec = importlib.util.spec_from_file_location("ppo", ROOT / "examples" / "ppo.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--task", required=True)
    p.add_argument("--model", required=True, help="a state dict written by ppo.py --save-model")
    p.add_argument("--out", required=True, help="path prefix of the videos (_start<i>.mp4 is appended)")
    p.add_argument("--starts", type=int, default=1)
    p.add_argument("--hidden", type=int, default=64)
    p.add_argument("--size", type=int, nargs=2, default=[320, 240])
    p.add_argument("--crf", type=int, default=30, help="x264 quality: higher is smaller")
    args = p.parse_args()

    ppo = load_ppo()
    env = groundsim.make(args.task, render_mode="rgb_array", render_size=tuple(args.size))
    task = ppo.Task(args.task, env.layout, env.action_space)
    agent = ppo.Agent(env.observation_space.shape[0], env.action_space.shape[0], args.hidden)
    agent.load_state_dict(torch.load(args.model))
    agent.eval()

    def policy(obs):
        with torch.no_grad():
            u = agent.actor_mean(agent.obs_rms(np.asarray(obs)[None, :])).numpy()[0]
        return task.env_action(u)

    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    for i in range(args.starts):
        path = out.with_name(f"{out.name}_start{i}.mp4")
        frames, ret = groundsim.record_video(env, policy, path, seed=ppo.HELDOUT_SEED + i, crf=args.crf)
        print(f"{path}: {frames} frames, return {ret:.2f}")


if __name__ == "__main__":
    main()
