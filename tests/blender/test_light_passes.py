"""Cycles' light passes against Cycles: build_scenes.light_passes (48x48: diffuse, glossy and
glass balls, an emissive ball, the world, a sun, a cube of fog) rendered by Cycles, then by
Rendezvous' path tracer and BDPT (or the integrators --integrators names: PSSMLT and MMLT with
as many mutations per pixel as Cycles' samples) in this process, with View Layer > Passes > Light all on (and
Cycles' Volume Direct / Indirect), written as a multilayer EXR and read back pass by pass
(oiiotool). Per integrator:
- every light pass (Direct and Indirect times their Color: what they add to Combined) as
  test_brightness.compare (means within 2%, 8x8 blocks within 3% or 5
  standard errors) where it holds at least 2% of Combined's mean; a smaller pass (noise
  dominated at these sample counts) must differ from Cycles' by at most 0.5% of Combined's
  mean;
- the Metropolis integrators: every pass (and Combined) within 1% of Combined's mean of Cycles'
  (their noise is correlated between neighbouring pixels, which the block test's noise estimate
  does not see; the engine's LightPasses.MetropolisAgreesWithBdpt compares them block by block
  with independent seeds);
- Emission + Environment + sum (Direct + Indirect) x Color + Volume equals Combined per pixel
  (relative 1e-4; pixels where a kind's colour is partly 0 next to pixels where it is not are
  left out: BDPT's light-tracing splats reach 1.5 px from the surface they classify).

    run_blender.py --script test_light_passes.py -- [--samples N] [--integrators PATH,BDPT]
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import brightness_failures, build_scenes, run_test  # noqa: E402
from pass_test import render_passes  # noqa: E402
import numpy as np  # noqa: E402

LIGHT = ["Emit", "Env", "DiffDir", "DiffInd", "DiffCol", "GlossDir", "GlossInd", "GlossCol",
         "TransDir", "TransInd", "TransCol", "VolumeDir", "VolumeInd"]
SMALL_SHARE = 0.02      # a pass below 2% of Combined's mean is compared absolutely ...
SMALL_ABS = 0.005       # ... within 0.5% of Combined's mean
SUM_TOLERANCE = 1e-4
# Metropolis: every pass within a share of Combined's mean, by each integrator's own spread at
# 1024 mutations per pixel here (Combined's mean over seeds 1-8, 2026-11-30): pssmlt 0.09% (1
# standard deviation), mmlt 0.49% (its chains' heavy tail: the glass ball's caustic; 0.37% at
# 4096 mutations, so more mutations would not buy a tighter bound). 1% and 2% are 11 and 4
# standard deviations: a false alarm below 1e-4 per run.
METROPOLIS_ABS = {"PSSMLT": 0.01, "MMLT": 0.02}


def enable_light_passes(layer):
    for prop in ("use_pass_emit", "use_pass_environment", "use_pass_diffuse_direct", "use_pass_diffuse_indirect",
                 "use_pass_diffuse_color", "use_pass_glossy_direct", "use_pass_glossy_indirect",
                 "use_pass_glossy_color", "use_pass_transmission_direct", "use_pass_transmission_indirect",
                 "use_pass_transmission_color"):
        setattr(layer, prop, True)
    layer.cycles.use_pass_volume_direct = True
    layer.cycles.use_pass_volume_indirect = True


def render(scene, engine, samples, path, integrator="PATH"):
    return render_passes(scene, engine, samples, path, [(name, "RGB") for name in ["Combined"] + LIGHT], integrator)


def contribution(p, name):
    """What the pass adds to Combined: a Direct or Indirect pass times its Color. The divided
    pass itself is ill-conditioned where the colour is small (a ball's silhouette), so its mean
    over an image is dominated by a few edge pixels' noise in either renderer."""
    for kind in ("Diff", "Gloss", "Trans"):
        if name in (kind + "Dir", kind + "Ind"):
            return p[name] * p[kind + "Col"]
    return p[name]


def absolute_check(label, r, t, combined_mean, tolerance, what):
    """Failures of a pass whose mean must be within tolerance x Combined's mean of Cycles'."""
    diff = abs(t.mean() - r.mean()) / combined_mean
    print("BRIGHTNESS %-24s %scycles mean %.5f rendezvous mean %.5f (%.2f%% of Combined) -> %s"
          % (label, what, r.mean(), t.mean(), 100 * diff, "ok" if diff <= tolerance else "FAIL"))
    return ["%s: mean %.5f vs Cycles %.5f" % (label, t.mean(), r.mean())] if diff > tolerance else []


def sum_check(name, p):
    """Failures of Emission + Environment + sum (Dir + Ind) x Col + Volume = Combined."""
    total = p["Emit"] + p["Env"] + p["VolumeDir"] + p["VolumeInd"]
    keep = np.ones(p["Combined"].shape[:2], bool)
    for kind in ("Diff", "Gloss", "Trans"):
        col = p[kind + "Col"]
        total = total + (p[kind + "Dir"] + p[kind + "Ind"]) * col
        partial = (col <= 0).any(axis=2)
        seen = (col != 0).any(axis=2)
        near = np.zeros_like(seen)
        for dy in range(-2, 3):
            for dx in range(-2, 3):
                near |= np.roll(np.roll(seen, dy, axis=0), dx, axis=1)
        keep &= ~(partial & near)
    err = np.abs(total - p["Combined"]) / (np.abs(p["Combined"]) + 1e-3)
    worst = float(err[keep].max()) if keep.any() else 0.0
    print("SUM %-12s pixels checked %d of %d, worst relative error %.2e" % (name, int(keep.sum()), keep.size, worst))
    if keep.sum() < keep.size * 3 // 4:
        return ["%s: too few pixels to check the pass sum (%d)" % (name, int(keep.sum()))]
    return ["%s: light passes sum to Combined only within %.2e" % (name, worst)] if worst > SUM_TOLERANCE else []


def check(a, odir, failures):
    # Samples per pixel (Metropolis: mutations per pixel) of each integrator.
    samples = {"PATH": a.samples, "BDPT": a.samples // 2, "PSSMLT": a.samples, "MMLT": a.samples}
    scene = build_scenes.build("light_passes")
    enable_light_passes(bpy.context.view_layer)
    ref = render(scene, "CYCLES", a.samples, os.path.join(odir, "light_passes_cycles.exr"))
    combined_mean = ref["Combined"].mean()
    for integrator in a.integrators.split(","):
        test = render(scene, "RENDEZVOUS", samples[integrator],
                      os.path.join(odir, "light_passes_%s.exr" % integrator.lower()), integrator)
        for name in ["Combined"] + LIGHT:
            r, t = contribution(ref, name), contribution(test, name)
            label = "%s %s" % (integrator, name)
            if not np.isfinite(t).all():
                failures.append("%s: non-finite pixels" % label)
                continue
            if integrator in ("PSSMLT", "MMLT"):
                failures += absolute_check(label, r, t, combined_mean, METROPOLIS_ABS[integrator], "")
                continue
            if r.mean() < SMALL_SHARE * combined_mean:
                failures += absolute_check(label, r, t, combined_mean, SMALL_ABS, "small pass: ")
                continue
            failures += brightness_failures(label, r, t)
        failures += sum_check(integrator, test)


if __name__ == "__main__":
    run_test("LIGHT PASSES", check, samples=1024, needs_oiiotool=True,
             add_arguments=lambda ap: ap.add_argument("--integrators", default="PATH,BDPT"))
