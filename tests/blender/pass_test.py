"""What the render-pass tests (test_light_passes, test_strategy_passes, test_data_passes,
test_denoising_data, test_shadow_catcher) share: a render saved as a 32-bit multilayer EXR and
read back pass by pass (oiiotool picks a pass's channels into an EXR of its own, which Blender
loads). Their main() is test_brightness.run_test (with needs_oiiotool), their comparison
with Cycles' image test_brightness.brightness_failures.
"""

import os
import subprocess
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
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
