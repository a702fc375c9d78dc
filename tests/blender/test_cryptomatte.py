"""Cryptomatte against Cycles: build_scenes.cryptomatte (48x48: two balls sharing a material,
a cube parented to the first ball, a cone without a material, a floor, a card 70% opaque in
front of the first ball; View Layer > Passes > Cryptomatte Object, Material and Asset at 6
levels) rendered by Cycles, then by Rendezvous' path tracer, BDPT and PSSMLT in this process,
each saved as a multilayer EXR and read back.

Per integrator:
- the metadata as Cycles writes it: each kind's layer key and name (cryptomatte/<key>/name),
  hash and conversion; the Object and Asset manifests equal to Cycles'; every name of the
  Material manifest in Cycles' (Cycles also lists its built-in shaders);
- each id's coverage (its weight summed over the ranks, for every name of Cycles' manifests):
  the image means within 5 standard errors, each pixel's variance bounded by c (1 - c) / n for
  its coverage c of n samples (a coverage sample lies in [0, 1]; false alarm < 1e-6 per
  comparison, fewer with stratified samples), and 8x8 blocks as test_brightness.compare
  (within 3% or 5 standard errors); the card's 0.7 and the ball's 0.3 behind it included.
  PSSMLT's passes come from its first-hit pass, 16 rays a pixel at 128 mutations;
- rank 0's id equal to Cycles' on every pixel where both give it at least 95% of the pixel;
- the compositor's Cryptomatte node (Render source, matte "Ball, Cube" by name) on the
  render gives the matte it gives on Cycles' (test_brightness.compare of the Matte output).

    run_blender.py --script test_cryptomatte.py -- [--samples N]
"""

import os
import re
import subprocess
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import brightness_failures, build_scenes, compare, read_render, run_test  # noqa: E402
from test_light_paths import render as render_engine  # noqa: E402
from pass_test import render_passes  # noqa: E402

KINDS = ("CryptoObject", "CryptoMaterial", "CryptoAsset")
PASSES = [("%s%02d" % (kind, k), "RGBA") for kind in KINDS for k in range(3)]
MATTE = "Ball, Cube"


def metadata(exr):
    """{key: value} of the EXR's cryptomatte/... header attributes (oiiotool --info -v)."""
    text = subprocess.run(["oiiotool", "--info", "-v", exr], check=True, capture_output=True, text=True).stdout
    return {m.group(1): m.group(2) for m in re.finditer(r'^\s*(cryptomatte/[0-9a-f]{7}/\w+): "(.*)"$', text, re.M)}


def id_float(hex_hash):
    """A manifest's hash (8 hex digits) as the float id the passes hold (Cycles' hash_to_float)."""
    h = int(hex_hash, 16)
    exponent = min(max((h >> 23) & 0xFF, 1), 254)
    return float(np.array([(h & 0x807FFFFF) | (exponent << 23)], np.uint32).view(np.float32)[0])


def coverage(passes, kind, id_value):
    """H x W x 3: the id's weight over the kind's ranks (each pass: id, coverage, id, coverage)."""
    total = 0.0
    for k in range(3):
        p = passes["%s%02d" % (kind, k)]
        total = total + np.where(p[:, :, 0] == id_value, p[:, :, 1], 0.0) + np.where(p[:, :, 2] == id_value, p[:, :, 3], 0.0)
    return np.repeat(total[:, :, None], 3, 2)


def coverage_failures(label, ref, n_ref, test, n_test, blocks=True):
    """Coverage maps (H x W x 3, equal channels) of n_ref and n_test samples a pixel: the means
    within 5 standard errors of the bound above, and the 8x8 blocks as compare()."""
    c_ref, c_test = ref[:, :, 0], test[:, :, 0]
    se = np.sqrt((c_ref * (1 - c_ref)).sum() / n_ref + (c_test * (1 - c_test)).sum() / n_test) / c_ref.size
    difference = abs(c_test.mean() - c_ref.mean())
    print("  %s: mean %.5f, Cycles' %.5f, %.1f standard errors" % (label, c_test.mean(), c_ref.mean(),
                                                                  difference / max(se, 1e-12)))
    failures = [] if difference <= 5 * se + 1e-6 else ["%s: mean %.5f, Cycles' %.5f" % (label, c_test.mean(), c_ref.mean())]
    if blocks and not compare(label, ref, test)[1]:
        failures.append("%s: block means differ beyond noise" % label)
    return failures


