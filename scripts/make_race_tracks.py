#!/usr/bin/env python3
"""Writes the race tracks: configs/race/circuit.json (+ circuit.png) and configs/race/rally_stage.json.

    scripts/make_race_tracks.py [--out configs/race]

circuit: an oval of two 120 m straights joined by half circles of 30 m
(centre line radius), 12 m wide, run counter-clockwise, asphalt (friction
patches) up to the walls and grass around and inside, on a 16-bit PNG
heightfield of 257 x 257 samples of 2 m (512 m square, centred on the
origin): flat (z = 0) within 14 m of the centre line and over the infield,
rising as rolling hills to 18 m beyond. Concrete walls (1 m high) line the
outside of the straights and the corners and the inside of the straights;
red and white kerbs (0.15 m) the inside of each corner. 10 gates, 3 laps,
a grid of 8 slots behind the line.

rally_stage: a point-to-point stage along the valley road of
configs/terrain/valley_road.png (2 km, the floor along y = 0) over friction
patches: asphalt, wet, grass, snow, a patch of ice and asphalt again to the
finish at x = 1450 m; 12 gates, cones at the gates' posts.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_terrain import write_png  # noqa: E402

STRAIGHT = 60.0   # half length of a straight (m)
RADIUS = 30.0     # centre line radius of the corners (m)
HALF_WIDTH = 6.0  # the track's half width (m)
WALL_GAP = 3.0    # walls this far outside the track's edge (m)
CELLS, CELL = 257, 2.0
HILLS = 18.0      # m


def sedan(name, x, y, yaw):
    return {"name": name, "kind": "road_car", "initial": {"position": [x, y, 0], "yaw_deg": yaw}}


def oval_point(s):
    """Centre line at arc length s (counter-clockwise from (0, -RADIUS)) and heading (deg)."""
    L = 2 * STRAIGHT
    arc = math.pi * RADIUS
    s %= 2 * L + 2 * arc
    if s < STRAIGHT:
        return (s, -RADIUS), 0.0
    s -= STRAIGHT
    if s < arc:
        a = -math.pi / 2 + s / RADIUS
        return (STRAIGHT + RADIUS * math.cos(a), RADIUS * math.sin(a)), math.degrees(a + math.pi / 2)
    s -= arc
    if s < L:
        return (STRAIGHT - s, RADIUS), 180.0
    s -= L
    if s < arc:
        a = math.pi / 2 + s / RADIUS
        return (-STRAIGHT + RADIUS * math.cos(a), RADIUS * math.sin(a)), math.degrees(a + math.pi / 2)
    s -= arc
    return (-STRAIGHT + s, -RADIUS), 0.0


def oval_length():
    return 4 * STRAIGHT + 2 * math.pi * RADIUS


def oval_distance(x, y):
    """Distance from the centre line."""
    cx = max(-STRAIGHT, min(STRAIGHT, x))
    return abs(math.hypot(x - cx, y) - RADIUS)


def circuit_heights():
    rows = []
    half = (CELLS - 1) / 2
    for j in range(CELLS):
        y = (j - half) * CELL
        row = []
        for i in range(CELLS):
            x = (i - half) * CELL
            d = oval_distance(x, y)
            inside = abs(y) < RADIUS and abs(x) < STRAIGHT + RADIUS and math.hypot(max(0.0, abs(x) - STRAIGHT), y) < RADIUS
            if inside or d < HALF_WIDTH + WALL_GAP + 5.0:
                h = 0.0
            else:
                u = min(1.0, (d - HALF_WIDTH - WALL_GAP - 5.0) / 40.0)
                ramp = u * u * (3 - 2 * u)
                wave = 0.6 + 0.4 * math.sin(x / 37.0) * math.cos(y / 29.0)
                h = HILLS * ramp * wave
            row.append(h / HILLS)
        rows.append(row)
    return rows


def box(name, x, y, yaw, length, thick, height, friction=0.6):
    return {"name": name, "shape": "box", "size": [round(length, 3), thick, height], "position": [round(x, 3), round(y, 3), 0],
            "yaw_deg": round(yaw, 3), "friction": friction, "rounding": 0.05}


def circuit():
    objects = []
    out_off = HALF_WIDTH + WALL_GAP  # walls this far from the centre line
    # straights: outer and inner walls
    for side, sy in (("s", -1), ("n", 1)):
        objects.append(box("wall_out_" + side, 0.0, sy * (RADIUS + out_off), 0.0, 2 * STRAIGHT, 0.5, 1.0))
        objects.append(box("wall_in_" + side, 0.0, sy * (RADIUS - out_off), 0.0, 2 * STRAIGHT - 4.0, 0.5, 1.0))
    # corners: the outer wall as 12 chords each, kerbs on the inside
    for end, cx in (("e", STRAIGHT), ("w", -STRAIGHT)):
        base = -math.pi / 2 if cx > 0 else math.pi / 2
        n = 12
        r = RADIUS + out_off
        for k in range(n):
            a0, a1 = base + math.pi * k / n, base + math.pi * (k + 1) / n
            am = 0.5 * (a0 + a1)
            chord = 2 * r * math.sin(math.pi / n / 2) + 0.6
            objects.append(box("wall_%s%d" % (end, k), cx + r * math.cos(am) * math.cos(math.pi / n / 2),
                               r * math.sin(am) * math.cos(math.pi / n / 2), math.degrees(am + math.pi / 2), chord, 0.5, 1.0))
        rk = RADIUS - HALF_WIDTH - 0.4
        for k in range(1, 6):
            am = base + math.pi * k / 6
            objects.append(box("kerb_%s%d" % (end, k), cx + rk * math.cos(am), rk * math.sin(am),
                               math.degrees(am + math.pi / 2), 3.0, 0.8, 0.15, friction=0.8))
    gates = []
    n_gates = 10
    for g in range(n_gates):
        (x, y), h = oval_point(g * oval_length() / n_gates)
        gates.append({"center": [round(x, 3), round(y, 3)], "width": 2 * HALF_WIDTH + 2.0, "heading_deg": round(h, 3)})
    grid = []
    for k in range(8):
        grid.append({"position": [-8.0 - 6.0 * (k // 2), -RADIUS + (2.5 if k % 2 == 0 else -2.5)], "heading_deg": 0})
    centerline = []
    n_line = 64
    for k in range(n_line):
        (x, y), _ = oval_point(k * oval_length() / n_line)
        centerline.append([round(x, 3), round(y, 3)])
    return {
        "name": "circuit",
        "description": "Race: 3 laps of an oval circuit (two 120 m straights, 30 m corners, 12 m wide) of asphalt "
                       "walled in concrete with kerbs on the corners, grass around, in rolling hills (a 512 m "
                       "heightfield); 10 gates, "
                       "a countdown, a grid for 8. Made by scripts/make_race_tracks.py",
        "duration": 600,
        "output_rate": 50,
        "physics": {"integrator": "semi_implicit_euler", "dt": 0.004},
        # grass off the track, asphalt on it (up to the walls), the infield grass again: the last patch wins
        "contact": {"friction": 0.45},
        "ground": {"type": "heightfield", "file": "circuit.png", "cell_size": CELL,
                   "origin": [-(CELLS - 1) / 2 * CELL, -(CELLS - 1) / 2 * CELL], "height_scale": HILLS,
                   "friction_patches": [
                       {"name": "track_s", "region": [-STRAIGHT, -RADIUS - out_off, STRAIGHT, -RADIUS + out_off], "surface": "asphalt"},
                       {"name": "track_n", "region": [-STRAIGHT, RADIUS - out_off, STRAIGHT, RADIUS + out_off], "surface": "asphalt"},
                       {"name": "track_e", "circle": [STRAIGHT, 0, RADIUS + out_off], "surface": "asphalt"},
                       {"name": "track_w", "circle": [-STRAIGHT, 0, RADIUS + out_off], "surface": "asphalt"},
                       {"name": "infield", "region": [-STRAIGHT, -RADIUS + out_off, STRAIGHT, RADIUS - out_off], "surface": "grass"},
                       {"name": "infield_e", "circle": [STRAIGHT, 0, RADIUS - out_off], "surface": "grass"},
                       {"name": "infield_w", "circle": [-STRAIGHT, 0, RADIUS - out_off], "surface": "grass"}]},
        "vehicles": [sedan("sedan", grid[0]["position"][0], grid[0]["position"][1], 0)],
        "objects": objects,
        "race": {"laps": 3, "countdown": 3, "gates": gates, "grid": grid,
                 "track": {"centerline": centerline, "half_width": HALF_WIDTH + WALL_GAP}},
    }


def rally_stage():
    # along the valley floor (y = 0), x from 40 m to 1450 m
    xs = [60, 150, 260, 380, 500, 620, 740, 860, 980, 1100, 1250, 1450]
    gates = [{"center": [x, 0.0], "width": 12.0, "heading_deg": 0} for x in xs]
    patches = [
        {"name": "asphalt", "region": [0, -64, 300, 64], "surface": "asphalt"},
        {"name": "wet", "region": [300, -64, 560, 64], "surface": "wet"},
        {"name": "grass", "region": [560, -64, 820, 64], "surface": "grass"},
        {"name": "snow", "region": [820, -64, 1050, 64], "surface": "snow"},
        {"name": "ice", "region": [1050, -64, 1130, 64], "surface": "ice"},
        {"name": "asphalt_2", "region": [1130, -64, 2048, 64], "surface": "asphalt"},
    ]
    objects = []
    for i, x in enumerate(xs):
        for side, y in (("l", 6.4), ("r", -6.4)):
            objects.append({"name": "cone_%d%s" % (i, side), "shape": "cone", "radius": 0.18, "top_radius": 0.03,
                            "height": 0.7, "friction": 0.6, "position": [x, y, 0]})
    grid = [{"position": [40.0 - 8.0 * (k // 2), 2.5 if k % 2 == 0 else -2.5], "heading_deg": 0} for k in range(8)]
    return {
        "name": "rally_stage",
        "description": "Race: a 1.4 km rally stage up and down the valley road (a 2 km heightfield) over asphalt, "
                       "wet asphalt, grass, snow and a patch of ice, then asphalt to the finish; 12 gates marked by "
                       "cones (static: a cone at a post stops a car). Made by scripts/make_race_tracks.py",
        "duration": 900,
        "output_rate": 50,
        "physics": {"integrator": "semi_implicit_euler", "dt": 0.004},
        "contact": {"friction": 1.0},
        "ground": {"type": "heightfield", "file": "../terrain/valley_road.png", "cell_size": 2.0, "origin": [0, -64],
                   "height_scale": 64.0, "friction_patches": patches},
        "vehicles": [sedan("sedan", grid[0]["position"][0], grid[0]["position"][1], 0)],
        "objects": objects,
        "race": {"laps": 1, "circuit": False, "countdown": 3, "gates": gates, "grid": grid,
                 "track": {"centerline": [[0, 0], [2040, 0]], "half_width": 14}},
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs", "race"))
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    write_png(os.path.join(a.out, "circuit.png"), CELLS, 16, circuit_heights(), CELLS)
    for name, doc in (("circuit.json", circuit()), ("rally_stage.json", rally_stage())):
        with open(os.path.join(a.out, name), "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
