#!/usr/bin/env python3
"""Writes scenes/smoke_spot.json: a smoke cloud (an analytic density: Gaussian puffs
modulated by a few octaves of smooth turbulence, written as a dense 40^3 grid) in an
index-matched box, lit by a spot from above, over a floor in front of a wall.
    python3 scenes/make_smoke_spot.py"""
import json
import math
import os

N = 40
BOUNDS = [[-1.5, -1.5, 0.0], [1.5, 1.5, 3.0]]


def density(x, y, z):  # x, y, z in [0, 1]
    def puff(cx, cy, cz, r):
        return math.exp(-((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) / (r * r))
    d = puff(0.5, 0.5, 0.45, 0.2) + 0.8 * puff(0.62, 0.42, 0.62, 0.14) + 0.6 * puff(0.36, 0.58, 0.6, 0.12)
    turbulence = 0.0
    for octave in range(3):
        f = 2.0 ** octave * 6.0
        turbulence += 0.5 ** octave * math.sin(f * x + 1.3 * octave) * math.sin(f * y + 2.1) * math.sin(f * z + 0.7 * octave)
    return max(0.0, d * (0.6 + 0.6 * turbulence) - 0.05)


values = []
for k in range(N):
    for j in range(N):
        for i in range(N):
            values.append(round(density((i + 0.5) / N, (j + 0.5) / N, (k + 0.5) / N), 4))

size = [BOUNDS[1][a] - BOUNDS[0][a] for a in range(3)]
centre = [(BOUNDS[1][a] + BOUNDS[0][a]) / 2 for a in range(3)]
scene = {
    "settings": {"width": 320, "height": 240, "samples": 64, "max_bounces": 12},
    "camera": {"type": "perspective", "focal_length": 32,
               "transform": {"look_at": {"from": [0.0, -7.0, 1.8], "to": [0.0, 0.0, 1.4]}}},
    "world": {"color": [0.02, 0.02, 0.025]},
    "materials": [
        {"name": "floor", "type": "diffuse", "color": [0.6, 0.6, 0.6]},
        {"name": "wall", "type": "diffuse", "color": [0.5, 0.5, 0.55]},
        {"name": "smoke", "type": "volume",
         "volume": {"density": 6.0, "color": [0.85, 0.85, 0.85], "anisotropy": 0.4, "method": "tracking",
                    "grid": {"resolution": [N, N, N], "values": values, "bounds": BOUNDS}}},
    ],
    "meshes": [
        {"name": "floor", "shape": {"type": "quad", "size": 12}, "materials": ["floor"]},
        {"name": "back", "shape": {"type": "quad", "size": 12}, "materials": ["wall"],
         "transform": {"translate": [0, 4, 6], "rotate": [90, 0, 0]}},
        {"name": "smoke_box", "shape": {"type": "box", "size": size}, "materials": ["smoke"],
         "transform": {"translate": centre}},
    ],
    "lights": [{"name": "spot", "type": "spot", "position": [0.8, -0.6, 4.6], "direction": [-0.15, 0.1, -1],
                "power": 1500, "radius": 0.05, "spot_size": 0.8, "spot_blend": 0.25}],
}
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "smoke_spot.json"), "w") as f:
    json.dump(scene, f, separators=(",", ":"))
