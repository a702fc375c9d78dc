"""Cycles' data passes against Cycles: build_scenes.data_passes (40x40: two balls and a
40%-transparent card on a floor running into the distance, linear mist from 2 to 8 units)
rendered by Cycles, then by Rendezvous' path tracer, BDPT and PSSMLT in this process with
View Layer > Passes > Mist, Object Index and Material Index on, written as a multilayer EXR and
read back pass by pass (oiiotool). Per integrator:
- Mist as test_brightness.compare (means within 2%, 8x8 blocks within 3% or 5 standard errors;
  PSSMLT, whose mist comes from its 4-sample first-hit pass: the mean only);
- Object Index and Material Index exactly Cycles' on every pixel whose 5x5 neighbourhood (the
  pixel filter reaches 1.5 px) shows one index in Cycles' pass (both engines keep the value of
  a pixel's first sample, so edge pixels may differ), and only values Cycles has anywhere.

    run_blender.py --script test_data_passes.py -- [--samples N]
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import brightness_failures, build_scenes, run_test  # noqa: E402
from pass_test import render_passes  # noqa: E402
import numpy as np  # noqa: E402

DATA = [("Mist", "Z"), ("IndexOB", "X"), ("IndexMA", "X")]


def render(scene, engine, samples, path, integrator="PATH"):
    """{pass name: H x W} of the data passes."""
    return {name: p[:, :, 0] for name, p in render_passes(scene, engine, samples, path, DATA, integrator).items()}


def uniform_pixels(index):
    """Pixels whose 5x5 neighbourhood holds one value (edges of the image left out)."""
    h, w = index.shape
    keep = np.zeros((h, w), bool)
    for y in range(2, h - 2):
        for x in range(2, w - 2):
            block = index[y - 2:y + 3, x - 2:x + 3]
            keep[y, x] = (block == block[0, 0]).all()
    return keep


def check(a, odir, failures):
    scene = build_scenes.build("data_passes")
    layer = bpy.context.view_layer
    layer.use_pass_mist = True
    layer.use_pass_object_index = True
    layer.use_pass_material_index = True
    ref = render(scene, "CYCLES", a.samples, os.path.join(odir, "data_passes_cycles.exr"))
    for integrator, samples in (("PATH", a.samples), ("BDPT", a.samples // 2), ("PSSMLT", 4)):
        test = render(scene, "RENDEZVOUS", samples, os.path.join(odir, "data_passes_%s.exr" % integrator.lower()),
                      integrator)
        label = "%s Mist" % integrator
        if not all(np.isfinite(p).all() for p in test.values()):
            failures.append("%s: non-finite pixels" % integrator)
            continue
        r, t = np.repeat(ref["Mist"][:, :, None], 3, 2), np.repeat(test["Mist"][:, :, None], 3, 2)
        failures += brightness_failures(label, r, t, blocks=integrator != "PSSMLT")
        for name in ("IndexOB", "IndexMA"):
            keep = uniform_pixels(ref[name])
            equal = (test[name] == ref[name])[keep]
            values = set(np.unique(ref[name]).tolist())
            foreign = set(np.unique(test[name]).tolist()) - values
            print("INDEX %-6s %-7s %d of %d covered pixels equal Cycles' (values %s)%s"
                  % (integrator, name, int(equal.sum()), int(keep.sum()), sorted(values),
                     "; values Cycles never has: %s" % sorted(foreign) if foreign else ""))
            if keep.sum() < keep.size // 3:
                failures.append("%s %s: too few covered pixels (%d)" % (integrator, name, int(keep.sum())))
            if not equal.all():
                failures.append("%s %s: %d covered pixels differ from Cycles'" % (integrator, name,
                                                                                  int((~equal).sum())))
            if foreign:
                failures.append("%s %s: values Cycles never has: %s" % (integrator, name, sorted(foreign)))


if __name__ == "__main__":
    run_test("DATA PASSES", check, samples=256, needs_oiiotool=True)
