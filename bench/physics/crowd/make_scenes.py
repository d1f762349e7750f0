#!/usr/bin/env python3
"""Writes the crowd benchmark's scenes (issue 33) next to this file: copies
of configs/sedan.json's car at 10 m/s on a plane for 20 s, apart, near,
spread, packed and pushing. Run it again after changing configs/sedan.json."""
import copy
import json
import os

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.abspath(os.path.join(here, "..", "..", ".."))
with open(os.path.join(root, "configs", "sedan.json")) as f:
    sedan = json.load(f)

CRUISE = 0.12  # throttle that holds the sedan near 10 m/s on the plane


def car(name, x, y, throttle=CRUISE):
    v = copy.deepcopy(sedan["vehicle"])
    v["name"] = name
    v["initial"] = {"position": [x, y, 0], "speed": 10}
    v["controls"] = [{"t": 0, "throttle": throttle}]
    return v


def scene(name, description, cars):
    return {
        "name": name,
        "description": description,
        "duration": 20,
        "output_rate": 50,
        "physics": copy.deepcopy(sedan["physics"]),
        "contact": copy.deepcopy(sedan["contact"]),
        "ground": {"type": "plane"},
        "vehicles": cars,
    }


def spread(n):  # two 10 m lanes, 15 m nose to nose
    return [car(f"car{i}", -15.0 * (i // 2), 10.0 * (i % 2)) for i in range(n)]


def pack(n):  # two abreast 2.3 m, 5.2 m nose to nose (0.5 m between bodies both ways)
    return [car(f"car{i}", -5.2 * (i // 2), 2.3 * (i % 2)) for i in range(n)]


scenes = {
    "pair_apart": scene("pair_apart", "two sedans side by side, centres 20 m apart", [car("a", 0, 0), car("b", 0, 20)]),
    "pair_near": scene("pair_near", "two sedans side by side, centres 2.2 m apart (0.4 m between bodies, never touching)",
                       [car("a", 0, 0), car("b", 0, 2.2)]),
    "spread8": scene("spread8", "8 sedans in two lanes 10 m apart, 15 m nose to nose", spread(8)),
    "pack8": scene("pack8", "8 sedans two abreast 2.3 m apart, 5.2 m nose to nose", pack(8)),
    "spread16": scene("spread16", "16 sedans in two lanes 10 m apart, 15 m nose to nose", spread(16)),
    "pack16": scene("pack16", "16 sedans two abreast 2.3 m apart, 5.2 m nose to nose", pack(16)),
    # bodies 2 cm apart at the start; the one behind at full cruise plus
    # 0.4 throttle pushes the one ahead, which coasts, for the whole run
    "push": scene("push", "one sedan pushing another, nose to tail, for 20 s",
                  [car("pusher", 0, 0, CRUISE + 0.4), car("pushed", 4.72, 0, 0.0)]),
    # the same pair pushing in a third lane beside 14 sedans spread: what
    # one touching pair costs the rest of a scene
    "spread16_push": scene("spread16_push", "14 sedans spread and a pair pushing in a third lane, for 20 s",
                           spread(14) + [car("pusher", 0, 20, CRUISE + 0.4), car("pushed", 4.72, 20, 0.0)]),
}
for name, doc in scenes.items():
    with open(os.path.join(here, name + ".json"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
