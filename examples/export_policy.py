#!/usr/bin/env python3
"""Exports a PPO agent trained by examples/ppo.py (its --save-model state
dict) as a policy file that sessions and clients load without Python
(server/drivers/policy.hpp, docs/drivers.md "Trained drivers"): the task's
observation features and track distances, its control period and step,
the running observation statistics, the actor's layers and the action
bounds.

    PYTHONPATH=build/python python3 examples/export_policy.py \\
        --task configs/tasks/circuit_drive.json --model out/circuit.pt --out configs/race/drivers/circuit.json

The weights are written with 9 significant digits (float32 round-trips);
the file is about 100 KB for the 64x64 actor.
"""
import argparse
import json
import pathlib

import torch

import groundsim


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--task", required=True, help="the task the agent was trained on")
    p.add_argument("--model", required=True, help="examples/ppo.py --save-model output")
    p.add_argument("--out", required=True)
    p.add_argument("--note", default="", help="free text kept in the file (the training command, say)")
    a = p.parse_args()
    doc = json.loads(pathlib.Path(a.task).read_text())
    task = doc["task"]
    env = groundsim.make_vec(a.task, 1, num_threads=1)
    layout = env.layout
    state = torch.load(a.model, map_location="cpu")
    layers = []
    names = sorted({k.split(".")[1] for k in state if k.startswith("actor_mean.") and k.endswith(".weight")}, key=int)
    for i, n in enumerate(names):
        w = state[f"actor_mean.{n}.weight"].double().tolist()
        b = state[f"actor_mean.{n}.bias"].double().tolist()
        layers.append({"weight": [[float(f"{x:.9g}") for x in row] for row in w], "bias": [float(f"{x:.9g}") for x in b],
                       "activation": "none" if i == len(names) - 1 else "tanh"})
    obs_size = len(layout.observation)
    if len(layers[0]["weight"][0]) != obs_size:
        raise SystemExit(f"the model observes {len(layers[0]['weight'][0])} values, the task {obs_size}")
    policy = {
        "format": "groundsim.policy",
        "version": 1,
        "task": doc.get("name", pathlib.Path(a.task).stem),
        "note": a.note,
        "scenario_hash": layout.scenario_hash,
        "observation": task["observation"],
        "observation_names": list(layout.observation),
        "track_ahead": task.get("track", {}).get("ahead", [5, 10, 20, 40]),
        "control_period": int(layout.control_period),
        "dt": float(layout.dt),
        "normalise": {"mean": state["obs_rms.mean"].tolist(), "var": state["obs_rms.var"].tolist(), "clip": 10.0},
        "layers": layers,
        "action_names": list(layout.action),
        "action_low": [float(x) for x in layout.action_low],
        "action_high": [float(x) for x in layout.action_high],
    }
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(policy, separators=(",", ":")) + "\n")
    print(f"{out}: {obs_size} observations -> {len(layers)} layers -> {len(policy['action_low'])} actions, "
          f"{out.stat().st_size} bytes")


if __name__ == "__main__":
    main()
