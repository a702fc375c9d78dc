"""Benchmark (label bench, not part of CI): what motion blur costs, against Cycles 3.4 at equal
samples. A floor and 24 balls under an area lamp, 192x192, 64 samples per pixel:
  static: nothing animated; Rendezvous path / BDPT with Render Properties > Motion Blur off and
          on (goal: no cost; the add-on samples nothing, the engine draws no time);
  moving: 12 of the balls keyframed to slide and the camera to pan (Cycles' default Steps 1:
          3 transforms each), motion blur off and on, Rendezvous path / BDPT and Cycles.
  deforming: the camera still, 12 of the balls sheared by a keyframed shape key (deformation
          blur: their vertices move, 3 steps each), motion blur off and on, Rendezvous path /
          BDPT and Cycles.
Each figure is the median of 3 renders (wall time of bpy.ops.render.render, export included),
renders of A and B alternated; the ratio on / off is what motion blur costs each renderer.

    python3 run_blender.py --lib build/engine/librendezvous.so --script bench_motion_blur.py [-- CASE ...]

CASE: static, moving, deforming (default: all three).
"""

import os
import statistics
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, out_dir, render_cycles, render_rendezvous  # noqa: E402

SIZE = 192
SAMPLES = 64
RUNS = 3


def build(moving, deforming=False):
    scene = build_scenes.reset(SIZE)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.08, 0.09, 0.1, 1.0)
    bpy.ops.mesh.primitive_plane_add(size=12, location=(0, 0, 0))
    for i in range(24):
        x, y = -3.0 + (i % 6) * 1.2, -1.0 + (i // 6) * 1.2
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.4, location=(x, y, 0.4), segments=32, ring_count=16)
        ball = bpy.context.object
        if deforming and i % 2 == 0:  # the top slides 1.2 m between frames 1 and 3, the bottom stays
            offsets = [(1.2 * (v.co.z + 0.4) / 0.8, 0.0, 0.0) for v in ball.data.vertices]
            build_scenes.shape_key_animation(ball, offsets, [(1, 0.0), (3, 1.0)])
        if moving and i % 2 == 0:
            for frame, dx in ((1, -0.6), (3, 0.6)):
                ball.location = (x + dx, y, 0.4)
                ball.keyframe_insert("location", frame=frame)
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "AREA"))
    lamp.data.energy = 600
    lamp.data.size = 2.0
    lamp.location = (0, -1, 5)
    scene.collection.objects.link(lamp)
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    cam.data.lens = 30
    cam.location = (0, -8, 4.5)
    build_scenes.look_at(cam, (0, 0.5, 0.3))
    scene.collection.objects.link(cam)
    scene.camera = cam
    if moving:
        for frame, dx in ((1, -0.3), (3, 0.3)):
            cam.location = (dx, -8, 4.5)
            cam.keyframe_insert("location", frame=frame)
        build_scenes.look_at(cam, (0, 0.5, 0.3))
    scene.frame_set(2)
    scene.render.motion_blur_shutter = 0.5
    return scene


def render_time(scene, engine, integrator, motion_blur):
    """Seconds of bpy.ops.render.render (export included; reading the image back is not)."""
    scene.render.use_motion_blur = motion_blur
    path = os.path.join(out_dir(), "bench_motion.exr")
    if engine == "CYCLES":
        return render_cycles(scene, SAMPLES, path)[1]
    return render_rendezvous(scene, SAMPLES, path, integrator)[1]


def compare(scene, label, engine, integrator=None):
    off, on = [], []
    for _ in range(RUNS):  # alternated, so a slow spell of the machine hits both
        off.append(render_time(scene, engine, integrator, False))
        on.append(render_time(scene, engine, integrator, True))
    a, b = statistics.median(off), statistics.median(on)
    print("BENCH motion blur %-28s off %.3f s  on %.3f s  on/off %.3f" % (label, a, b, b / a))
    return a, b


def against_cycles(scene, case):
    results = {}
    for integrator in ("PATH", "BDPT"):
        results[integrator] = compare(scene, "%s, Rendezvous %s" % (case, integrator.lower()), "RENDEZVOUS",
                                      integrator)
    results["CYCLES"] = compare(scene, case + ", Cycles", "CYCLES")
    print("BENCH motion blur: %s scene with motion blur, Rendezvous path / Cycles %.3f, bdpt / Cycles %.3f"
          % (case, results["PATH"][1] / results["CYCLES"][1], results["BDPT"][1] / results["CYCLES"][1]))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    cases = argv or ["static", "moving", "deforming"]
    print("BENCH motion blur: %dx%d, %d spp, median of %d" % (SIZE, SIZE, SAMPLES, RUNS))
    if "static" in cases:
        scene = build(moving=False)
        for integrator in ("PATH", "BDPT"):
            compare(scene, "static, Rendezvous " + integrator.lower(), "RENDEZVOUS", integrator)
    if "moving" in cases:
        against_cycles(build(moving=True), "moving")
    if "deforming" in cases:
        against_cycles(build(moving=False, deforming=True), "deforming")


main()
