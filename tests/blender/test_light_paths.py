"""Cycles' Light Paths settings agree with Cycles: each scene (build_scenes.LIGHT_PATH_SCENES)
sets scene.cycles as a user would (diffuse or glossy bounces, caustics switches, indirect
clamp, volume bounces), Cycles renders it, then Rendezvous' path tracer and BDPT read the
same settings (shared with Cycles, as Cycles shares them) and render it in this process.
Per integrator: image mean within 2% of Cycles', 8x8 blocks within 3% or 5 standard errors
(test_brightness.compare). A lamp's Light > Max Bounces (light.cycles.max_bounces) is read
too. The scene is also rendered by the path tracer with the settings (and the lamps' Max
Bounces) back at Cycles' defaults, to show they change the image (some 8x8 block brighter than a tenth
of the image mean changes by at least 5%).

A clamp acts on each contribution, so a clamped image depends on the estimator: BDPT's
(per strategy) is its own, and even the path tracer's differs from Cycles' where their light
sampling differs (Cycles 3.4 samples a nearby emissive triangle by solid angle, we by area:
fewer of its contributions exceed the cap). The clamp scene compares the path tracer's mean
only, within 3% (measured 0.979; unclamped, the box is within 0.5%).

    run_blender.py --script test_light_paths.py -- SCENE [SCENE ...] [--samples N] [--verdicts DIR]
"""

import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, compare, cycles_sampling, read_render, run_test, setting_effect  # noqa: E402

LIGHT_PATH_PROPS = ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces",
                    "transparent_max_bounces", "caustics_reflective", "caustics_refractive",
                    "sample_clamp_direct", "sample_clamp_indirect", "blur_glossy")
MIN_EFFECT = 0.05
CLAMP_MEAN_TOLERANCE = 0.03


def render(scene, engine, samples, path, integrator="PATH", seed=1, alpha=False):
    if engine == "CYCLES":
        cycles_sampling(scene, samples, seed)
    else:
        scene.render.engine = engine
        p = scene.rendezvous
        p.integrator = integrator
        p.samples = samples
        p.time_limit = 0.0
        p.seed = seed
        p.clamp = 0.0
    t = time.time()
    bpy.ops.render.render()
    return read_render(scene, path, alpha), time.time() - t


def check(a, odir, failures):
    scene = bpy.context.scene
    for prop in LIGHT_PATH_PROPS:  # Cycles' defaults, then what the scene sets
        scene.cycles.property_unset(prop)
    defaults = {prop: getattr(scene.cycles, prop) for prop in LIGHT_PATH_PROPS}
    scene = build_scenes.build(a.scene)
    changed = {prop: getattr(scene.cycles, prop) for prop in LIGHT_PATH_PROPS
               if getattr(scene.cycles, prop) != defaults[prop]}
    lamp_bounces = {l.name: l.cycles.max_bounces for l in bpy.data.lights if l.cycles.is_property_set("max_bounces")}
    print("LIGHT PATHS %s: scene.cycles %s, Light > Max Bounces %s" % (a.scene, changed, lamp_bounces))
    ref, tc = render(scene, "CYCLES", a.samples, os.path.join(odir, a.scene + "_cycles.exr"))
    print("  Cycles %d spp: %.1f s" % (a.samples, tc))
    # BDPT's clamp is per strategy (README): path tracing only. Filter Glossy: both.
    integrators = (("PATH", a.samples),) if "sample_clamp_indirect" in changed else \
        (("PATH", a.samples), ("BDPT", a.samples // 2))
    for integrator, samples in integrators:
        test, tr = render(scene, "RENDEZVOUS", samples, os.path.join(odir, "%s_%s.exr" % (a.scene, integrator.lower())),
                          integrator)
        print("  Rendezvous %s %d spp: %.1f s" % (integrator, samples, tr))
        ok_mean, ok_blocks, ratio = compare("%s %s" % (a.scene, integrator), ref, test)
        if "sample_clamp_indirect" in changed:
            ok_mean, ok_blocks = abs(ratio - 1.0) <= CLAMP_MEAN_TOLERANCE, True
        if not ok_mean:
            failures.append("%s %s: mean ratio Rendezvous/Cycles = %.4f" % (a.scene, integrator, ratio))
        if not ok_blocks:
            failures.append("%s %s: block means differ beyond noise" % (a.scene, integrator))
    for prop, value in changed.items():
        setattr(scene.cycles, prop, defaults[prop])
    for light in bpy.data.lights:  # Light > Max Bounces back at its default (1024) too
        light.cycles.property_unset("max_bounces")
    if "blur_glossy" in changed:  # Cycles' default filters too: compare with it off
        scene.cycles.blur_glossy = 0.0
    plain, _ = render(scene, "RENDEZVOUS", a.samples, os.path.join(odir, a.scene + "_default.exr"))
    effect = setting_effect(ref, plain)
    print("  with Cycles' default light paths instead: mean %.4f of Cycles', largest block change %.1f%%"
          % (plain.mean() / ref.mean(), 100 * effect))
    if effect < MIN_EFFECT:
        failures.append("%s: the settings change no block by %.0f%% (the test would not see them ignored)"
                        % (a.scene, 100 * MIN_EFFECT))


if __name__ == "__main__":
    run_test("LIGHT PATHS", check, samples=1024, members="scene")
