"""Ordinary scenes agree with Cycles: the Cornell box with an emissive quad 1 cm below
its white ceiling (two-sided emission lighting the ceiling at near contact; walls
meeting at corners, blocks standing on the floor), rendered by Cycles and by Rendezvous'
path tracer and BDPT in this Blender process. Per integrator: the image mean within 1%
of Cycles', every bright 16x16 block (mean above half the image mean) within 5%
(test_lamp_reflections.compare).

    run_blender.py --script test_cornell_accuracy.py -- [SCENE] [--cycles-samples N]
                   [--path-samples N] [--bdpt-samples N]

Cycles bounces every path type up to 12 here, as Rendezvous does (its default of 4
diffuse bounces leaves the box 1.5% darker). Measured at the default sample counts
(128x128): block ratios within 1.8% (PT) and 0.5% (BDPT), means within 0.1%. Before the
ray offsets followed each point's rounding error, the path tracer's floor blocks in
front of the blocks were 0.943 of Cycles'.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, out_dir, render_cycles, render_rendezvous  # noqa: E402
from test_lamp_reflections import compare  # noqa: E402


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("scene", nargs="?", default="cornell_lamp_near_ceiling")
    ap.add_argument("--cycles-samples", type=int, default=2048)
    ap.add_argument("--path-samples", type=int, default=1024)
    ap.add_argument("--bdpt-samples", type=int, default=512)
    a = ap.parse_args(argv)
    odir = out_dir()
    scene = build_scenes.build(a.scene)
    c = scene.cycles
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.transparent_max_bounces = 12
    ref, tc = render_cycles(scene, a.cycles_samples, os.path.join(odir, a.scene + "_cycles.exr"))
    print("  Cycles %d spp: %.1f s" % (a.cycles_samples, tc))
    failures = []
    for integrator, samples in (("PATH", a.path_samples), ("BDPT", a.bdpt_samples)):
        path = os.path.join(odir, "%s_%s.exr" % (a.scene, integrator.lower()))
        test, tr = render_rendezvous(scene, samples, path, integrator)
        print("  Rendezvous %s %d spp: %.1f s" % (integrator, samples, tr))
        failures += compare("%s %s" % (a.scene, integrator), ref, test)
    if failures:
        print("CORNELL ACCURACY TEST FAILED (images in %s):\n  %s" % (odir, "\n  ".join(failures)))
        sys.exit(1)
    print("CORNELL ACCURACY TEST PASSED")


if __name__ == "__main__":
    main()
