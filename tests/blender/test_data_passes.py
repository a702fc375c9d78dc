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

import argparse
import os
import shutil
import subprocess
import sys
import traceback

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, compare, finish, out_dir  # noqa: E402
from test_light_passes import read_rgb  # noqa: E402
from test_light_paths import render as render_engine  # noqa: E402
import numpy as np  # noqa: E402

DATA = [("Mist", "Z"), ("IndexOB", "X"), ("IndexMA", "X")]


def read_data_passes(path, layer, odir, tag):
    """{pass name: H x W} from the multilayer EXR at path."""
    out = {}
    for name, chan in DATA:
        one = os.path.join(odir, "%s_%s.exr" % (tag, name))
        c = "%s.%s.%s" % (layer, name, chan)
        subprocess.run(["oiiotool", path, "--ch", ",".join([c] * 3), "--chnames", "R,G,B", "-d", "float", "-o", one],
                       check=True, capture_output=True)
        out[name] = read_rgb(one)[:, :, 0]
    return out


def render(scene, engine, samples, path, integrator="PATH"):
    render_engine(scene, engine, samples, path + ".single.exr", integrator)
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    bpy.data.images["Render Result"].save_render(path)
    return read_data_passes(path, bpy.context.view_layer.name, os.path.dirname(path), os.path.basename(path))


def uniform_pixels(index):
    """Pixels whose 5x5 neighbourhood holds one value (edges of the image left out)."""
    h, w = index.shape
    keep = np.zeros((h, w), bool)
    for y in range(2, h - 2):
        for x in range(2, w - 2):
            block = index[y - 2:y + 3, x - 2:x + 3]
            keep[y, x] = (block == block[0, 0]).all()
    return keep


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=256)
    a = ap.parse_args(argv)
    odir = out_dir()
    failures = []
    if not shutil.which("oiiotool"):
        finish("DATA PASSES", ["oiiotool (Debian's openimageio-tools) is needed to read the passes"], odir)
    try:
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
            ok_mean, ok_blocks, ratio = compare(label, r, t)
            if not ok_mean:
                failures.append("%s: mean ratio Rendezvous/Cycles = %.4f" % (label, ratio))
            if not ok_blocks and integrator != "PSSMLT":
                failures.append("%s: block means differ beyond noise" % label)
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
    except Exception as exc:
        traceback.print_exc()
        failures.append("data passes: %s" % exc)
    finish("DATA PASSES", failures, odir)


if __name__ == "__main__":
    main()
