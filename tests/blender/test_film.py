"""Film > Transparent and holdouts against Cycles: the world seen directly (and through a
half-Transparent card, and through smooth glass when Transparent Glass is on) leaves alpha, not
colour; with an opaque film, a holdout object (Object > Visibility > Holdout) and a card half
Holdout shader cut their coverage out of the alpha and render black.
build_scenes.film_transparent, 48x48: Cycles renders it, then Rendezvous' path tracer and
BDPT in this process. Per integrator:
- colour (premultiplied) and alpha as test_brightness.compare: means within 2%, 8x8 blocks
  within 3% or 5 standard errors;
- exact where they must be: pixels 2 px or more from anything Cycles covers have alpha 0 and
  colour 0 in both; pixels 2 px or more from any partial alpha in Cycles' image have alpha 1;
- the film opaque again (Film > Transparent off): alpha exactly 1 everywhere.

    run_blender.py --script test_film.py -- VARIANT [VARIANT ...] [--samples N] [--verdicts DIR]
VARIANT: transparent (Transparent Glass off), transparent_glass, transparent_fog (a cube of fog
in front of the sky and the glass ball: the world seen through it partly transparent, as its
transmittance), or holdout (the opaque film with the diffuse ball a holdout object and the
card's Transparent BSDF a Holdout shader).
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import brightness_failures, build_scenes, run_test  # noqa: E402
from test_light_paths import render as render_engine  # noqa: E402
import numpy as np  # noqa: E402

MARGIN = 2  # pixels: the pixel filter reaches 1.5 px


def render(scene, engine, samples, path, integrator="PATH"):
    """RGBA of the scene rendered by engine (seed 1), and the seconds it took."""
    return render_engine(scene, engine, samples, path, integrator, alpha=True)


def dilate(mask, r):
    out = mask.copy()
    h, w = mask.shape
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            shifted = np.zeros_like(mask)
            shifted[max(dy, 0):h + min(dy, 0), max(dx, 0):w + min(dx, 0)] = \
                mask[max(-dy, 0):h + min(-dy, 0), max(-dx, 0):w + min(-dx, 0)]
            out |= shifted
    return out


def exact_checks(name, ref, test):
    """Failures where alpha (and colour) must be exact; ref: Cycles' RGBA."""
    failures = []
    empty = ~dilate(ref[:, :, 3] > 0, MARGIN)  # nothing of the scene within reach
    opaque = ~dilate(ref[:, :, 3] < 1, MARGIN)  # nothing transparent within reach
    wrong_empty = int(np.count_nonzero(test[empty] != 0))
    wrong_opaque = int(np.count_nonzero(test[:, :, 3][opaque] != 1))
    print("ALPHA %-26s empty pixels %d (non-zero in Rendezvous: %d), opaque pixels %d (alpha != 1: %d)"
          % (name, int(empty.sum()), wrong_empty, int(opaque.sum()), wrong_opaque))
    if empty.sum() < 50 or opaque.sum() < 50:
        failures.append("%s: the scene shows too little world (%d px) or solid surface (%d px) to test"
                        % (name, int(empty.sum()), int(opaque.sum())))
    if wrong_empty:
        failures.append("%s: %d values non-zero where only the transparent world is seen" % (name, wrong_empty))
    if wrong_opaque:
        failures.append("%s: %d pixels of solid surface have alpha != 1" % (name, wrong_opaque))
    return failures


VARIANTS = ("transparent", "transparent_glass", "transparent_fog", "holdout")


def check(a, odir, failures):
    if a.variant not in VARIANTS:
        raise ValueError("unknown variant %r (one of %s)" % (a.variant, ", ".join(VARIANTS)))
    scene = build_scenes.build("film_transparent")
    scene.cycles.film_transparent_glass = a.variant == "transparent_glass"
    scene.rendezvous.film_transparent_glass = a.variant == "transparent_glass"  # unused while Cycles is on
    if a.variant == "transparent_fog":
        fog = build_scenes.link(bpy.data.objects.new("Fog", build_scenes.box_mesh("FogMesh", 0.5)))
        fog.location = (0.6, -1.5, 1.5)
        fog.data.materials.append(build_scenes.principled_volume_material("FogMat", Density=1.5,
                                                                          Color=(0.9, 0.9, 0.8, 1.0))[0])
        scene.cycles.volume_bounces = 1
    if a.variant == "holdout":
        scene.render.film_transparent = False
        bpy.data.objects["Ball"].is_holdout = True
        bpy.data.objects["Card"].material_slots[0].material = build_scenes.mix_material(
            "HalfHoldout", ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.7, 0.3, 1)}), ("ShaderNodeHoldout", {}), 0.5)
    ref, tc = render(scene, "CYCLES", a.samples, os.path.join(odir, a.variant + "_cycles.exr"))
    print("  Cycles %d spp: %.1f s, alpha mean %.4f" % (a.samples, tc, ref[:, :, 3].mean()))
    for integrator, samples in (("PATH", a.samples), ("BDPT", a.samples // 2)):
        name = "%s %s" % (a.variant, integrator)
        test, tr = render(scene, "RENDEZVOUS", samples,
                          os.path.join(odir, "%s_%s.exr" % (a.variant, integrator.lower())), integrator)
        print("  Rendezvous %s %d spp: %.1f s, alpha mean %.4f" % (integrator, samples, tr, test[:, :, 3].mean()))
        if not np.isfinite(test).all():
            failures.append("%s: non-finite pixels" % name)
        for what, r, t in (("colour", ref[:, :, :3], test[:, :, :3]),
                           ("alpha", np.repeat(ref[:, :, 3:], 3, axis=2), np.repeat(test[:, :, 3:], 3, axis=2))):
            failures += brightness_failures("%s %s" % (name, what), r, t)
        failures += exact_checks(name, ref, test)
    if a.variant == "holdout":
        return
    scene.render.film_transparent = False
    opaque, _ = render(scene, "RENDEZVOUS", 16, os.path.join(odir, a.variant + "_opaque.exr"))
    not_one = int(np.count_nonzero(opaque[:, :, 3] != 1))
    print("ALPHA opaque film: %d pixels with alpha != 1" % not_one)
    if not_one:
        failures.append("opaque film: %d pixels with alpha != 1" % not_one)


if __name__ == "__main__":
    run_test("FILM", check, samples=256, members="variant")
