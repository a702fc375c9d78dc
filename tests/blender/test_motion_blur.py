"""Motion blur (Render Properties > Motion Blur, Object > Motion Blur) agrees with Cycles: a
red square keyframed to slide across a grey floor under an area lamp (variant `square`:
shutter 1 frame, Position Center, the square moves 2.4 m while the shutter is open, 2.4 times
its width), and a static ball and floor seen from a keyframed camera that pans sideways
(variant `camera`: shutter 0.5, Position Start), and a square whose vertices shear across the
floor by a shape key (variant `deform`: deformation blur, shutter 1, Position Center), and a
smooth ball a shape key squashes and slides (variant `deform_smooth`: its vertex normals turn
over the shutter), the sheared square seen only through two collection instances (variant
`deform_instanced`: the copies share its deformation), two glowing planes lighting the floor, one keyframed to slide and one slid
by a shape key (variant `emitters`: emitters move with their light; variant `deform_warnings`:
a mesh whose faces change over the shutter renders without deformation blur, with a warning
naming it, and a deforming emitter is blurred without one). Cycles renders it, then Rendezvous' path
tracer and BDPT render the same scene in this process (the add-on samples the transforms at
Cycles' step times). Per integrator: image mean within 2% of Cycles', 8x8 blocks within 3% or
5 standard errors (test_brightness.check_setting). Cycles also renders the scene with motion
blur off, to show that motion blur changes the image (some lit 8x8 block by at least 5%).

    run_blender.py --script test_motion_blur.py -- VARIANT [VARIANT ...] [--samples N] [--verdicts DIR]
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, check_setting, out_dir, render_rendezvous, run_test  # noqa: E402

MIN_EFFECT = 0.05
FRAME = build_scenes.MOTION_FRAME  # the frame rendered


def build(variant):
    """The motion blur scene of a variant (scenes/blend/build_scenes.py: motion_<variant>)."""
    return build_scenes.build("motion_" + variant)


def check_deform_warnings(failures):
    """Deformation blur refused where it cannot be done, with a warning naming the object: a
    mesh whose face and vertex counts change over the shutter (a Build modifier); an emitting
    one deforms with its light, and the sheared square deforms: no warning names them."""
    from rendezvous.engine import final
    scene = build("deform")
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.4, location=(1.0, 0.0, 0.5), subdivisions=2)
    growing = bpy.context.object
    growing.name = "Growing"
    build_mod = growing.modifiers.new("Build", "BUILD")
    build_mod.frame_start, build_mod.frame_duration = 1, 4
    bpy.ops.mesh.primitive_plane_add(size=0.5, location=(0.0, 0.8, 1.5))
    glow = bpy.context.object
    glow.name = "Glow"
    m = bpy.data.materials.new("GlowMat")
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Emission"].default_value = (1.0, 1.0, 1.0, 1.0)
    m.node_tree.nodes["Principled BSDF"].inputs["Emission Strength"].default_value = 2.0
    glow.data.materials.append(m)
    build_scenes.shape_key_animation(glow, [(0.5, 0.0, 0.0)] * len(glow.data.vertices),
                                     [(FRAME - 1, 0.0), (FRAME + 1, 1.0)])
    scene.frame_set(FRAME)
    render_rendezvous(scene, 4, os.path.join(out_dir(), "motion_deform_warnings.exr"))
    msgs = final.last_render["messages"]
    for text in msgs:
        print("WARNING SEEN:", text)
    if not any("Object 'Growing'" in text and "without deformation blur" in text for text in msgs):
        failures.append("no warning naming Object 'Growing' (without deformation blur) in: %s" % msgs)
    for name in ("'Plane'", "'Glow'"):
        if any(name in text for text in msgs):
            failures.append("unexpected warning about %s: %s" % (name, msgs))


def check(a, odir, failures):
    if a.variant == "deform_warnings":
        check_deform_warnings(failures)
        return
    scene = build(a.variant)
    scene.render.use_motion_blur = False

    def apply():
        scene.render.use_motion_blur = True

    check_setting("MOTION BLUR", "motion_" + a.variant, scene, apply, a.samples, odir, failures, MIN_EFFECT)


if __name__ == "__main__":
    run_test("MOTION BLUR", check, samples=512, members="variant")
