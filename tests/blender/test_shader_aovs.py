"""Shader AOVs against Cycles: build_scenes.shader_aovs (48x48: a ball writing a Noise colour
and its height, a cube a constant colour, the floor its height, a 70%-transparent card in front
writing green; View Layer AOVs "tint" (colour) and "height" (value)) rendered by Cycles, then
by Rendezvous' path tracer, BDPT and PSSMLT in this process, saved as a multilayer EXR and read
back pass by pass. Per integrator, as test_brightness.compare (means within 2%, 8x8 blocks
within 3% or 5 standard errors): tint's colour, tint's alpha (the share of samples that wrote
it: 1 on the ball and cube, 2 where the card lies over the ball, 0 on the floor and the world)
and height (PSSMLT's passes come from its 4-sample first-hit pass: means only).

    run_blender.py --script test_shader_aovs.py -- [--samples N]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import brightness_failures, build_scenes, run_test  # noqa: E402
from pass_test import render_passes  # noqa: E402
import numpy as np  # noqa: E402

PASSES = [("tint", "RGBA"), ("height", "X")]


def check(a, odir, failures):
    scene = build_scenes.build("shader_aovs")
    ref = render_passes(scene, "CYCLES", a.samples, os.path.join(odir, "shader_aovs_cycles.exr"), PASSES)
    for integrator, samples in (("PATH", a.samples), ("BDPT", a.samples // 2), ("PSSMLT", 4)):
        test = render_passes(scene, "RENDEZVOUS", samples, os.path.join(odir, "shader_aovs_%s.exr" % integrator.lower()),
                             PASSES, integrator)
        if not all(np.isfinite(p).all() for p in test.values()):
            failures.append("%s: non-finite pixels" % integrator)
            continue
        blocks = integrator != "PSSMLT"
        failures += brightness_failures("%s tint" % integrator, ref["tint"][:, :, :3], test["tint"][:, :, :3], blocks=blocks)
        alpha = lambda p: np.repeat(p["tint"][:, :, 3:4], 3, 2)  # noqa: E731
        failures += brightness_failures("%s tint alpha" % integrator, alpha(ref), alpha(test), blocks=blocks)
        failures += brightness_failures("%s height" % integrator, ref["height"], test["height"], blocks=blocks)
        if float(alpha(ref).max()) < 1.5:
            failures.append("the card should write over the ball (Cycles' alpha reaches %.2f)" % float(alpha(ref).max()))


if __name__ == "__main__":
    run_test("SHADER AOVS", check, samples=64, needs_oiiotool=True)
