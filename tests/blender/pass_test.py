"""What the render-pass tests (test_light_passes, test_strategy_passes, test_data_passes,
test_denoising_data, test_shadow_catcher) share: a render saved as a 32-bit multilayer EXR and
read back pass by pass (oiiotool picks a pass's channels into an EXR of its own, which Blender
loads), the comparison with Cycles' image that counts its failures, and main()'s argument
parsing, oiiotool check and verdict.
"""

import argparse
import os
import shutil
import subprocess
import sys
import traceback

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import compare, finish, out_dir  # noqa: E402
from test_light_paths import render as render_engine  # noqa: E402


def read_pass(exr, layer, name, chans):
    """One pass of the multilayer EXR `exr` as H x W x 3 floats (x 4 for four channels; a
    one-channel pass repeated in all three), rows from the top. The pass is written beside
    it as <exr>_<name>.exr on the way (kept for a look at a failure)."""
    cs = ["%s.%s.%s" % (layer, name, c) for c in chans]
    if len(cs) == 1:
        cs = cs * 3
    one = "%s_%s.exr" % (exr, name.replace(" ", "_"))
    subprocess.run(["oiiotool", exr, "--ch", ",".join(cs), "--chnames", ",".join("RGBA"[:len(cs)]), "-d", "float",
                    "-o", one], check=True, capture_output=True)
    im = bpy.data.images.load(one, check_existing=False)
    px = np.empty(im.size[0] * im.size[1] * 4, np.float32)
    im.pixels.foreach_get(px)
    shape = (im.size[1], im.size[0], 4)
    bpy.data.images.remove(im)
    return px.reshape(shape)[::-1, :, :len(cs)].astype(np.float64)


def render_passes(scene, engine, samples, path, passes, integrator="PATH"):
    """{pass name: pixels} of one render (test_light_paths.render: seed 1, Combined also saved
    as path + '.single.exr'), the Render Result saved as a multilayer EXR at path; passes:
    (name, channels) pairs, e.g. ("Combined", "RGBA"), ("Mist", "Z")."""
    render_engine(scene, engine, samples, path + ".single.exr", integrator)
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    bpy.data.images["Render Result"].save_render(path)
    layer = bpy.context.view_layer.name
    return {name: read_pass(path, layer, name, chans) for name, chans in passes}


def brightness_failures(label, ref, test, blocks=True):
    """test_brightness.compare of test against Cycles' ref (means within 2%, 8x8 blocks within
    3% or 5 standard errors; blocks=False: the mean only), as failure messages."""
    ok_mean, ok_blocks, ratio = compare(label, ref, test)
    failures = [] if ok_mean else ["%s: mean ratio Rendezvous/Cycles = %.4f" % (label, ratio)]
    if blocks and not ok_blocks:
        failures.append("%s: block means differ beyond noise" % label)
    return failures


def run(title, body, samples, add_arguments=None):
    """main() of a pass test: parses the arguments after '--' (--samples N, `samples` by
    default, and those add_arguments(parser) adds), needs oiiotool, calls
    body(args, odir, failures) and prints the verdict (exit 1 on failures or an exception)."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=samples)
    if add_arguments:
        add_arguments(ap)
    a = ap.parse_args(argv)
    odir = out_dir()
    failures = []
    if not shutil.which("oiiotool"):
        finish(title, ["oiiotool (Debian's openimageio-tools) is needed to read the passes"], odir)
    try:
        body(a, odir, failures)
    except Exception as exc:
        traceback.print_exc()
        failures.append("%s: %s (traceback above)" % (title.lower(), exc))
    finish(title, failures, odir)
