"""Alpha-mapped cards (build_scenes.alpha_leaves: a checker cut-out into Principled Alpha and a
half-transparent Mix over a floor, a sun and a point lamp without a radius, an orthographic
camera) against Cycles, path tracing and BDPT: image means within 2% and 8x8 blocks within 3%
or 5 standard errors (test_brightness.compare). The shadows through the cards come from
next-event estimation alone (delta lights; light tracing cannot reach an orthographic camera),
so BDPT must see through the cards as the path tracer does: before it made each card a vertex
that blocked its connections, and the floor under the cards was black.

    run_blender.py --script test_transparent_layers.py -- [--samples N]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import brightness_failures, build_scenes, render_cycles, render_rendezvous, run_test  # noqa: E402


def check(a, odir, failures):
    scene = build_scenes.build("alpha_leaves")
    ref, tc = render_cycles(scene, a.samples, os.path.join(odir, "alpha_leaves_cycles.exr"))
    print("  Cycles %d spp: %.1f s" % (a.samples, tc))
    for integrator, samples in (("PATH", a.samples // 2), ("BDPT", a.samples // 4)):
        test, tr = render_rendezvous(scene, samples, os.path.join(odir, "alpha_leaves_%s.exr" % integrator.lower()),
                                     integrator)
        print("  Rendezvous %s %d spp: %.1f s" % (integrator, samples, tr))
        failures += brightness_failures("alpha_leaves %s" % integrator, ref, test)


if __name__ == "__main__":
    run_test("TRANSPARENT LAYERS", check, samples=512)
