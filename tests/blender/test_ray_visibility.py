"""Ray visibility (Object > Visibility > Ray Visibility, a light object's, the world's) agrees
with Cycles: a red ball over a grey floor under an area lamp, in a dim world, with one setting
changed per variant. Cycles renders it, then Rendezvous' path tracer and BDPT render the
same scene in this process. Per integrator: image mean within 2% of Cycles', 8x8 blocks
within 3% or 5 standard errors (test_brightness.compare). The same scene with every object
seen by every ray is also rendered by Cycles, to show the setting changes the image (some
8x8 block brighter than a tenth of the image mean changes by at least 5%).

Variants: ball_camera (the ball hidden from the camera: its shadow and the light it bounces
stay), ball_diffuse (hidden from diffuse rays, lit from below by a lamp facing up: the floor
around it loses the light it bounced), ball_shadow (casts
no shadow), ball_glossy (a glossy floor does not reflect it; not in ctest: where the floor's
reflection of the lamp passes through the ball, Cycles mixes its blocked shadow ray and its
unblocked glossy ray by their MIS weights and we block it, docs/scene-format.md),
ball_transmission (a pane of smooth glass between the camera and the ball, hidden from shadow
and diffuse rays: seen through it the ball is gone, the floor behind it shows), lamp_camera (an area lamp in view
with visible_camera on: Cycles 3.4 shows it), lamp_diffuse (the lamp lights no diffuse
surface: the world alone lights the scene), world_camera (the world hidden from the camera:
black background, the world still lights the scene).

    run_blender.py --script test_ray_visibility.py -- VARIANT [VARIANT ...] [--samples N] [--verdicts DIR]
"""

import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, check_setting, run_test  # noqa: E402

MIN_EFFECT = 0.05
SIZE = 48


def material(name, bsdf, color, roughness=None):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes = m.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    b = nodes.new(bsdf)
    b.inputs["Color"].default_value = (*color, 1.0)
    if roughness is not None:
        b.inputs["Roughness"].default_value = roughness
    if bsdf == "ShaderNodeBsdfGlossy":
        b.distribution = "GGX"
    m.node_tree.links.new(b.outputs[0], out.inputs["Surface"])
    return m


def build(variant):
    """The scene of `variant` with its setting not yet applied; returns (scene, apply)."""
    scene = build_scenes.reset(SIZE)
    scene.cycles.filter_glossy = 0.0  # Rendezvous does not blur caustics (the ball lit by the floor's reflection)
    world = scene.world
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (
        (0.3, 0.35, 0.45, 1.0) if variant in ("world_camera", "lamp_diffuse") else (0.08, 0.09, 0.1, 1.0))

    glossy_floor = variant == "ball_glossy"
    floor_mat = (material("Floor", "ShaderNodeBsdfGlossy", (0.8, 0.8, 0.8), 0.2) if glossy_floor
                 else material("Floor", "ShaderNodeBsdfDiffuse", (0.7, 0.7, 0.7)))
    bpy.ops.mesh.primitive_plane_add(size=5, location=(0, 0, 0))
    floor = bpy.context.object
    floor.data.materials.append(floor_mat)
    ball = build_scenes.uv_sphere(radius=0.6, location=(0, 0, 0.7), segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(material("Ball", "ShaderNodeBsdfDiffuse", (0.8, 0.2, 0.2)))

    lamp_data = bpy.data.lights.new("Lamp", "AREA")
    lamp_data.energy = 150
    lamp_data.size = 0.6
    lamp = bpy.data.objects.new("Lamp", lamp_data)
    lamp.location = (0.8, -0.3, 2.6)
    scene.collection.objects.link(lamp)
    if variant == "ball_diffuse":  # under the ball, facing up: the floor sees only what the ball bounces
        lamp.location = (0, 0, 0.12)
        lamp.rotation_euler = (math.pi, 0, 0)
        ball.location = (0, 0, 1.0)
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    if variant == "ball_transmission":  # a glass pane in front of the ball: rays through it are transmission rays
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, -1.4, 0.75))
        pane = bpy.context.object
        pane.scale = (1.8, 0.08, 1.4)
        glass = material("Pane", "ShaderNodeBsdfGlass", (1.0, 1.0, 1.0), 0.0)
        next(n for n in glass.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfGlass").distribution = "SHARP"
        pane.data.materials.append(glass)
        # No shadow and nothing for diffuse bounces: the floor is lit as without the pane (no
        # caustic of the lamp through or off it, which only Filter Glossy's blur would tame).
        pane.visible_shadow = False
        pane.visible_diffuse = False
    if variant == "lamp_camera":  # in view, facing the camera, 45 degrees up
        lamp.location = (-1.2, 0.8, 1.4)
        build_scenes.look_at(lamp, (0, -4.2, 2.8))

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 35
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = (0, -4.2, 2.8)
    build_scenes.look_at(cam, (0, 0, 0.5))
    scene.collection.objects.link(cam)
    scene.camera = cam

    # What each variant sets: (owner, property, value).
    settings = {"ball_camera": (ball, "visible_camera", False), "ball_diffuse": (ball, "visible_diffuse", False),
                "ball_shadow": (ball, "visible_shadow", False), "ball_glossy": (ball, "visible_glossy", False),
                "ball_transmission": (ball, "visible_transmission", False),
                "lamp_camera": (lamp, "visible_camera", True), "lamp_diffuse": (lamp, "visible_diffuse", False),
                "world_camera": (world.cycles_visibility, "camera", False)}
    if variant not in settings:
        raise ValueError("unknown variant %r" % variant)
    owner, prop, value = settings[variant]

    def apply():
        setattr(owner, prop, value)

    return scene, apply


def check(a, odir, failures):
    scene, apply = build(a.variant)
    check_setting("RAY VISIBILITY", a.variant, scene, apply, a.samples, odir, failures, MIN_EFFECT)


if __name__ == "__main__":
    run_test("RAY VISIBILITY", check, samples=512, members="variant")
