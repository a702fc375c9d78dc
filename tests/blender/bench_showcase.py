"""Benchmark (label bench, not part of CI): the README's showcase next to Cycles at equal time.
The `showcase` scene of scenes/blend/build_scenes.py (a room lit through a door gap, fog, a
glass ball's caustic), rendered by Rendezvous' BDPT and by Cycles 3.4 (CPU, no denoising, no
adaptive sampling) with the same time limit, both on every core. Prints each one's samples
per pixel, mean and relative MSE against a long BDPT reference (the mean of two renders with
different seeds, cached; its own noise, a quarter of the two halves' relMSE, is printed and
taken out of the "net" figures), and writes both images as the scene shows them (Filmic).

    python3 run_blender.py --lib build/engine/librendezvous.so --script bench_showcase.py -- \\
        [--time 60] [--reference-time 600] [--cache DIR] [--images DIR] [--steps ref1,ref2,compare]

The reference halves and the comparison are separate steps so that each stays under ten
minutes on a shared machine; a step whose output is cached is skipped.
"""

import argparse
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, out_dir, read_render  # noqa: E402
from rendezvous.engine import final  # noqa: E402

EPSILON = 0.01  # engine/src/film/image_error.h: (x - ref)^2 / (ref^2 + 0.01)


def relative_mse(image, reference, mask=None, denominator=None):
    """Mean over pixels (those of mask, else all) and channels; denominator: the reference
    the error is relative to (default `reference`)."""
    d = reference if denominator is None else denominator
    e = np.mean((image - reference) ** 2 / (d ** 2 + EPSILON), axis=2)
    return float(e.mean() if mask is None else e[mask].mean())


def outside_glints(reference, margin=2):
    """The pixels away from the lamp's glints: where the reference exceeds 50 times the
    image's mean (the spot seen through and in the glass ball) and `margin` pixels around.
    Only paths that hit the 5 cm lamp by chance render those (a pure specular chain from the
    camera), in either engine: one such sample makes a pixel of thousands, and the few
    glint pixels would otherwise hold almost all of either image's error."""
    glint = reference.mean(axis=2) > 50.0 * reference.mean()
    near = glint.copy()
    for dy in range(-margin, margin + 1):
        for dx in range(-margin, margin + 1):
            near |= np.roll(np.roll(glint, dy, 0), dx, 1)
    return ~near


def render(scene, engine, seconds, seed, exr_path, png_path=None):
    """One render with a time limit; (linear RGB, wall seconds, samples per pixel)."""
    if engine == "CYCLES":
        scene.render.engine = "CYCLES"
        c = scene.cycles
        c.device = "CPU"
        c.samples = 1 << 24
        c.time_limit = seconds
        c.use_denoising = False
        c.use_adaptive_sampling = False
        c.seed = seed
    else:
        scene.render.engine = "RENDEZVOUS"
        p = scene.rendezvous
        p.integrator = engine
        p.samples = 1 << 24
        p.time_limit = seconds
        p.seed = seed
    scene.render.threads_mode = "AUTO"
    t = time.time()
    bpy.ops.render.render()
    dt = time.time() - t
    # Rendezvous' progress; Cycles reports its samples only on the console
    spp = final.last_render["progress"]["samples_done"] if engine != "CYCLES" else None
    image = read_render(scene, exr_path)
    if png_path:
        settings = scene.render.image_settings
        settings.file_format, settings.color_depth, settings.color_mode = "PNG", "8", "RGB"
        bpy.data.images["Render Result"].save_render(png_path)
    return image, dt, spp


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("--time", type=float, default=60.0, help="each engine's time limit (s)")
    ap.add_argument("--reference-time", type=float, default=600.0, help="the two reference halves together (s)")
    ap.add_argument("--cache", default=os.path.join(out_dir(), "showcase_reference"))
    ap.add_argument("--images", default="", help="write rendezvous_bdpt.png and cycles.png here")
    ap.add_argument("--steps", default="ref1,ref2,compare")
    a = ap.parse_args(argv)
    os.makedirs(a.cache, exist_ok=True)
    scene = build_scenes.build("showcase")
    w, h = scene.render.resolution_x, scene.render.resolution_y
    halves = []
    for i, step in enumerate(("ref1", "ref2")):
        path = os.path.join(a.cache, "reference_%dx%d_%gs_seed%d.npy" % (w, h, a.reference_time / 2, 101 + i))
        if not os.path.exists(path) and step in a.steps:
            image, dt, spp = render(scene, "BDPT", a.reference_time / 2, 101 + i, path[:-4] + ".exr")
            np.save(path, image)
            print("SHOWCASE reference half %d: %.0f s, %d spp, mean %.5f" % (i + 1, dt, spp, image.mean()))
        if os.path.exists(path):
            halves.append(np.load(path))
    if "compare" not in a.steps:
        return
    if len(halves) != 2:
        sys.exit("bench_showcase: the reference halves are not cached yet (run the ref1 and ref2 steps)")
    reference = 0.5 * (halves[0] + halves[1])
    mask = outside_glints(reference)
    # the mean of two independent halves has a quarter of their difference's variance
    noise = 0.25 * relative_mse(halves[0], halves[1], denominator=reference)
    noise_out = 0.25 * relative_mse(halves[0], halves[1], mask, denominator=reference)
    print("SHOWCASE %dx%d, reference: BDPT 2 x %.0f s, mean %.5f, own noise %.3e (outside the %d glint pixels %.3e)"
          % (w, h, a.reference_time / 2, reference.mean(), noise, int((~mask).sum()), noise_out))
    errors = {}
    for engine, name in (("BDPT", "rendezvous_bdpt"), ("CYCLES", "cycles")):
        png = os.path.join(a.images, name + ".png") if a.images else None
        if png:
            os.makedirs(a.images, exist_ok=True)
        image, dt, spp = render(scene, engine, a.time, 7, os.path.join(a.cache, name + ".exr"), png)
        errors[engine] = (relative_mse(image, reference), relative_mse(image, reference, mask))
        pixel_errors = np.sort(np.mean((image - reference) ** 2 / (reference ** 2 + EPSILON), axis=2).ravel())
        print("SHOWCASE %-8s limit %.0f s, wall %.1f s, %s spp, mean %.5f (reference %.5f), relMSE %.3e "
              "(net %.3e; its 10 worst pixels hold %.1f%%), outside the glints %.3e (net %.3e)"
              % (engine, a.time, dt, "?" if spp is None else spp, image.mean(), reference.mean(), errors[engine][0],
                 errors[engine][0] - noise, 100.0 * pixel_errors[-10:].sum() / pixel_errors.sum(), errors[engine][1],
                 errors[engine][1] - noise_out))
    print("SHOWCASE Cycles / BDPT relMSE: whole image %.3g (net %.3g), outside the glints %.3g (net %.3g)" % (
        errors["CYCLES"][0] / errors["BDPT"][0], (errors["CYCLES"][0] - noise) / (errors["BDPT"][0] - noise),
        errors["CYCLES"][1] / errors["BDPT"][1], (errors["CYCLES"][1] - noise_out) / (errors["BDPT"][1] - noise_out)))


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
