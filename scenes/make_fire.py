#!/usr/bin/env python3
"""Writes scenes/fire.json: a small fire (blackbody emission from an analytic temperature
field, in thin smoke, dense 32^3 grids) on a floor in front of a wall, lit by nothing else
but a dim world: the scene where camera paths alone find the light rarely and volume-light
sampling (next-event estimation, BDPT light subpaths from the flame) pays.
    python3 scenes/make_fire.py"""
import json
import math
import os

N = 32
BOUNDS = [[-0.4, -0.4, 0.0], [0.4, 0.4, 1.2]]  # the box stands on the floor (its bottom face in the floor plane)


def flame(x, y, z):  # x, y, z in [0, 1]: a tapering plume, hottest low in the middle
    r = math.hypot(x - 0.5, y - 0.5)
    width = 0.32 * (1.0 - 0.75 * z)
    wobble = 1.0 + 0.25 * math.sin(9.0 * z + 4.0 * x) * math.sin(7.0 * y + 2.0)
    core = max(0.0, 1.0 - r / max(width * wobble, 1e-3))
    return core * max(0.0, 1.0 - z) * min(1.0, 6.0 * z)


def smoke(x, y, z):
    r = math.hypot(x - 0.5, y - 0.5)
    return max(0.0, 0.6 - r / (0.25 + 0.3 * z)) * z


temperature, density = [], []
for k in range(N):
    for j in range(N):
        for i in range(N):
            p = ((i + 0.5) / N, (j + 0.5) / N, (k + 0.5) / N)
            temperature.append(round(flame(*p), 4))
            density.append(round(smoke(*p), 4))

size = [BOUNDS[1][a] - BOUNDS[0][a] for a in range(3)]
centre = [(BOUNDS[1][a] + BOUNDS[0][a]) / 2 for a in range(3)]
scene = {
    "settings": {"width": 320, "height": 240, "samples": 64, "max_bounces": 12},
    "camera": {"type": "perspective", "focal_length": 30,
               "transform": {"look_at": {"from": [0.3, -3.2, 1.2], "to": [0.0, 0.0, 0.6]}}},
    "world": {"color": [0.005, 0.005, 0.008]},
    "materials": [
        {"name": "floor", "type": "diffuse", "color": [0.6, 0.6, 0.6]},
        {"name": "wall", "type": "diffuse", "color": [0.5, 0.45, 0.4]},
        {"name": "fire", "type": "volume",
         "volume": {"density": 1.5, "color": [0.4, 0.4, 0.4], "blackbody_intensity": 8.0, "temperature": 3000.0,
                    "grid": {"resolution": [N, N, N], "values": density, "bounds": BOUNDS},
                    "temperature_grid": {"resolution": [N, N, N], "values": temperature, "bounds": BOUNDS}}},
    ],
    "meshes": [
        {"name": "floor", "shape": {"type": "quad", "size": 10}, "materials": ["floor"]},
        {"name": "back", "shape": {"type": "quad", "size": 10}, "materials": ["wall"],
         "transform": {"translate": [0, 2, 5], "rotate": [90, 0, 0]}},
        {"name": "fire_box", "shape": {"type": "box", "size": size}, "materials": ["fire"],
         "transform": {"translate": centre}},
    ],
}
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "fire.json"), "w") as f:
    json.dump(scene, f, separators=(",", ":"))
