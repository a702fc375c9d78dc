"""A Volume object from a .vdb file renders with Rendezvous under `blender -b --factory-startup`:

    run_blender.py --script test_volume.py -- --vdb-writer build/tests/blender/write_test_vdb

The test writes a ball of smoke (with empty tiles beside it) to a .vdb with write_test_vdb,
builds a scene with a Volume object reading it (Principled Volume material) in front of a
white world, and checks that the image is finite and the smoke is visible (the centre is
darker than the corners). Then a missing file: a warning naming the object, the render goes on.
"""

import argparse
import math
import os
import subprocess
import sys
import traceback

import bpy
import numpy as np

from rendezvous.engine import final  # noqa: E402

TMP = os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir


class Failure(AssertionError):
    pass


def check(cond, msg):
    if not cond:
        raise Failure(msg)


def build_scene(vdb_path):
    scene = bpy.context.scene
    for ob in list(scene.objects):
        if ob.type != "CAMERA":
            bpy.data.objects.remove(ob)
    cam = scene.camera
    cam.location = (0.0, -4.0, 0.0)
    cam.rotation_euler = (math.radians(90), 0.0, 0.0)
    scene.world.use_nodes = True
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bg.inputs["Strength"].default_value = 1.0

    vol = bpy.data.volumes.new("CloudData")
    vol.filepath = vdb_path
    ob = bpy.data.objects.new("Cloud", vol)
    ob.location = (0.0, 0.0, 0.0)
    ob.scale = (1.5, 1.5, 1.5)
    scene.collection.objects.link(ob)
    mat = bpy.data.materials.new("Smoke")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        if n.bl_idname != "ShaderNodeOutputMaterial":
            nodes.remove(n)
    pv = nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density"].default_value = 6.0
    pv.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1.0)
    mat.node_tree.links.new(pv.outputs["Volume"], nodes["Material Output"].inputs["Volume"])
    vol.materials.append(mat)
    scene.render.resolution_x = scene.render.resolution_y = 48
    scene.render.resolution_percentage = 100
    scene.render.engine = "RENDEZVOUS"
    scene.rendezvous.samples = 32
    scene.rendezvous.time_limit = 0.0
    return scene, ob


def render_pixels(scene, name):
    result = bpy.ops.render.render()
    check(result == {"FINISHED"}, "%s: render returned %s" % (name, result))
    path = os.path.join(TMP, name + ".exr")
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    bpy.data.images["Render Result"].save_render(path)
    im = bpy.data.images.load(path, check_existing=False)
    px = np.empty(im.size[0] * im.size[1] * 4, np.float32)
    im.pixels.foreach_get(px)
    shape = (im.size[1], im.size[0], 4)
    bpy.data.images.remove(im)
    return px.reshape(shape)[:, :, :3]


def centre_and_corners(px):
    h, w = px.shape[:2]
    centre = float(px[h * 3 // 8: h * 5 // 8, w * 3 // 8: w * 5 // 8].mean())
    corners = float(np.mean([px[:4, :4].mean(), px[:4, -4:].mean(), px[-4:, :4].mean(), px[-4:, -4:].mean()]))
    return centre, corners


def run(args):
    vdb = os.path.join(TMP, "rdv_cloud.vdb")
    subprocess.run([args.vdb_writer, vdb], check=True)
    scene, ob = build_scene(vdb)
    px = render_pixels(scene, "volume_object")
    msgs = final.last_render["messages"]
    for m in msgs:
        print("WARNING SEEN:", m)
    check(np.isfinite(px).all(), "non-finite pixels")
    centre, corners = centre_and_corners(px)
    print("VOLUME: centre %.4f corners %.4f" % (centre, corners))
    check(abs(corners - 1.0) < 0.05, "the white world should show in the corners (%.4f)" % corners)
    check(centre < 0.8 * corners, "the smoke is not visible (centre %.4f, corners %.4f)" % (centre, corners))
    check(not any("Cloud" in m for m in msgs), "unexpected warnings about the volume: %s" % msgs)

    # A missing file: a warning naming the object; the render goes on without it.
    ob.data.filepath = os.path.join(TMP, "no_such_cloud.vdb")
    px = render_pixels(scene, "volume_missing")
    msgs = final.last_render["messages"]
    for m in msgs:
        print("WARNING SEEN:", m)
    check(np.isfinite(px).all(), "non-finite pixels with a missing file")
    check(any("Cloud" in m for m in msgs), "no warning naming the volume object 'Cloud': %s" % msgs)
    centre, corners = centre_and_corners(px)
    check(abs(centre - corners) < 0.05, "a missing volume should leave the world visible (%.4f vs %.4f)"
          % (centre, corners))
    print("VOLUME TEST PASSED")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--vdb-writer", required=True)
    a = ap.parse_args(argv)
    try:
        run(a)
    except Exception:
        traceback.print_exc()
        print("TEST FAILED: volume_object")
        sys.exit(1)


main()
