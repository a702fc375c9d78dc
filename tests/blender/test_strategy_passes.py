"""BDPT's strategy passes in Blender: build_scenes.light_passes (48x48: diffuse, glossy and
glass balls, an emissive ball, the world, a sun, a cube of fog) rendered by Rendezvous' BDPT
with View Layer > Passes > Rendezvous Passes > BDPT Strategies on (Strategy Depth 2), saved as a
multilayer EXR and read back pass by pass (oiiotool):
- every pass (Strategy_s0t2 .. Strategy_s3t1 and Strategy_rest) exists in the Render Result,
  is finite, and they sum to Combined per pixel (relative 1e-4: float rounding);
- the passes of the camera-side and light-tracing strategies both hold light (the scene has
  paths of every kind);
- the Path Tracing integrator with the toggle on renders, warns that the passes are
  Bidirectional's and leaves them black.

    run_blender.py --script test_strategy_passes.py -- [--samples N]
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, run_test  # noqa: E402
from pass_test import render_passes  # noqa: E402
import numpy as np  # noqa: E402

DEPTH = 2
SUM_TOLERANCE = 1e-4


def strategy_names(depth):
    """The passes' names (engine/src/film/strategy_passes.h), written out for the test."""
    names = ["Strategy_s0t2"]
    for d in range(1, depth + 1):
        names += ["Strategy_s%dt%d" % (s, d + 2 - s) for s in range(d + 2)]
    return names + ["Strategy_rest"]


def render(scene, samples, path, integrator):
    return render_passes(scene, "RENDEZVOUS", samples, path,
                         [(name, "RGB") for name in ["Combined"] + strategy_names(DEPTH)], integrator)


def check(a, odir, failures):
    scene = build_scenes.build("light_passes")
    layer = bpy.context.view_layer
    layer.rendezvous.use_pass_strategies = True
    layer.rendezvous.strategy_max_depth = DEPTH
    names = strategy_names(DEPTH)

    # The passes registered with Blender (the compositor's Render Layers node lists them).
    from rendezvous.engine import passes as addon_passes
    registered = [p[0] for p in addon_passes.enabled_passes(layer, scene)]
    missing = [n for n in names if n not in registered]
    if missing:
        failures.append("passes not registered: %s" % ", ".join(missing))

    p = render(scene, a.samples, os.path.join(odir, "strategy_passes_bdpt.exr"), "BDPT")
    total = np.zeros_like(p["Combined"])
    for name in names:
        v = p[name]
        print("PASS %-16s mean %.5f" % (name, v.mean()))
        if not np.isfinite(v).all():
            failures.append("%s: non-finite pixels" % name)
        total += v
    err = np.abs(total - p["Combined"]) / (np.abs(p["Combined"]) + 1e-3)
    print("SUM of %d passes vs Combined: worst relative error %.2e (Combined mean %.5f)"
          % (len(names), float(err.max()), p["Combined"].mean()))
    if err.max() > SUM_TOLERANCE:
        failures.append("strategy passes sum to Combined only within %.2e" % err.max())
    for name in ("Strategy_s1t2", "Strategy_s2t1", "Strategy_s2t2", "Strategy_rest"):
        if not p[name].mean() > 0:
            failures.append("%s holds no light" % name)

    # Path tracing: the toggle stays on, the passes stay black, a warning says why.
    from rendezvous.engine import final
    q = render(scene, 4, os.path.join(odir, "strategy_passes_path.exr"), "PATH")
    warned = any("strategy passes" in line for line in final.last_render.get("messages", []))
    print("PATH: Combined mean %.5f, strategy passes max %.3g, warned %s"
          % (q["Combined"].mean(), max(float(np.abs(q[n]).max()) for n in names), warned))
    if not q["Combined"].mean() > 0:
        failures.append("path tracing with the strategy passes on rendered nothing")
    if any(np.abs(q[n]).max() != 0 for n in names):
        failures.append("path tracing filled the strategy passes")
    if not warned:
        failures.append("path tracing with the strategy passes on did not warn")


run_test("STRATEGY PASSES", check, samples=16, needs_oiiotool=True)
