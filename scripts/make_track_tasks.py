#!/usr/bin/env python3
"""Writes the track-following tasks (docs/drivers.md, docs/scenario.md "Tasks")
from the shipped races, so that a task drives the very track, walls and
surfaces a race session runs:

    scripts/make_track_tasks.py [--out configs/tasks]

configs/tasks/circuit_drive.json   one sedan on configs/race/circuit.json,
                                   started anywhere along the track
configs/tasks/rally_drive.json     one sedan on configs/race/rally_stage.json,
                                   started anywhere along the stage
configs/tasks/circuit_pack.json    four sedans from the circuit's grid, one
                                   agent each, seeing each other

The circuit's tasks take half its narrowest gate less 1 m as the track's
half width (its asphalt, 6 m; the race's own is 9), so that a driver
trained on them passes between every gate's posts. The rally stage's
task keeps the race's 14 m (its trained driver, configs/race/drivers/
rally.policy, was trained on that and keeps within 5.3 m of the line,
inside its gates' 6 m, from every held-out start: docs/drivers.md).

The observation is what a trained driver can sense in a session too
(server/drivers/policy_driver.hpp): the body's motion, the track ahead in
the body frame, its curvature, the pose against the line, the next gate,
the previous action. The reward pays for metres gained along the track
and laps, and charges leaving the track and hits.
"""
import argparse
import copy
import json
import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

OBSERVATION = ["velocity_body", "angular_velocity_body", "up_body", "track_pose", "track_ahead",
               "track_curvature", "next_gate", "previous_action"]
AHEAD = [5, 10, 20, 30, 45, 60]


def task_of(race, name, description, time_limit, agents=None, laps=0, gate_width=True, off_track=0.05):
    doc = copy.deepcopy(race)
    doc["name"] = name
    doc["description"] = description
    for key in ("duration", "output_rate"):
        doc.pop(key, None)
    # the task's track is what a race counts: between the gates' posts. Its
    # half width (off_track) is half the narrowest gate less 1 m, not the
    # race's looser off-track limit, so a driver trained here passes every
    # gate (a car outside a gate's posts has not passed it)
    gates = doc["race"]["gates"]
    widths = [g["width"] if "width" in g else
              ((g["left"][0] - g["right"][0]) ** 2 + (g["left"][1] - g["right"][1]) ** 2) ** 0.5 for g in gates]
    if gate_width:
        doc["race"]["track"]["half_width"] = round(min(widths) / 2 - 1.0, 3)
    # the files the race names sit next to it in configs/race
    ground = doc["ground"]
    if "file" in ground and not ground["file"].startswith(".."):
        ground["file"] = "../race/" + ground["file"]
    task = {
        "observation": OBSERVATION + (["agents_body"] if agents else []),
        "track": {"ahead": AHEAD},
        "action": {"type": "car_controls"},
        "control_period": 10,
        "time_limit": time_limit,
        # leaving the track costs about what 12 m/s of progress earns (the
        # circuit's): the termination 2 m beyond its edge is what keeps a
        # driver on it. The rally stage's task (trained first) charges 0.5
        "reward": {"track_progress": 0.1, "lap": 5.0, "off_track": off_track, "collision": 0.05, "effort": 0.01},
        "termination": {"off_track": 2.0, "max_tilt_deg": 45, "laps": laps},
    }
    if agents:
        task["agents"] = agents
        task["randomize"] = {"x": [-0.3, 0.3], "y": [-0.3, 0.3], "yaw_deg": [-2, 2]}
    else:
        task["vehicle"] = doc["vehicles"][0]["name"]
        length = 2000.0
        task["randomize"] = {"track_s": [0, length], "x": [-1, 1], "y": [-3, 3], "yaw_deg": [-10, 10],
                             "speed": [0, 15]}
    doc["task"] = task
    return doc


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=os.path.join(ROOT, "configs", "tasks"))
    a = p.parse_args()
    with open(os.path.join(ROOT, "configs", "race", "circuit.json")) as f:
        circuit = json.load(f)
    with open(os.path.join(ROOT, "configs", "race", "rally_stage.json")) as f:
        rally = json.load(f)
    docs = {}
    one = task_of(circuit, "circuit_drive",
                  "Drive configs/race/circuit.json's oval fast and clean: one sedan started anywhere along the "
                  "track (drawn distance, offsets, heading and speed), rewarded per metre gained along the line "
                  "and per lap, charged for every action off the track and for hits; the episode ends 2 m beyond "
                  "the track's edge, on tipping over, or after 40 s", 40.0)
    one["task"]["randomize"]["track_s"] = [0, 560]
    docs["circuit_drive.json"] = one
    stage = task_of(rally, "rally_drive",
                    "Drive configs/race/rally_stage.json's stage over asphalt, wet, grass, snow and ice: one sedan "
                    "started anywhere along the first 1300 m, rewarded per metre gained and for the finish, charged "
                    "for leaving the road and for hits (cones); the episode ends at the finish, 2 m beyond the "
                    "road's edge, on tipping over, or after 60 s", 60.0, laps=1, gate_width=False,
                    off_track=0.5)
    stage["task"]["randomize"]["track_s"] = [0, 1300]
    docs["rally_drive.json"] = stage
    pack = copy.deepcopy(circuit)
    names = ["red", "blue", "green", "yellow"]
    grid = pack["race"]["grid"]
    pack["vehicles"] = [{"name": n, "kind": "road_car",
                         "initial": {"position": [grid[k]["position"][0], grid[k]["position"][1], 0],
                                     "yaw_deg": grid[k]["heading_deg"]}} for k, n in enumerate(names)]
    docs["circuit_pack.json"] = task_of(
        pack, "circuit_pack",
        "Four sedans from configs/race/circuit.json's grid, one agent each: the circuit_drive task in a pack, "
        "each seeing the others (agents_body) and charged for hits; 40 s", 40.0, agents=names)
    for name, doc in docs.items():
        with open(os.path.join(a.out, name), "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