def compositor_matte(scene, engine, samples, path, integrator="PATH"):
    """The compositor's Cryptomatte node (Render source, MATTE picked by name) on a render."""
    scene.use_nodes = True
    nodes, links = scene.node_tree.nodes, scene.node_tree.links
    nodes.clear()
    layers = nodes.new("CompositorNodeRLayers")
    layers.scene = scene
    matte = nodes.new("CompositorNodeCryptomatteV2")
    matte.source = "RENDER"
    matte.scene = scene
    matte.layer_name = "%s.CryptoObject" % bpy.context.view_layer.name
    matte.matte_id = MATTE
    out = nodes.new("CompositorNodeComposite")
    links.new(layers.outputs["Image"], matte.inputs["Image"])
    links.new(matte.outputs["Matte"], out.inputs["Image"])
    scene.render.use_compositing = True
    try:
        render_engine(scene, engine, samples, path + ".unused.exr", integrator)
        return read_render(scene, path)
    finally:
        scene.use_nodes = False


def check(a, odir, failures):
    scene = build_scenes.build("cryptomatte")
    path = os.path.join(odir, "cryptomatte_cycles.exr")
    ref = render_passes(scene, "CYCLES", a.samples, path, PASSES)
    ref_meta = metadata(path)
    manifests = {v: json_manifest(ref_meta[k.replace("/name", "/manifest")]) for k, v in ref_meta.items()
                 if k.endswith("/name")}
    layer = bpy.context.view_layer.name
    ref_matte = compositor_matte(scene, "CYCLES", a.samples, os.path.join(odir, "cryptomatte_matte_cycles.exr"))
    if ref_matte.mean() < 0.02:
        failures.append("Cycles' Cryptomatte node gives no matte for %s (mean %.4f)" % (MATTE, ref_matte.mean()))
    # (integrator, samples, camera rays a pixel of its passes)
    for integrator, samples, rays in (("PATH", a.samples, a.samples), ("BDPT", a.samples // 2, a.samples // 2),
                                      ("PSSMLT", 128, 16)):
        path = os.path.join(odir, "cryptomatte_%s.exr" % integrator.lower())
        test = render_passes(scene, "RENDEZVOUS", samples, path, PASSES, integrator)
        if not all(np.isfinite(p).all() for p in test.values()):
            failures.append("%s: non-finite pixels" % integrator)
            continue
        meta = metadata(path)
        for key, value in ref_meta.items():
            if key.endswith("/manifest"):
                continue
            if meta.get(key) != value:
                failures.append("%s: metadata %s is %r, Cycles' %r" % (integrator, key, meta.get(key), value))
        for kind in KINDS:
            name = "%s.%s" % (layer, kind)
            key = next((k for k, v in meta.items() if k.endswith("/name") and v == name), None)
            ours = json_manifest(meta.get(key.replace("/name", "/manifest"), "{}")) if key else {}
            theirs = manifests.get(name, {})
            if kind == "CryptoMaterial" and not set(ours) <= set(theirs):
                failures.append("%s: materials %s not in Cycles' manifest" % (integrator, sorted(set(ours) - set(theirs))))
            elif kind != "CryptoMaterial" and ours != theirs:
                failures.append("%s: %s manifest %s, Cycles' %s" % (integrator, kind, ours, theirs))
            for object_name, hex_hash in sorted(theirs.items()):
                c_ref = coverage(ref, kind, id_float(hex_hash))
                if c_ref.max() <= 0:
                    continue  # not seen (Cycles' built-in shaders)
                c_test = coverage(test, kind, id_float(hex_hash))
                failures += coverage_failures("%s %s '%s' coverage" % (integrator, kind, object_name), c_ref,
                                              a.samples, c_test, rays)
            rank0_ref, rank0_test = ref["%s00" % kind], test["%s00" % kind]
            solid = (rank0_ref[:, :, 1] >= 0.95) & (rank0_test[:, :, 1] >= 0.95)
            wrong = int(np.count_nonzero(solid & (rank0_ref[:, :, 0] != rank0_test[:, :, 0])))
            if wrong or not solid.any():
                failures.append("%s: %s rank 0 differs from Cycles' on %d of %d solid pixels"
                                % (integrator, kind, wrong, int(np.count_nonzero(solid))))
        matte = compositor_matte(scene, "RENDEZVOUS", samples, os.path.join(odir, "cryptomatte_matte_%s.exr"
                                                                            % integrator.lower()), integrator)
        failures += coverage_failures("%s Cryptomatte node matte" % integrator, ref_matte, a.samples, matte, rays)


def json_manifest(text):
    import json
    return json.loads(text.replace('\\"', '"')) if text else {}


if __name__ == "__main__":
    run_test("CRYPTOMATTE", check, samples=64, needs_oiiotool=True)
