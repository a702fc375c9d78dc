"""Cycles' denoising data against Cycles: build_scenes.denoising_data (40x40: a smooth glass
ball, a diffuse ball, a tinted mirror behind them on a diffuse floor) rendered by Cycles, then
by Rendezvous' path tracer, BDPT and PSSMLT in this process with View Layer > Passes > Data >
Denoising Data on, written as a multilayer EXR and read back pass by pass (oiiotool).
Per integrator and pass (Denoising Normal, Albedo, Depth):
- the image's mean of each channel within MEAN_ABS of Cycles' (Depth: MEAN_REL relative);
- 8x8 block means within BLOCK_ABS of Cycles' (Depth: BLOCK_REL relative) in every block
  (PSSMLT, whose features come from its 4-sample first-hit pass: the means only).
The glass ball's pixels are noisy in both (each sample follows its path's Fresnel choice),
which is what the block tolerances allow for at these sample counts.
The same on build_scenes.denoising_fog (a cube of grey fog in front of a wall, a ball and the
floor): every sample adds the fog's albedo x (1 - transmittance), and one that scatters there
ends with Normal (0, 0, -1), as Cycles 3.4's volume integration writes them.

Then Blender's compositor Denoise node on Rendezvous' passes: a 4-spp path-traced image with
its Denoising Normal and Albedo through Render Layers > Denoise > Composite, against a 1024-spp
render: the RMS error of the noisy and of the denoised image are printed. Debian's Blender 3.4
is built without OpenImageDenoise, and its Denoise node then passes the image through
unchanged; the test says which it saw (either passes: the figure is the report).

    run_blender.py --script test_denoising_data.py -- [--samples N]
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, run_test  # noqa: E402
from test_light_paths import render as render_engine  # noqa: E402
from pass_test import render_passes  # noqa: E402
import numpy as np  # noqa: E402

PASSES = [("Denoising Normal", "XYZ"), ("Denoising Albedo", "RGB"), ("Denoising Depth", "Z")]
MEAN_ABS, BLOCK_ABS = 0.01, 0.04   # normal and albedo
MEAN_REL, BLOCK_REL = 0.01, 0.04   # depth
BLOCK = 8


def block_means(img):
    h, w = img.shape[:2]
    return img[:h // BLOCK * BLOCK, :w // BLOCK * BLOCK].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, -1).mean(axis=(1, 3))


def compare(label, name, ref, test, blocks=True):
    """Failures of test against ref for one pass (messages), printing the figures."""
    depth = name == "Denoising Depth"
    r, t = (ref[:, :, :1], test[:, :, :1]) if depth else (ref, test)
    mr, mt = r.reshape(-1, r.shape[2]).mean(axis=0), t.reshape(-1, t.shape[2]).mean(axis=0)
    br, bt = block_means(r), block_means(t)
    if depth:
        mean_err = np.abs(mt - mr) / np.maximum(np.abs(mr), 1e-6)
        block_err = np.abs(bt - br) / np.maximum(np.abs(br), 0.25)  # (blocks of the world: 0)
        mean_tol, block_tol = MEAN_REL, BLOCK_REL
    else:
        mean_err, block_err = np.abs(mt - mr), np.abs(bt - br)
        mean_tol, block_tol = MEAN_ABS, BLOCK_ABS
    bad = int((block_err.max(axis=2) > block_tol).sum())
    print("DENOISING %-7s %-16s means Cycles %s Rendezvous %s; worst mean error %.4f (tolerance %.2f), "
          "worst 8x8 block error %.4f (tolerance %.2f), %d of %d blocks beyond"
          % (label, name, np.round(mr, 4).tolist(), np.round(mt, 4).tolist(), mean_err.max(), mean_tol,
             block_err.max(), block_tol, bad, block_err.shape[0] * block_err.shape[1]))
    failures = []
    if mean_err.max() > mean_tol:
        failures.append("%s %s: mean error %.4f > %.2f" % (label, name, mean_err.max(), mean_tol))
    if blocks and bad:
        failures.append("%s %s: %d blocks beyond %.2f" % (label, name, bad, block_tol))
    return failures


def denoise_node_check(scene, odir):
    """Renders 4 spp through the compositor's Denoise node and 1024 spp without it; prints the
    RMS errors. Returns failures (non-finite output, or a denoiser that made it worse)."""
    scene.use_nodes = True
    tree = scene.node_tree
    for node in list(tree.nodes):
        tree.nodes.remove(node)
    layers = tree.nodes.new("CompositorNodeRLayers")
    denoise = tree.nodes.new("CompositorNodeDenoise")
    composite = tree.nodes.new("CompositorNodeComposite")
    tree.links.new(layers.outputs["Image"], denoise.inputs["Image"])
    tree.links.new(layers.outputs["Denoising Normal"], denoise.inputs["Normal"])
    tree.links.new(layers.outputs["Denoising Albedo"], denoise.inputs["Albedo"])
    tree.links.new(denoise.outputs["Image"], composite.inputs["Image"])
    scene.render.use_compositing = True
    denoised, _ = render_engine(scene, "RENDEZVOUS", 4, os.path.join(odir, "denoise_node_4spp.exr"), "PATH")
    denoise.mute = True  # the same render without the denoiser
    noisy, _ = render_engine(scene, "RENDEZVOUS", 4, os.path.join(odir, "denoise_node_4spp_noisy.exr"), "PATH")
    reference, _ = render_engine(scene, "RENDEZVOUS", 1024, os.path.join(odir, "denoise_node_1024spp.exr"), "PATH")
    scene.use_nodes = False

    def rms(a):
        return float(np.sqrt(np.mean((a - reference) ** 2)))

    passed_through = np.array_equal(denoised, noisy)
    print("DENOISE NODE 4 spp RMS error vs 1024 spp: noisy %.5f, through the Denoise node %.5f (%s); "
          "reference mean %.4f" % (rms(noisy), rms(denoised),
                                   "unchanged: this Blender's Denoise node has no OpenImageDenoise"
                                   if passed_through else "%.2fx lower" % (rms(noisy) / max(rms(denoised), 1e-12)),
                                   float(reference.mean())))
    failures = []
    if not np.isfinite(denoised).all():
        failures.append("Denoise node: non-finite pixels")
    elif not passed_through and rms(denoised) >= rms(noisy):
        failures.append("Denoise node: error %.5f not below the noisy image's %.5f" % (rms(denoised), rms(noisy)))
    return failures


def compare_scene(scene_name, tag, samples, odir):
    """Failures of Rendezvous' path tracer, BDPT and PSSMLT against Cycles on one scene."""
    scene = build_scenes.build(scene_name)
    bpy.context.view_layer.cycles.denoising_store_passes = True
    ref = render_passes(scene, "CYCLES", samples, os.path.join(odir, "%s_cycles.exr" % tag), PASSES)
    failures = []
    for integrator, n in (("PATH", samples), ("BDPT", samples // 2), ("PSSMLT", 4)):
        test = render_passes(scene, "RENDEZVOUS", n, os.path.join(odir, "%s_%s.exr" % (tag, integrator.lower())),
                             PASSES, integrator)
        label = integrator if tag == "denoising" else "%s %s" % (tag, integrator)
        if not all(np.isfinite(p).all() for p in test.values()):
            failures.append("%s: non-finite pixels" % label)
            continue
        for name, _ in PASSES:
            failures += compare(label, name, ref[name], test[name], blocks=integrator != "PSSMLT")
    return failures, scene


def check(a, odir, failures):
    found, scene = compare_scene("denoising_data", "denoising", a.samples, odir)
    failures += found
    failures += denoise_node_check(scene, odir)
    failures += compare_scene("denoising_fog", "fog", a.samples, odir)[0]


if __name__ == "__main__":
    run_test("DENOISING DATA", check, samples=256, needs_oiiotool=True)
