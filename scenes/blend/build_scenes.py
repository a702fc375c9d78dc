"""Builds the Blender test scenes (Cycles scenes that Rendezvous must render like Cycles).

Inside Blender:
    import build_scenes; build_scenes.build("plane_point")      # replaces the current scene's content
Save them all as .blend files:
    blender -b --factory-startup --python scenes/blend/build_scenes.py -- --out DIR [NAME ...]

Every scene is small (64x64 by default) so tests stay fast.
"""

import math
import os
import sys

import bpy

RES = 64


# ---- helpers ------------------------------------------------------------------------------
def reset(res=RES):
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.lights, bpy.data.cameras, bpy.data.materials, bpy.data.images,
                 bpy.data.node_groups, bpy.data.worlds, bpy.data.particles):
        for block in list(coll):
            if getattr(block, "type", None) == "RENDER_RESULT":
                continue
            coll.remove(block)
    for c in list(bpy.data.collections):
        bpy.data.collections.remove(c)
    scene = bpy.context.scene
    scene.render.resolution_x = res
    scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    scene.render.use_border = False
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world
    return scene


def remove_shader_aovs():
    """The view layer's Shader AOVs (shader_aovs adds them) taken away, so that a scene built
    after it in the same process has none (ViewLayer.aovs has no remove()). Not in reset: the
    Cycles references key on the code the scenes run (tests/blender/cycles_reference.py)."""
    layer = bpy.context.view_layer
    while len(layer.aovs):
        layer.active_aov_index = len(layer.aovs) - 1
        bpy.ops.scene.view_layer_remove_aov()


def link(ob):
    bpy.context.scene.collection.objects.link(ob)
    return ob


def empty_material(name):
    """A node material with nothing but its Material Output: (material, tree, output)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    return m, nt, nt.nodes.new("ShaderNodeOutputMaterial")


def add_node(nt, idname, inputs=(), **props):
    """A new node in tree nt with its input sockets' values from `inputs` (a dict) and its
    properties (wave_type, space, ...) from props."""
    node = nt.nodes.new(idname)
    for k, v in dict(inputs).items():
        node.inputs[k].default_value = v
    for k, v in props.items():
        setattr(node, k, v)
    return node


def shader_material(name, shader, inputs):
    """empty_material with one shader node of type `shader`, its inputs set from `inputs` (not
    linked yet): (material, tree, output, shader node)."""
    m, nt, out = empty_material(name)
    return m, nt, out, add_node(nt, shader, inputs)


def node_material(name, node_type, inputs, output="BSDF", **props):
    """A material of one stock shader node (its inputs by name, its properties) into the output."""
    m, nt, out = empty_material(name)
    node = nt.nodes.new(node_type)
    for k, v in props.items():
        setattr(node, k, v)
    for k, v in inputs.items():
        node.inputs[k].default_value = v
    nt.links.new(node.outputs[output], out.inputs["Surface"])
    return m


def diffuse_material(name, color=(0.8, 0.8, 0.8)):
    return node_material(name, "ShaderNodeBsdfDiffuse", {"Color": (*color, 1.0)})


def emission_material(name, color=(1.0, 1.0, 1.0), strength=1.0):
    return node_material(name, "ShaderNodeEmission", {"Color": (*color, 1.0), "Strength": strength}, "Emission")


def canonical_face_order(ob):
    """Sorts the mesh's faces by their vertices. Blender's mesh primitives (the UV sphere, the
    cylinder) list their faces in an order that changes from one Blender process to the next
    (their bmesh operators hash pointers). The triangles' order picks which triangle a random
    number lands on (an emissive sphere's lamp samples, BVH ties), so without this, a test's
    Monte Carlo outcome changed from run to run with nothing else changed."""
    import bmesh
    bm = bmesh.new()
    bm.from_mesh(ob.data)
    nv = len(bm.verts) + 1

    def key(face):  # the face's vertex indices, sorted, as one number (bmesh sorts by a number)
        k = 0.0
        for i in sorted(v.index for v in face.verts) + [-1] * max(0, 4 - len(face.verts)):
            k = k * nv + i + 1
        return k
    bm.faces.sort(key=key)
    bm.to_mesh(ob.data)
    bm.free()
    return ob


def uv_sphere(**op_args):
    """bpy.ops.mesh.primitive_uv_sphere_add(**op_args), its faces in a fixed order; the object."""
    bpy.ops.mesh.primitive_uv_sphere_add(**op_args)
    return canonical_face_order(bpy.context.active_object)


def quad_mesh(name, size_x, size_y=None):
    size_y = size_x if size_y is None else size_y
    me = bpy.data.meshes.new(name)
    hx, hy = size_x / 2, size_y / 2
    me.from_pydata([(-hx, -hy, 0), (hx, -hy, 0), (hx, hy, 0), (-hx, hy, 0)], [], [(0, 1, 2, 3)])
    me.update()
    return me


def shape_key_animation(ob, key_offsets, frames):
    """Deforms a mesh object by a shape key: key_offsets (one (dx, dy, dz) per vertex, in the
    object's space) scaled by the key's value, keyframed linearly through (frame, value)
    pairs. For deformation motion blur: the vertices move while the transform stays."""
    ob.shape_key_add(name="Basis")
    key = ob.shape_key_add(name="Deform")
    for point, offset in zip(key.data, key_offsets):
        point.co = [c + d for c, d in zip(point.co, offset)]
    for frame, value in frames:
        key.value = value
        key.keyframe_insert("value", frame=frame)
    for fc in ob.data.shape_keys.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"
    return key


def plane(name="Floor", size=20.0, material=None, location=(0, 0, 0)):
    ob = link(bpy.data.objects.new(name, quad_mesh(name + "Mesh", size)))
    ob.location = location
    ob.data.materials.append(material or diffuse_material(name + "Mat"))
    return ob


def quad_object(name, size_x, size_y, location, rotation, material):
    """A quad (size_x by size_y) placed at location, rotated by Euler angles in degrees."""
    ob = link(bpy.data.objects.new(name, quad_mesh(name + "Mesh", size_x, size_y)))
    ob.location = location
    ob.rotation_euler = tuple(math.radians(a) for a in rotation)
    ob.data.materials.append(material)
    return ob


def camera_down(height=3.0, lens=50.0, location=(0.0, 0.0)):
    cam = bpy.data.cameras.new("Camera")
    cam.lens = lens
    cam.clip_start = 0.05
    cam.clip_end = 100.0
    ob = link(bpy.data.objects.new("Camera", cam))
    ob.location = (location[0], location[1], height)
    ob.rotation_euler = (0.0, 0.0, 0.0)  # looks down -Z
    bpy.context.scene.camera = ob
    return ob


def light(kind, name, energy, location, rotation=(0.0, 0.0, 0.0), **props):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    for k, v in props.items():
        setattr(data, k, v)
    ob = link(bpy.data.objects.new(name, data))
    ob.location = location
    ob.rotation_euler = rotation
    return ob


# ---- scenes -------------------------------------------------------------------------------
def plane_point():
    reset()
    plane()
    camera_down(3.0)
    light("POINT", "Point", 100.0, (0.3, 0.2, 1.5), shadow_soft_size=0.1)


def plane_spot():
    reset()
    plane()
    camera_down(3.0)
    light("SPOT", "Spot", 300.0, (0.0, 0.0, 2.0), rotation=(math.radians(10), 0, 0),
          spot_size=math.radians(40.0), spot_blend=0.3, shadow_soft_size=0.05)


def plane_sun():
    reset()
    plane()
    camera_down(3.0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(30), 0, math.radians(20)), angle=math.radians(1.0))


def plane_area(floor_material=None):
    """floor_material: a function making the floor's material (after the reset)."""
    reset()
    plane(material=floor_material() if floor_material else None)
    camera_down(3.0)
    light("AREA", "Area", 60.0, (0.0, 0.0, 1.2), rotation=(math.radians(15), 0, 0), shape="RECTANGLE",
          size=0.8, size_y=0.4)


def plane_area_disk_scaled():
    reset()
    plane()
    camera_down(3.0)
    ob = light("AREA", "AreaDisk", 40.0, (0.2, 0.0, 1.0), shape="DISK", size=0.5)
    ob.scale = (2.0, 1.0, 1.0)


def world_color():
    scene = reset()
    plane()
    cam = camera_down(3.0, lens=20.0)
    cam.rotation_euler = (math.radians(60), 0, 0)  # sees the floor and the sky
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.2, 0.3, 0.5, 1.0)
    bg.inputs["Strength"].default_value = 1.5


def emissive_mesh(panel_material=None):
    """panel_material: a function making the panel's material (after the reset)."""
    reset()
    plane()
    camera_down(4.0, lens=35.0)
    panel = link(bpy.data.objects.new("Panel", quad_mesh("PanelMesh", 1.0, 0.6)))
    panel.location = (0.4, 0.0, 1.0)
    panel.rotation_euler = (math.radians(180), 0, 0)  # faces down (both faces emit anyway)
    panel.data.materials.append(panel_material() if panel_material else emission_material("Glow", (1.0, 0.8, 0.6), 5.0))


def principled_floor():
    m = bpy.data.materials.new("PrincipledFloor")
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0.8, 0.45, 0.25, 1.0)
    p.inputs["Roughness"].default_value = 0.35
    p.inputs["Specular"].default_value = 0.5
    return m


def principled_plane():
    """plane_area with a Principled floor: diffuse plus a rough specular highlight."""
    plane_area(principled_floor)


def grazing_gloss():
    """Rough gloss lit and seen at about 9 degrees of elevation by a point lamp, four strips: a
    Principled specular (roughness 0.8, black base), a Principled clearcoat (0.3, Specular 0), a
    Glossy BSDF (0.8) and a Principled glass (transmission 1, roughness 0.5). There Cycles 3.4's
    separable GGX shadowing G1 G1 is 0.6 of the height-correlated form's, its clearcoat's GTR1
    spreads a wide glow, and its glass splits reflection from refraction by the Fresnel at the
    shading normal (our images were 1.50x, 3.13x, 1.0x and 0.79x Cycles' before we did so)."""
    reset()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 64, 48

    def principled(name, **inputs):
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        p = m.node_tree.nodes["Principled BSDF"]
        for k, v in inputs.items():
            p.inputs[k.replace("_", " ")].default_value = v
        return m
    black = (0.0, 0.0, 0.0, 1.0)
    strips = [principled("GrazingSpecular", Base_Color=black, Roughness=0.8),
              principled("GrazingCoat", Base_Color=black, Specular=0.0, Clearcoat=1.0, Clearcoat_Roughness=0.3),
              glossy_material("GrazingGlossy", 0.8),
              principled("GrazingGlass", Base_Color=(1.0, 1.0, 1.0, 1.0), Transmission=1.0, Roughness=0.5)]
    for i, m in enumerate(strips):
        quad_object(m.name + "Strip", 1.0, 4.0, (-1.5 + i, 0.0, 0.0), (0, 0, 0), m)
    camera_looking_at((0.0, -4.0, 0.6), (0.0, 0.0, 0.0), 35.0)
    light("POINT", "Lamp", 400.0, (0.0, 3.0, 0.5), shadow_soft_size=0.0)


def noise_texture():
    """Three strips emitting a Noise Texture's Color (Scale 1.5, Detail 2, Distortion 0.5), 2D, 3D
    and 4D (W 0.37), seen from above, the strips filling the view: Blender's pattern, block for
    block (a Perlin noise of our own, as we had before 2026-11-29, has the statistics but not
    the pattern)."""
    reset()
    for i, dims in enumerate(("2D", "3D", "4D")):
        m = emission_material("NoiseGlow" + dims, strength=1.0)
        nt = m.node_tree
        tex = nt.nodes.new("ShaderNodeTexNoise")
        tex.noise_dimensions = dims
        tex.inputs["Scale"].default_value = 1.5
        tex.inputs["Distortion"].default_value = 0.5
        tex.inputs["W"].default_value = 0.37
        nt.links.new(tex.outputs["Color"], nt.nodes["Emission"].inputs["Color"])
        quad_object("Noise" + dims, 1.0, 4.0, (-1.0 + i, 0.0, 0.0), (0, 0, 0), m)
    camera_down(4.0)


def emission_tiles(tiles, source=None, rows=2):
    """Tiles of emission planes (1 unit, 32 px, four to a row) seen from above, for the tests
    of shader nodes against Cycles: tiles lists (name, build); build(nt, src) returns the
    socket the tile emits as its colour, src the socket source(nt) made (None without)."""
    scene = reset(128)
    scene.render.resolution_y = 32 * rows
    for i, (name, build) in enumerate(tiles):
        m = emission_material(name + "Glow", strength=1.0)
        nt = m.node_tree
        nt.links.new(build(nt, source(nt) if source else None), nt.nodes["Emission"].inputs["Color"])
        quad_object(name, 1.0, 1.0, (-1.5 + i % 4, (rows - 1) / 2 - i // 4, 0.0), (0, 0, 0), m)
    camera_down(4.0 * 50.0 / 36.0)


def noise_source(nt):
    """A Noise Texture (Scale 3) for a tile to build on."""
    noise = nt.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 3.0
    return noise


def procedural_textures():
    """Twelve tiles, each emitting one of Blender's procedural textures (Voronoi's features,
    dimensions and metrics, Musgrave's types, Wave, Magic, Brick, White Noise per Voronoi cell),
    seen from above: Blender's patterns block for block. Each tile's emission is kept positive
    (Musgrave's heights through a Map Range)."""
    tiles = []

    def tile(name, idname, output, props=(), inputs=(), chain=None):
        def build(nt, _):
            tex = nt.nodes.new(idname)
            for k, v in props:
                setattr(tex, k, v)
            for k, v in inputs:
                tex.inputs[k].default_value = v
            out = tex.outputs[output]
            return chain(nt, tex, out) if chain else out
        tiles.append((name, build))

    def map_range(lo, hi):
        def chain(nt, tex, out):
            r = nt.nodes.new("ShaderNodeMapRange")
            r.inputs["From Min"].default_value, r.inputs["From Max"].default_value = lo, hi
            nt.links.new(out, r.inputs["Value"])
            return r.outputs["Result"]
        return chain

    def per_cell_white_noise(nt, tex, out):
        w = nt.nodes.new("ShaderNodeTexWhiteNoise")
        nt.links.new(out, w.inputs["Vector"])
        return w.outputs["Color"]

    tile("VoronoiF1", "ShaderNodeTexVoronoi", "Color", inputs=(("Scale", 4.0),))
    tile("VoronoiSmooth2D", "ShaderNodeTexVoronoi", "Distance",
         (("voronoi_dimensions", "2D"), ("feature", "SMOOTH_F1"), ("distance", "CHEBYCHEV")),
         (("Scale", 5.0), ("Smoothness", 0.6)))
    tile("VoronoiEdge4D", "ShaderNodeTexVoronoi", "Distance",
         (("voronoi_dimensions", "4D"), ("feature", "DISTANCE_TO_EDGE")), (("Scale", 4.0), ("W", 0.3)))
    tile("VoronoiF2Minkowski", "ShaderNodeTexVoronoi", "Distance",
         (("feature", "F2"), ("distance", "MINKOWSKI")), (("Scale", 3.0), ("Exponent", 1.5), ("Randomness", 0.8)))
    tile("MusgraveRidged", "ShaderNodeTexMusgrave", "Fac", (("musgrave_type", "RIDGED_MULTIFRACTAL"),),
         (("Scale", 3.0), ("Detail", 4.0), ("Offset", 1.0), ("Gain", 2.0)), map_range(0.0, 3.0))
    tile("MusgraveFbm4D", "ShaderNodeTexMusgrave", "Fac", (("musgrave_dimensions", "4D"),),
         (("Scale", 3.0), ("Detail", 3.5), ("W", 0.6)), map_range(-1.5, 1.5))
    tile("MusgraveHybrid2D", "ShaderNodeTexMusgrave", "Fac",
         (("musgrave_dimensions", "2D"), ("musgrave_type", "HYBRID_MULTIFRACTAL")),
         (("Scale", 3.0), ("Detail", 2.5), ("Offset", 0.8), ("Gain", 1.5)), map_range(0.0, 3.0))
    tile("WaveRings", "ShaderNodeTexWave", "Color",
         (("wave_type", "RINGS"), ("rings_direction", "SPHERICAL"), ("wave_profile", "SAW")),
         (("Scale", 1.5), ("Distortion", 4.0), ("Detail", 3.0), ("Detail Scale", 2.0)))
    tile("WaveBands", "ShaderNodeTexWave", "Fac", (("bands_direction", "DIAGONAL"), ("wave_profile", "TRI")),
         (("Scale", 2.0), ("Phase Offset", 1.0)))
    tile("Magic", "ShaderNodeTexMagic", "Color", (("turbulence_depth", 4),), (("Scale", 2.0), ("Distortion", 2.0)))
    tile("Brick", "ShaderNodeTexBrick", "Color", (("offset", 0.4), ("squash", 0.7), ("squash_frequency", 3)),
         (("Color1", (0.9, 0.3, 0.2, 1.0)), ("Color2", (0.2, 0.6, 0.9, 1.0)), ("Mortar", (0.9, 0.9, 0.8, 1.0)),
          ("Scale", 3.0), ("Mortar Size", 0.05), ("Mortar Smooth", 0.4), ("Bias", -0.2)))
    tile("CellColors", "ShaderNodeTexVoronoi", "Position", inputs=(("Scale", 3.0),), chain=per_cell_white_noise)
    emission_tiles(tiles, rows=3)


def curves_and_ramps():
    """Eight tiles: Color Ramps in each interpolation Blender has (B-Spline, Cardinal, Ease,
    Constant) and in HSV, RGB / Vector / Float Curves with bent, auto-handled points, each on a
    Noise or Wave texture, emitted and seen from above. Cycles bakes ramps and curves from
    Blender's own evaluation; so do we (B-Spline, Cardinal and HSV were linear RGB before)."""
    def ramp(interpolation, mode="RGB", hue="NEAR"):
        def build(nt, noise):
            r = nt.nodes.new("ShaderNodeValToRGB")
            cr = r.color_ramp
            cr.interpolation, cr.color_mode, cr.hue_interpolation = interpolation, mode, hue
            cr.elements[0].position, cr.elements[0].color = 0.3, (0.9, 0.1, 0.1, 1.0)
            cr.elements[1].position, cr.elements[1].color = 0.7, (0.1, 0.3, 0.9, 1.0)
            e = cr.elements.new(0.5)
            e.color = (0.2, 0.9, 0.2, 1.0)
            nt.links.new(noise.outputs["Fac"], r.inputs["Fac"])
            return r.outputs["Color"]
        return build

    def curve_points(curve, points, handle="AUTO"):
        for p, (x, y) in zip(curve.points, points[:2]):
            p.location = (x, y)
        for x, y in points[2:]:
            curve.points.new(x, y)
        for p in curve.points:
            p.handle_type = handle

    def rgb_curves(nt, noise):
        c = nt.nodes.new("ShaderNodeRGBCurve")
        m = c.mapping
        curve_points(m.curves[3], [(0.0, 0.1), (1.0, 0.9), (0.5, 0.7)])
        curve_points(m.curves[0], [(0.0, 0.0), (1.0, 1.0), (0.4, 0.1)], "AUTO_CLAMPED")
        curve_points(m.curves[2], [(0.0, 0.2), (1.0, 0.6), (0.6, 0.9)], "VECTOR")
        m.update()
        nt.links.new(noise.outputs["Color"], c.inputs["Color"])
        c.inputs["Fac"].default_value = 0.9
        return c.outputs["Color"]

    def vector_curves(nt, noise):
        c = nt.nodes.new("ShaderNodeVectorCurve")
        m = c.mapping
        for k in range(3):
            curve_points(m.curves[k], [(-1.0, 0.0), (1.0, 1.0), (0.0, 0.2 + 0.3 * k)])
        m.extend = "HORIZONTAL"
        m.update()
        nt.links.new(noise.outputs["Color"], c.inputs["Vector"])
        return c.outputs["Vector"]

    def float_curve(nt, noise):
        wave = nt.nodes.new("ShaderNodeTexWave")
        wave.inputs["Scale"].default_value = 2.0
        c = nt.nodes.new("ShaderNodeFloatCurve")
        curve_points(c.mapping.curves[0], [(0.0, 0.0), (1.0, 1.0), (0.3, 0.8), (0.6, 0.1)])
        c.mapping.update()
        nt.links.new(wave.outputs["Fac"], c.inputs["Value"])
        return c.outputs["Value"]

    emission_tiles((("RampBSpline", ramp("B_SPLINE")), ("RampCardinal", ramp("CARDINAL")), ("RampEase", ramp("EASE")),
                    ("RampConstant", ramp("CONSTANT")), ("RampHsv", ramp("LINEAR", "HSV", "FAR")),
                    ("RgbCurves", rgb_curves), ("VectorCurves", vector_curves), ("FloatCurve", float_curve)),
                   noise_source)


def math_nodes():
    """Twelve tiles of Vector Math and Map Range on a tile's Generated coordinate (or a Noise):
    Map Range stepped, smooth-step, smoother-step and on vectors; Vector Math's length,
    distance, cross product, reflect, snap, wrap, sine and dot product, emitted and seen from
    above (a Vector Math other than add / subtract / multiply / divide / scale was a constant,
    a Map Range other than linear was linear, before 2026-11-30)."""
    def map_range(kind, lo=0.2, hi=0.8, vector=False):
        def build(nt, coord):
            r = nt.nodes.new("ShaderNodeMapRange")
            r.data_type, r.interpolation_type = ("FLOAT_VECTOR" if vector else "FLOAT"), kind
            if vector:  # the vector sockets share the float ones' names: by identifier
                socket = {s.identifier: s for s in r.inputs}
                socket["From_Min_FLOAT3"].default_value = (lo, 0.1, 0.0)
                socket["From_Max_FLOAT3"].default_value = (hi, 0.9, 1.0)
                socket["Steps_FLOAT3"].default_value = (3.0, 5.0, 2.0)
                nt.links.new(coord, socket["Vector"])
                return r.outputs["Vector"]
            r.inputs["From Min"].default_value, r.inputs["From Max"].default_value = lo, hi
            r.inputs["Steps"].default_value = 5.0
            sep = nt.nodes.new("ShaderNodeSeparateXYZ")
            nt.links.new(coord, sep.inputs["Vector"])
            nt.links.new(sep.outputs["X"], r.inputs["Value"])
            return r.outputs["Result"]
        return build

    def vmath(op, b=(0.5, 0.5, 0.0), c=(0.0, 0.0, 0.0), scale=1.0, value=False, gain=1.0, absolute=False):
        def build(nt, coord):
            m = nt.nodes.new("ShaderNodeVectorMath")
            m.operation = op
            nt.links.new(coord, m.inputs[0])
            m.inputs[1].default_value, m.inputs[2].default_value = b, c
            m.inputs["Scale"].default_value = scale
            out = m.outputs["Value" if value else "Vector"]
            if absolute:  # emission stays positive (we clamp a negative colour; Cycles emits it)
                a = nt.nodes.new("ShaderNodeVectorMath")
                a.operation = "ABSOLUTE"
                nt.links.new(out, a.inputs[0])
                out = a.outputs["Vector"]
            if gain != 1.0:  # into the visible range
                g = nt.nodes.new("ShaderNodeVectorMath")
                g.operation = "SCALE"
                g.inputs["Scale"].default_value = gain
                nt.links.new(out, g.inputs[0])
                out = g.outputs["Vector"]
            return out
        return build

    tiles = (("MapStepped", map_range("STEPPED")), ("MapSmooth", map_range("SMOOTHSTEP", 0.8, 0.2)),
             ("MapSmoother", map_range("SMOOTHERSTEP")), ("MapVector", map_range("STEPPED", vector=True)),
             ("Length", vmath("LENGTH", value=True)), ("Distance", vmath("DISTANCE", value=True, gain=1.4)),
             ("Cross", vmath("CROSS_PRODUCT", b=(0.3, -0.6, 0.9), gain=1.5, absolute=True)),
             ("Reflect", vmath("REFLECT", b=(0.3, 0.8, 0.5), absolute=True)),
             ("Snap", vmath("SNAP", b=(0.2, 0.3, 0.3))), ("Wrap", vmath("WRAP", b=(0.35, 0.6, 0.8), c=(0.1, 0.0, 0.2))),
             ("Sine", vmath("SINE", gain=0.5)), ("Dot", vmath("DOT_PRODUCT", b=(1.0, 0.6, 0.0), value=True, gain=0.7)))
    emission_tiles(tiles, lambda nt: nt.nodes.new("ShaderNodeTexCoord").outputs["Generated"], rows=3)


def geometry_coordinates():
    """Geometry > Position / Normal / True Normal / Tangent and Texture Coordinate > Normal
    (object space) on tilted, rotated tiles (their object and world normals differ; one tangent
    tile scaled), each through Vector Math ABSOLUTE so the emission stays positive; seen from
    above."""
    def coordinate(node, output):
        def build(nt, _):
            a = nt.nodes.new("ShaderNodeVectorMath")
            a.operation = "ABSOLUTE"
            nt.links.new(nt.nodes.new(node).outputs[output], a.inputs[0])
            return a.outputs["Vector"]
        return build
    emission_tiles((("Position", coordinate("ShaderNodeNewGeometry", "Position")),
                    ("Normal", coordinate("ShaderNodeNewGeometry", "Normal")),
                    ("TrueNormal", coordinate("ShaderNodeNewGeometry", "True Normal")),
                    ("ObjectNormal", coordinate("ShaderNodeTexCoord", "Normal")),
                    ("Tangent", coordinate("ShaderNodeNewGeometry", "Tangent")),
                    ("TangentScaled", coordinate("ShaderNodeNewGeometry", "Tangent"))), rows=2)
    for i, ob in enumerate(o for o in bpy.data.objects if o.type == "MESH"):
        ob.rotation_euler = (math.radians(25), math.radians(-20 + 10 * i), math.radians(30 * i))
    # Tangent: the direction around the object's Z axis through its Generated centre, carried
    # as a normal: a scaled object's differs from its direction carried as a vector.
    bpy.data.objects["TangentScaled"].scale = (1.0, 0.4, 1.0)


def object_info():
    """Object Info per instance: twelve tiles, eight separate objects and four instances of a
    tile on a mesh's vertices (Instancing > Vertices), each emitting its Random (through a Color
    Ramp), its Viewport Display colour, its Object Index and its material's index. Random is
    Blender's per-instance number (the depsgraph's random_id, as Cycles maps it)."""
    reset(128)
    scene = bpy.context.scene
    scene.render.resolution_y = 96
    m, nt, out = empty_material("InfoGlow")
    info = nt.nodes.new("ShaderNodeObjectInfo")
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (1.0, 0.2, 0.1, 1.0)
    ramp.color_ramp.elements[1].color = (0.1, 0.4, 1.0, 1.0)
    nt.links.new(info.outputs["Random"], ramp.inputs["Fac"])
    mix = nt.nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    mix.inputs["Fac"].default_value = 1.0
    nt.links.new(ramp.outputs["Color"], mix.inputs["Color1"])
    nt.links.new(info.outputs["Color"], mix.inputs["Color2"])
    index = nt.nodes.new("ShaderNodeMath")
    index.operation = "MULTIPLY_ADD"
    nt.links.new(info.outputs["Object Index"], index.inputs[0])
    index.inputs[1].default_value, index.inputs[2].default_value = 0.1, 0.5
    glow = nt.nodes.new("ShaderNodeEmission")
    nt.links.new(mix.outputs["Color"], glow.inputs["Color"])
    nt.links.new(index.outputs["Value"], glow.inputs["Strength"])
    nt.links.new(glow.outputs["Emission"], out.inputs["Surface"])
    m.pass_index = 2
    for i in range(8):
        ob = quad_object("Tile%d" % i, 0.9, 0.9, (-1.5 + i % 4, 1.0 - i // 4, 0.0), (0, 0, 0), m)
        ob.pass_index = i
        ob.color = (1.0, 1.0 - 0.1 * i, 0.6 + 0.05 * i, 1.0)
    # Four instances of one tile on the vertices of a hidden mesh (their random_ids from the
    # instance's persistent id).
    dots = bpy.data.meshes.new("InstanceDots")
    dots.from_pydata([(-1.5 + k, -1.0, 0.0) for k in range(4)], [], [])
    parent = link(bpy.data.objects.new("InstanceParent", dots))
    parent.instance_type = "VERTS"
    child = quad_object("InstancedTile", 0.9, 0.9, (0.0, 0.0, 0.0), (0, 0, 0), m)
    child.parent = parent
    child.pass_index = 3
    camera_down(4.0 * 50.0 / 36.0)


def color_nodes():
    """Twelve tiles: Separate / Combine Color in HSV and HSL on a Noise's colour (hue rotated,
    saturation raised), Blackbody colours at 1200, 2500, 4000, 6500 and 10000 K and driven by a
    Noise over 1000-8000 K, and Wavelength colours at 455, 532 and 607 nm and driven by a Noise
    over 400-700 nm (Separate / Combine HSV and HSL were RGB, Blackbody and Wavelength constants,
    before 2026-11-30)."""
    def hue_shift(mode):
        def build(nt, noise):
            sep = nt.nodes.new("ShaderNodeSeparateColor")
            com = nt.nodes.new("ShaderNodeCombineColor")
            sep.mode = com.mode = mode
            nt.links.new(noise.outputs["Color"], sep.inputs["Color"])
            add = nt.nodes.new("ShaderNodeMath")
            add.operation, add.inputs[1].default_value = "WRAP", 1.0
            shift = nt.nodes.new("ShaderNodeMath")
            shift.inputs[1].default_value = 0.4
            nt.links.new(sep.outputs[0], shift.inputs[0])
            nt.links.new(shift.outputs[0], add.inputs[0])
            add.inputs[2].default_value = 0.0
            nt.links.new(add.outputs[0], com.inputs[0])
            sat = nt.nodes.new("ShaderNodeMath")
            sat.operation, sat.inputs[1].default_value = "MULTIPLY", 3.0
            sat.use_clamp = True  # saturation above 1 makes negative colours (Cycles emits them; we clamp)
            nt.links.new(sep.outputs[1], sat.inputs[0])
            nt.links.new(sat.outputs[0], com.inputs[1])
            nt.links.new(sep.outputs[2], com.inputs[2])
            return com.outputs["Color"]
        return build

    def blackbody(kelvin=None):
        def build(nt, noise):
            b = nt.nodes.new("ShaderNodeBlackbody")
            if kelvin is None:
                r = nt.nodes.new("ShaderNodeMapRange")
                r.inputs["From Min"].default_value, r.inputs["From Max"].default_value = 0.3, 0.7
                r.inputs["To Min"].default_value, r.inputs["To Max"].default_value = 1000.0, 8000.0
                nt.links.new(noise.outputs["Fac"], r.inputs["Value"])
                nt.links.new(r.outputs["Result"], b.inputs["Temperature"])
            else:
                b.inputs["Temperature"].default_value = kelvin
            return b.outputs["Color"]
        return build

    def wavelength(nm=None):
        def build(nt, noise):
            w = nt.nodes.new("ShaderNodeWavelength")
            if nm is None:  # 400-700 nm by the Noise
                r = nt.nodes.new("ShaderNodeMapRange")
                r.inputs["From Min"].default_value, r.inputs["From Max"].default_value = 0.3, 0.7
                r.inputs["To Min"].default_value, r.inputs["To Max"].default_value = 400.0, 700.0
                nt.links.new(noise.outputs["Fac"], r.inputs["Value"])
                nt.links.new(r.outputs["Result"], w.inputs[0])
            else:
                w.inputs[0].default_value = nm
            return w.outputs["Color"]
        return build

    emission_tiles((("HueShiftHsv", hue_shift("HSV")), ("HueShiftHsl", hue_shift("HSL")),
                    ("Blackbody1200", blackbody(1200)), ("Blackbody2500", blackbody(2500)),
                    ("Blackbody4000", blackbody(4000)), ("Blackbody6500", blackbody(6500)),
                    ("Blackbody10000", blackbody(10000)), ("BlackbodyNoise", blackbody()),
                    ("Wavelength455", wavelength(455)), ("Wavelength532", wavelength(532)),
                    ("Wavelength607", wavelength(607)), ("WavelengthNoise", wavelength())), noise_source, rows=3)


def checker_glow():
    m = emission_material("CheckerGlow", strength=5.0)
    nt = m.node_tree
    chk = nt.nodes.new("ShaderNodeTexChecker")
    chk.inputs["Color1"].default_value = (1.0, 0.8, 0.6, 1.0)
    chk.inputs["Color2"].default_value = (0.1, 0.2, 1.0, 1.0)
    chk.inputs["Scale"].default_value = 3.0
    nt.links.new(chk.outputs["Color"], nt.nodes["Emission"].inputs["Color"])
    return m


def emissive_textured():
    """emissive_mesh with a Checker texture (generated coordinates) as the emission colour."""
    emissive_mesh(checker_glow)


def glossy_material(name, roughness, color=(0.8, 0.8, 0.8)):
    """A stock Glossy BSDF (GGX) of the given roughness."""
    return node_material(name, "ShaderNodeBsdfGlossy", {"Color": (*color, 1.0), "Roughness": roughness},
                         distribution="GGX")


def look_at(ob, target):
    from mathutils import Vector
    d = Vector(target) - Vector(ob.location)
    ob.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()


VEACH_RADII = (0.01, 0.04, 0.13, 0.4)
VEACH_ROUGHNESS = (0.01, 0.05, 0.1, 0.3)


def veach_mis(kind="POINT", radii=VEACH_RADII, roughness=VEACH_ROUGHNESS, res=(96, 64), wall=True, **lamp_props):
    """Veach's multiple importance sampling scene: glossy plates (one per roughness, the
    sharpest nearest the camera), each tilted to reflect a row of equal-power lamps (one per
    radius: point / spot radius, area half size; suns: angular diameter 100 x it in degrees)
    toward the camera, and a diffuse wall behind the lamps. Lamps are hidden from the camera (Cycles 3.4)."""
    from mathutils import Vector
    scene = reset(res[0])
    scene.render.resolution_y = res[1]
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 50.0
    cam_data.clip_start = 0.05
    cam_data.clip_end = 100.0
    cam = link(bpy.data.objects.new("Camera", cam_data))
    cam.location = (0.0, -4.6, 1.7)
    look_at(cam, (0.0, -0.5, 0.45))
    scene.camera = cam
    lamp_centre = Vector((0.0, 1.4, 1.7))
    n = len(roughness)
    for i, r in enumerate(roughness):
        c = Vector((0.0, -1.5 + 1.6 * i / max(n - 1, 1), 0.2 * i))
        normal = ((Vector(cam.location) - c).normalized() + (lamp_centre - c).normalized()).normalized()
        ob = plane("Plate%d" % i, 1.0, glossy_material("Glossy%d" % i, r), tuple(c))
        ob.scale = (3.2, 0.42, 1.0)
        ob.rotation_euler = (math.atan2(-normal.y, normal.z), 0.0, 0.0)
    if wall:
        w = plane("Wall", 1.0, diffuse_material("WallMat", (0.5, 0.5, 0.5)), (0.0, 3.0, 1.5))
        w.scale = (12.0, 6.0, 1.0)
        w.rotation_euler = (math.radians(90), 0.0, 0.0)
    m = len(radii)
    for j, size in enumerate(radii):
        x = -1.5 + 3.0 * j / max(m - 1, 1)
        loc = (x, lamp_centre.y, lamp_centre.z)
        if kind in ("POINT", "SPOT"):
            ob = light(kind, "Lamp%d" % j, 60.0, loc, shadow_soft_size=size, **lamp_props)
        elif kind == "AREA":
            ob = light(kind, "Lamp%d" % j, 60.0, loc, size=2.0 * size, **lamp_props)
        elif kind == "SUN":  # angular diameter 100 x the radius in degrees: 1 to 40 degrees
            ob = light(kind, "Lamp%d" % j, 1.0, loc, angle=math.radians(100.0 * size), **lamp_props)
        else:
            raise ValueError(kind)
        if kind != "POINT":
            look_at(ob, (x, 0.0, 0.3))  # toward the plates
    return scene


def veach_point():
    veach_mis("POINT")


def veach_spot():
    veach_mis("SPOT", spot_size=math.radians(60.0), spot_blend=0.2)


def veach_sun():
    veach_mis("SUN")


def veach_area_square():
    veach_mis("AREA", shape="SQUARE")


def veach_area_disk():
    veach_mis("AREA", shape="DISK")


def box_mesh(name, size):
    """An axis-aligned cube of edge `size` centred on the origin (outward faces)."""
    h = size / 2
    verts = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    return me


def principled_volume_material(name, **inputs):
    """(material, its Principled Volume node) with only a volume shader; inputs by socket
    name with '_' for ' '."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for n in list(nt.nodes):
        if n.bl_idname != "ShaderNodeOutputMaterial":
            nt.nodes.remove(n)
    pv = nt.nodes.new("ShaderNodeVolumePrincipled")
    for k, v in inputs.items():
        pv.inputs[k.replace("_", " ")].default_value = v
    nt.links.new(pv.outputs["Volume"], nt.nodes["Material Output"].inputs["Volume"])
    return m, pv


def fire_domain(cache_dir, frames, resolution=24):
    """A tiny fire simulation (gas domain 'Smoke Domain' `resolution` voxels across, Replay cache in
    OpenVDB under cache_dir, a burner sphere below) run for `frames` frames, with a
    Quick-Fire-like Principled Volume (density 5, blackbody 1); returns the domain object."""
    import bmesh
    scene = bpy.context.scene
    domain = link(bpy.data.objects.new("Smoke Domain", box_mesh("Smoke Domain", 2.0)))
    domain.location, domain.scale = (0.2, 0.0, 1.0), (1.0, 0.8, 1.2)
    ds = domain.modifiers.new("Fluid", "FLUID")
    ds.fluid_type = "DOMAIN"
    ds = ds.domain_settings
    ds.domain_type = "GAS"
    ds.resolution_max = resolution
    ds.cache_type = "REPLAY"
    ds.cache_data_format = "OPENVDB"
    ds.cache_directory = cache_dir
    me = bpy.data.meshes.new("Burner")
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=0.3)
    bm.to_mesh(me)
    bm.free()
    flow = link(bpy.data.objects.new("Burner", me))
    flow.location = (0.4, 0.0, 0.4)
    fm = flow.modifiers.new("Fluid", "FLUID")
    fm.fluid_type = "FLOW"
    fm.flow_settings.flow_type = "BOTH"
    fm.flow_settings.flow_behavior = "INFLOW"
    flow.hide_render = True
    mat, _ = principled_volume_material("Fire", Density=5.0, Blackbody_Intensity=1.0)
    domain.data.materials.append(mat)
    scene.frame_start, scene.frame_end = 1, frames
    for f in range(1, frames + 1):  # the Replay cache simulates as the frames play
        scene.frame_set(f)
    return domain


def cloud_and_fog(vdb_path):
    """The viewport media scene: a Volume object 'Cloud' reading vdb_path (a Principled
    Volume 'Smoke', density 8, left) and a cube 'Fog' with a volume material ('FogMat',
    density 1.5, right), lit by a sun and a pale sky, seen along +y from 6 units; 64x48.
    Returns (cloud, its Principled Volume, the fog's Principled Volume)."""
    scene = reset()
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.6, 0.7, 0.9, 1.0)
    cam = link(bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera")))
    cam.location, cam.rotation_euler = (0.0, -6.0, 0.0), (math.radians(90), 0.0, 0.0)
    cam.data.lens = 50.0
    scene.camera = cam
    light("SUN", "Sun", 3.0, (0.0, 0.0, 5.0), rotation=(math.radians(-40), math.radians(30), 0.0))
    vol = bpy.data.volumes.new("CloudData")
    vol.filepath = vdb_path
    cloud = link(bpy.data.objects.new("Cloud", vol))
    cloud.location, cloud.scale = (-1.1, 0.0, 0.0), (0.7, 0.7, 0.7)
    smoke, pv = principled_volume_material("Smoke", Density=8.0, Color=(0.8, 0.8, 0.8, 1.0))
    vol.materials.append(smoke)
    fog = link(bpy.data.objects.new("Fog", box_mesh("FogBox", 0.9)))
    fog.location = (1.1, 0.0, 0.0)
    fog_mat, fog_pv = principled_volume_material("FogMat", Density=1.5, Color=(0.9, 0.6, 0.3, 1.0))
    fog.data.materials.append(fog_mat)
    return cloud, pv, fog_pv


def volume_blackbody():
    """A cube of glowing smoke (Principled Volume blackbody at 1500 K, uniform: a mesh has
    no temperature grid) over a floor that it lights, a black world, no lamps."""
    reset()
    plane()
    camera_down(4.0, lens=35.0)
    m, _ = principled_volume_material("Glowing smoke", Density=0.5, Blackbody_Intensity=1.0, Temperature=1500.0,
                                      Blackbody_Tint=(1.0, 0.9, 0.8, 1.0))
    cube = link(bpy.data.objects.new("Smoke", box_mesh("SmokeBox", 1.0)))
    cube.location = (0.3, 0.0, 1.0)
    cube.data.materials.append(m)


def volume_tinted():
    """A cube of fog whose Principled Volume absorbs by channel (Absorption Color (0.25, 0.64,
    1.0): Cycles 3.4 absorbs by 1 - its square root) over a floor lit by a sun: the floor
    seen through the fog and its shadow are tinted by the per-channel extinction."""
    reset()
    plane()
    camera_down(4.0, lens=35.0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(25), 0, math.radians(20)))
    m, _ = principled_volume_material("Tinted fog", Density=1.2, Color=(0.7, 0.7, 0.7, 1.0),
                                      Absorption_Color=(0.25, 0.64, 1.0, 1.0))
    cube = link(bpy.data.objects.new("TintedFog", box_mesh("TintedFogBox", 1.0)))
    cube.location = (0.2, 0.0, 0.8)
    cube.data.materials.append(m)


def hdri_path():
    d = os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir or "/tmp"
    return os.path.join(d, "rdv_test_sky.exr")


def hdri():
    """An environment image that varies with longitude only: a floor facing up receives
    exactly its average, so a constant-average approximation is exact for the floor."""
    scene = reset()
    plane(size=200.0)
    camera_down(3.0)
    w, h = 64, 32
    img = bpy.data.images.new("sky_src", w, h, float_buffer=True, alpha=False)
    import numpy as np
    u = (np.arange(w) + 0.5) / w
    row = np.stack([0.5 + 0.4 * np.cos(2 * np.pi * u), 0.6 + 0.3 * np.sin(2 * np.pi * u), np.full(w, 0.9),
                    np.ones(w)], axis=1).astype(np.float32)
    px = np.tile(row[None, :, :], (h, 1, 1)).reshape(-1)
    img.pixels.foreach_set(px)
    path = hdri_path()
    img.filepath_raw = path
    img.file_format = "OPEN_EXR"
    img.save()
    bpy.data.images.remove(img)
    sky = bpy.data.images.load(path)
    nt = scene.world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = sky
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    nt.nodes["Background"].inputs["Strength"].default_value = 1.0


def bad_input():
    """Objects the exporter must warn about by name, while the render goes on."""
    reset()
    plane()
    camera_down(4.0, lens=35.0)
    light("SUN", "Sun", 2.0, (0, 0, 5))
    # NaN vertex
    me = quad_mesh("NaNMesh", 0.5)
    me.vertices[2].co = (float("nan"), 0.0, 0.0)
    ob = link(bpy.data.objects.new("NaNObject", me))
    ob.location = (-1, -1, 0.5)
    # no faces
    me = bpy.data.meshes.new("EdgesOnly")
    me.from_pydata([(0, 0, 0), (1, 0, 0)], [(0, 1)], [])
    link(bpy.data.objects.new("NoFacesObject", me)).location = (1, 1, 0.5)
    # zero scale
    ob = link(bpy.data.objects.new("ZeroScaleObject", quad_mesh("ZeroMesh", 0.5)))
    ob.scale = (0.0, 0.0, 0.0)
    # unsupported node (Particle Info)
    m = diffuse_material("WavyMaterial")
    particles = m.node_tree.nodes.new("ShaderNodeParticleInfo")
    particles.name = "UnsupportedParticleInfo"
    m.node_tree.links.new(particles.outputs["Random"], m.node_tree.nodes["Diffuse BSDF"].inputs["Color"])
    ob = link(bpy.data.objects.new("WavyObject", quad_mesh("WavyMesh", 0.6)))
    ob.location = (1, -1, 0.3)
    ob.data.materials.append(m)
    # missing texture file
    m = diffuse_material("MissingTexMaterial")
    tex = m.node_tree.nodes.new("ShaderNodeTexImage")
    tex.name = "MissingImage"
    img = bpy.data.images.new("missing.png", 4, 4)
    img.source = "FILE"
    img.filepath = "/nonexistent/rendezvous/missing.png"
    tex.image = img
    m.node_tree.links.new(tex.outputs["Color"], m.node_tree.nodes["Diffuse BSDF"].inputs["Color"])
    ob = link(bpy.data.objects.new("MissingTexObject", quad_mesh("TexMesh", 0.6)))
    ob.location = (-1, 1, 0.3)
    ob.data.materials.append(m)


def materials_instances():
    """Materials, instances (collection instance, shared mesh), smooth and flat shading: the
    general scene of the add-on tests (export, cancel, viewport)."""
    reset(96)
    plane(material=diffuse_material("FloorMat", (0.6, 0.6, 0.6)))
    cam = camera_down(6.0, lens=35.0)
    cam.location = (0, -6, 4)
    cam.rotation_euler = (math.radians(55), 0, 0)
    light("AREA", "Key", 300.0, (2, -2, 4), rotation=(math.radians(30), math.radians(20), 0), size=2.0)
    bpy.context.scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.06, 0.08, 1)
    sphere = uv_sphere(radius=0.6, location=(-1.2, 0, 0.6))
    bpy.ops.object.shade_smooth()
    m = bpy.data.materials.new("Principled")
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.2, 0.1, 1)
    sphere.data.materials.append(m)
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(1.2, 0, 0.4))
    cube = bpy.context.active_object
    g = bpy.data.materials.new("Metal")
    g.use_nodes = True
    p = g.node_tree.nodes["Principled BSDF"]
    p.inputs["Metallic"].default_value = 1.0
    p.inputs["Roughness"].default_value = 0.3
    cube.data.materials.append(g)
    # a collection instanced three times
    coll = bpy.data.collections.new("Pillars")
    bpy.ops.mesh.primitive_cylinder_add(radius=0.15, depth=1.0, location=(0, 0, 0.5))
    pillar = canonical_face_order(bpy.context.active_object)
    for c in pillar.users_collection:
        c.objects.unlink(pillar)
    coll.objects.link(pillar)
    for i, x in enumerate((-1.5, 0.0, 1.5)):
        inst = bpy.data.objects.new("PillarInstance%d" % i, None)
        inst.instance_type = "COLLECTION"
        inst.instance_collection = coll
        inst.location = (x, 1.5, 0)
        link(inst)
    # a second object sharing the sphere's mesh
    twin = link(bpy.data.objects.new("SphereTwin", sphere.data))
    twin.location = (0, -0.8, 0.6)



def showcase():
    """What Rendezvous is for, the README's render command: a room lit only through a gap in
    its back wall by a spot outside, thin fog in the room (the beam shows as a shaft) and a
    glass ball in the beam (its caustic on the floor). Unbiased Light Paths in both engines:
    caustics on, no Filter Glossy, no clamping, two volume bounces. 640 x 360."""
    scene = reset(64)
    scene.render.resolution_x, scene.render.resolution_y = 640, 360
    plane("Floor", 20.0, diffuse_material("FloorMat", (0.55, 0.5, 0.45)))
    wall_mat = diffuse_material("WallMat", (0.7, 0.7, 0.68))
    half, height = 2.5, 2.8

    def wall(name, size_x, size_y, location, rotation):
        return quad_object(name, size_x, size_y, location, rotation, wall_mat)

    wall("Ceiling", 2 * half, 2 * half, (0, 0, height), (180, 0, 0))
    wall("LeftWall", 2 * half, height, (-half, 0, height / 2), (90, 0, 90))
    wall("RightWall", 2 * half, height, (half, 0, height / 2), (90, 0, -90))
    wall("FrontWall", 2 * half, height, (0, -half, height / 2), (-90, 0, 0))
    # the back wall in three pieces around a door-high gap 0.3 m wide at x = 0.8
    gap_x, gap_w, gap_h = 0.8, 0.3, 2.2
    left_w = gap_x - gap_w / 2 + half
    right_w = half - (gap_x + gap_w / 2)
    wall("BackWallLeft", left_w, height, (-half + left_w / 2, half, height / 2), (90, 0, 0))
    wall("BackWallRight", right_w, height, (half - right_w / 2, half, height / 2), (90, 0, 0))
    wall("BackWallLintel", gap_w, height - gap_h, (gap_x, half, (gap_h + height) / 2), (90, 0, 0))
    # the spot outside, aimed through the gap at the ball
    ball_at = (0.0, 0.3, 0.3)
    spot = light("SPOT", "Sun through the door", 8000.0, (1.5, 4.5, 2.6), spot_size=math.radians(30),
                 spot_blend=0.1, shadow_soft_size=0.05)
    look_at(spot, ball_at)
    ball = smooth_ball("GlassBall", ball_at, 0.3, node_material(
        "Glass", "ShaderNodeBsdfGlass", {"Color": (1, 1, 1, 1), "Roughness": 0.0, "IOR": 1.5}, distribution="SHARP"))
    # thin fog filling the room (inside the walls)
    fog = link(bpy.data.objects.new("Fog", box_mesh("FogBox", 1.0)))
    fog.location = (0, 0, height / 2)
    fog.scale = (2 * half - 0.02, 2 * half - 0.02, height - 0.02)
    fog_mat, _ = principled_volume_material("FogMat", Density=0.06, Color=(1.0, 1.0, 1.0, 1.0))
    fog.data.materials.append(fog_mat)
    camera_looking_at((-1.9, -2.4, 1.6), (0.25, 0.35, 0.45), 22.0)
    scene.view_settings.view_transform = "Filmic"
    c = scene.cycles
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.volume_bounces = 2
    return scene


def cornell_box(lamp_gap=0.0, res=128):
    """scenes/cornell_box.json in Blender (2 m tall, camera at y = -3.9), its emissive
    quad `lamp_gap` below the white ceiling (Cycles' mesh emission is two-sided: the gap
    is lit by the quad's back)."""
    reset(res)
    white = diffuse_material("White", (0.73, 0.73, 0.73))
    red = diffuse_material("Red", (0.63, 0.065, 0.05))
    green = diffuse_material("Green", (0.14, 0.45, 0.09))

    def block(name, size, location, rot_z):
        ob = link(bpy.data.objects.new(name, box_mesh(name + "Mesh", 1.0)))
        ob.scale = size
        ob.location = location
        ob.rotation_euler = (0.0, 0.0, math.radians(rot_z))
        ob.data.materials.append(white)

    quad_object("Floor", 2, 2, (0, 0, 0), (0, 0, 0), white)
    quad_object("Ceiling", 2, 2, (0, 0, 2), (180, 0, 0), white)
    quad_object("Back", 2, 2, (0, 1, 1), (90, 0, 0), white)
    quad_object("Left", 2, 2, (-1, 0, 1), (0, 90, 0), red)
    quad_object("Right", 2, 2, (1, 0, 1), (0, -90, 0), green)
    block("ShortBlock", (0.6, 0.6, 0.6), (0.33, -0.35, 0.3), -17)
    block("TallBlock", (0.6, 0.6, 1.2), (-0.33, 0.3, 0.6), 17)
    quad_object("Lamp", 0.47, 0.38, (0, 0, 2 - lamp_gap), (180, 0, 0), emission_material("Lamp", (1.0, 0.85, 0.6), 15.0))
    cam = bpy.data.cameras.new("Camera")
    cam.lens = 50
    cam.sensor_width = 36
    cam.sensor_fit = "HORIZONTAL"
    cam.clip_start = 0.1
    cam.clip_end = 100.0
    ob = link(bpy.data.objects.new("Camera", cam))
    ob.location = (0, -3.9, 1)
    ob.rotation_euler = (math.radians(90), 0, 0)
    bpy.context.scene.camera = ob
    return bpy.context.scene


def cornell_lamp_near_ceiling():
    return cornell_box(lamp_gap=0.01)


# ---- Light Paths (tests/blender/test_light_paths.py): Cycles' bounce limits, caustics
# switches and clamps where they change the image; each sets scene.cycles as a user would.
def light_paths_diffuse():
    """The Cornell box with Cycles' diffuse bounces at 1 (its default 4 is 1.5% brighter)."""
    scene = cornell_box(lamp_gap=0.01, res=48)
    scene.cycles.diffuse_bounces = 1
    return scene


def light_paths_mirror():
    """The Cornell box with a mirror for its back wall and glossy bounces 0: the mirror shows
    the lamp (the path's last bounce) but not the lit room (a glossy bounce before a diffuse one)."""
    scene = cornell_box(lamp_gap=0.01, res=48)
    back = bpy.data.objects["Back"]
    back.data.materials[0] = glossy_material("Mirror", 0.0, (0.9, 0.9, 0.9))
    scene.cycles.glossy_bounces = 0
    scene.cycles.diffuse_bounces = 2
    return scene


def smooth_glass_ball():
    """A smooth glass ball (IOR 1.5, sharp) of radius 0.6 resting on the floor at the origin."""
    ball = uv_sphere(segments=48, ring_count=24, radius=0.6, location=(0, 0, 0.6))
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(node_material("Glass", "ShaderNodeBsdfGlass",
                                             {"Color": (1, 1, 1, 1), "Roughness": 0.0, "IOR": 1.5},
                                             distribution="SHARP"))
    return ball


def glass_ball_on_floor():
    """A smooth glass ball on a floor before a wall, under a small area lamp (48x48)."""
    reset(48)
    plane("Floor", 10.0, diffuse_material("FloorMat", (0.7, 0.7, 0.7)))
    back = plane("Wall", 10.0, diffuse_material("WallMat", (0.5, 0.55, 0.6)), location=(0, 3, 5))
    back.rotation_euler = (math.radians(90), 0, 0)
    smooth_glass_ball()
    light("AREA", "Lamp", 300.0, (-1.2, -0.6, 3.2), size=0.3)
    camera_looking_at((0, -4.5, 2.6), (0, 0, 0.4), 35)
    return bpy.context.scene


def light_paths_caustics():
    """A smooth glass ball on a floor under an area lamp with both caustics switches off:
    the floor under it stays in shadow, the ball still shows the floor and the lamp."""
    scene = glass_ball_on_floor()
    scene.cycles.caustics_reflective = False
    scene.cycles.caustics_refractive = False
    return scene


def light_paths_transmission():
    """A smooth glass ball on a floor under an area lamp with transmission bounces 1 (Cycles'
    default is 12): the floor seen through the ball (two refractions before the floor's bounce)
    goes dark, as does its caustic; its reflections and the lamp's reflection in it stay."""
    scene = glass_ball_on_floor()
    scene.cycles.transmission_bounces = 1
    return scene


def light_paths_filter_glossy():
    """Filter Glossy 1 (Cycles' default): a smooth glass ball on a diffuse floor under a small
    area lamp; the caustic under it is seen after the floor's diffuse bounce, so the glass
    there is blurred (0.5 sqrt(1 - pdf) roughness) and the caustic spreads (path tracing and
    BDPT)."""
    reset(32)
    plane("Floor", 10.0, diffuse_material("FloorMat", (0.7, 0.7, 0.7)))
    smooth_glass_ball()
    light("AREA", "Lamp", 300.0, (-0.6, -0.3, 3.2), size=0.5)
    camera_looking_at((0.4, -2.6, 2.6), (0.35, 0.2, 0.0), 50)
    scene = bpy.context.scene
    scene.cycles.blur_glossy = 2.0
    return scene


def light_paths_clamp():
    """The Cornell box with indirect light clamped at 0.5 (sum of RGB per contribution)."""
    scene = cornell_box(lamp_gap=0.01, res=48)
    scene.cycles.sample_clamp_indirect = 0.5
    return scene


def light_paths_lamp_bounces():
    """The Cornell box lit by two point lamps instead of its emitting quad, one of them with
    Light > Max Bounces 0 (direct light only). Dim enough that Cycles' default indirect clamp
    (10) does not bind: where it does, the path tracer's clamped image differs from Cycles',
    which picks lamps with another probability (test_light_paths.py)."""
    scene = cornell_box(res=48)
    bpy.data.objects.remove(bpy.data.objects["Lamp"])
    limited = light("POINT", "Limited", 6.0, (0.3, 0.0, 1.6), shadow_soft_size=0.0)
    limited.data.cycles.max_bounces = 0
    light("POINT", "Free", 3.0, (-0.4, 0.2, 1.5), shadow_soft_size=0.0)
    return scene


def light_paths_principled():
    """The Cornell box with Principled BSDFs (their stock Specular 0.5, Roughness 0.3): each
    bounce is a diffuse or a glossy one by the closure Cycles samples there, so under glossy
    bounces 0 a path is kept with the odds that every bounce before its last vertex was diffuse
    (counted as their BSDF's dominant kind, diffuse, every path was kept)."""
    scene = cornell_box(lamp_gap=0.01, res=48)
    for m in ("White", "Red", "Green"):
        mat = bpy.data.materials[m]
        nt = mat.node_tree
        diffuse = next(n for n in nt.nodes if n.type == "BSDF_DIFFUSE")
        p = nt.nodes.new("ShaderNodeBsdfPrincipled")
        p.inputs["Base Color"].default_value = diffuse.inputs["Color"].default_value
        p.inputs["Roughness"].default_value = 0.3
        out = next(n for n in nt.nodes if n.type == "OUTPUT_MATERIAL")
        nt.links.new(p.outputs["BSDF"], out.inputs["Surface"])
        nt.nodes.remove(diffuse)
    scene.cycles.diffuse_bounces = 4
    scene.cycles.glossy_bounces = 0
    return scene


def light_paths_principled_caustics():
    """The Principled Cornell box (light_paths_principled) with both caustics switches off and
    Cycles' default bounces: right after a diffuse bounce Cycles drops the glossy closures, so
    each wall's specular reflection of light from another wall is dropped with the odds that the
    bounce before it sampled a diffuse closure."""
    scene = light_paths_principled()
    scene.cycles.property_unset("diffuse_bounces")
    scene.cycles.property_unset("glossy_bounces")
    scene.cycles.caustics_reflective = False
    scene.cycles.caustics_refractive = False
    return scene


def light_paths_transparent():
    """Transparent max bounces 3: a floor seen through a staircase of Transparent BSDF cards
    (behind 0 .. 5 of them across the image), lit by an area lamp that shines under the cards,
    with an emitting strip on it. Behind 3 cards or more the floor is black (Cycles ends the
    path there); the strip still shows behind 3 (its emission counts), not behind 4 or 5."""
    scene = reset(48)
    plane("Floor", 4.0, diffuse_material("FloorMat", (0.8, 0.8, 0.8)))
    glow = emission_material("Glow", (1.0, 0.6, 0.3), 2.0)
    quad_object("Strip", 3.0, 0.15, (0, 0.5, 0.001), (0, 0, 0), glow)
    clear = node_material("Clear", "ShaderNodeBsdfTransparent", {"Color": (0.9, 0.95, 1.0, 1.0)})
    for i in range(1, 6):  # card i covers x <= 0.6 - 0.2 i
        quad_object("Card%d" % i, 4.0, 4.0, (-1.4 - 0.2 * i, 0, 1.0 + 0.15 * i), (0, 0, 0), clear)
    light("AREA", "Lamp", 150.0, (1.2, 0, 0.8), (0, math.radians(50), 0), size=0.4)
    camera_looking_at((0, -0.4, 3), (0, 0, 0), 40)
    scene.cycles.transparent_max_bounces = 3
    return scene


def alpha_leaves():
    """Alpha-mapped cards over a floor, seen from above by an orthographic camera: a card cut
    out by a checker texture into Principled Alpha, and a half-transparent one over it, lit by
    a sun and by a point lamp without a radius (both delta lights: the shadows through the
    cards come from next-event estimation alone, and light tracing cannot reach the camera)."""
    scene = reset(48)
    plane("Floor", 6.0, diffuse_material("FloorMat", (0.8, 0.8, 0.8)))
    m, nt, out = empty_material("Leaf")
    bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (0.2, 0.6, 0.1, 1.0)
    checker = nt.nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 4.0
    checker.inputs["Color1"].default_value = (1.0, 1.0, 1.0, 1.0)
    checker.inputs["Color2"].default_value = (0.0, 0.0, 0.0, 1.0)
    nt.links.new(checker.outputs["Fac"], bsdf.inputs["Alpha"])
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    quad_object("CutOut", 1.6, 1.6, (-0.3, 0.2, 0.7), (0, 0, 20), m)
    half = mix_material("Half", ("ShaderNodeBsdfDiffuse", {"Color": (0.6, 0.3, 0.1, 1.0)}),
                        ("ShaderNodeBsdfTransparent", {"Color": (1.0, 1.0, 1.0, 1.0)}), 0.5)
    quad_object("Half", 1.2, 1.2, (0.4, -0.3, 1.1), (0, 0, -10), half)
    light("SUN", "Sun", 2.0, (0, 0, 5), (math.radians(25), math.radians(-15), 0), angle=0.0)
    light("POINT", "Point", 150.0, (0.6, 0.5, 2.4), shadow_soft_size=0.0)
    cam = bpy.data.cameras.new("Camera")
    cam.type = "ORTHO"
    cam.ortho_scale = 3.0
    ob = link(bpy.data.objects.new("Camera", cam))
    ob.location = (0, 0, 4)
    scene.camera = ob
    return scene


def mix_material(name, first, second, fac):
    """Mix Shader of two stock shader nodes ((node type, inputs) each), fac toward the second."""
    m, nt, out = empty_material(name)
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = fac
    for slot, (node_type, inputs) in ((1, first), (2, second)):
        node = nt.nodes.new(node_type)
        for k, v in inputs.items():
            node.inputs[k].default_value = v
        nt.links.new(node.outputs[0], mix.inputs[slot])
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return m


def camera_looking_at(location, target, lens):
    """The scene's camera at location, looking at target."""
    cam = bpy.data.cameras.new("Camera")
    cam.lens = lens
    ob = link(bpy.data.objects.new("Camera", cam))
    ob.location = location
    look_at(ob, target)
    bpy.context.scene.camera = ob
    return ob


def smooth_ball(name, location, radius, material):
    """A smooth-shaded UV sphere (32 x 16) with one material."""
    ob = uv_sphere(segments=32, ring_count=16, radius=radius, location=location)
    ob.name = name
    bpy.ops.object.shade_smooth()
    ob.data.materials.append(material)
    return ob


def view_mix_material(name, color, roughness, fac_node, fac_output, glossy_color=(0.9, 0.9, 0.9), ramp=None,
                      **fac_inputs):
    """Mix Shader of a Diffuse BSDF (color) and a GGX Glossy (roughness; 0: Sharp), its Fac a
    Fresnel or Layer Weight node (fac_node) output with fac_inputs; ramp: (position of black,
    position of white) of a Color Ramp (Ease) between the two."""
    m = mix_material(name, ("ShaderNodeBsdfDiffuse", {"Color": color + (1.0,)}),
                     ("ShaderNodeBsdfGlossy", {"Color": glossy_color + (1.0,), "Roughness": roughness}), 0.5)
    nt = m.node_tree
    if roughness == 0.0:
        next(n for n in nt.nodes if n.bl_idname == "ShaderNodeBsdfGlossy").distribution = "SHARP"
    fac = nt.nodes.new(fac_node)
    for k, v in fac_inputs.items():
        fac.inputs[k].default_value = v
    mix = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeMixShader")
    out = fac.outputs[fac_output]
    if ramp is not None:
        r = nt.nodes.new("ShaderNodeValToRGB")
        r.color_ramp.interpolation = "EASE"
        r.color_ramp.elements[0].position, r.color_ramp.elements[1].position = ramp
        nt.links.new(out, r.inputs["Fac"])
        out = r.outputs["Color"]
    nt.links.new(out, mix.inputs["Fac"])
    return m


def view_dependent_mixes():
    """Mix Shaders by the viewing direction: four smooth balls (a Fresnel of IOR 1.45 over a GGX
    0.2 gloss; Layer Weight's Fresnel, blend 0.3; its Facing, blend 0.6, through a Color Ramp
    (Ease, 0.2 to 0.7); a Fresnel of IOR 1.8 over a mirror) on a floor mixed by Layer Weight's
    Fresnel, and two two-sided cards behind them (Geometry > Backfacing), seen from 13 degrees
    above, under a blue world and a sun."""
    scene = reset(64)
    scene.render.resolution_x = 128
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.3, 0.4, 0.6, 1.0)
    plane("Floor", 6.0, view_mix_material("FloorMat", (0.5, 0.45, 0.4), 0.15, "ShaderNodeLayerWeight", "Fresnel",
                                          Blend=0.2))
    balls = (("FresnelBall", -1.2, view_mix_material("Fresnel", (0.8, 0.2, 0.1), 0.2, "ShaderNodeFresnel", "Fac", IOR=1.45)),
             ("LayerFresnelBall", -0.4, view_mix_material("LayerFresnel", (0.1, 0.3, 0.8), 0.1, "ShaderNodeLayerWeight",
                                                          "Fresnel", Blend=0.3)),
             ("FacingBall", 0.4, view_mix_material("Facing", (0.2, 0.7, 0.2), 0.3, "ShaderNodeLayerWeight", "Facing",
                                                   ramp=(0.2, 0.7), Blend=0.6)),
             ("MirrorRimBall", 1.2, view_mix_material("MirrorRim", (0.8, 0.7, 0.2), 0.0, "ShaderNodeFresnel", "Fac",
                                                      IOR=1.8)))
    for name, x, material in balls:
        smooth_ball(name, (x, 0, 0.35), 0.35, material)
    # Two-sided cards (Geometry > Backfacing: green in front, red behind) behind the balls, one
    # facing the camera and one turned away.
    two_sided = mix_material("TwoSided", ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.7, 0.2, 1.0)}),
                             ("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.15, 0.1, 1.0)}), 0.5)
    nt = two_sided.node_tree
    mix = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeMixShader")
    nt.links.new(nt.nodes.new("ShaderNodeNewGeometry").outputs["Backfacing"], mix.inputs["Fac"])
    for name, x, turn in (("CardFront", -0.8, 90), ("CardBack", 0.8, -90)):
        quad_object(name, 0.7, 0.5, (x, 1.0, 0.75), (turn, 0, 0), two_sided)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(40), 0, math.radians(-30)), angle=math.radians(5))
    camera_looking_at((0, -3.0, 1.0), (0, 0, 0.3), 32)
    return scene


def incoming_facing():
    """Mix Shaders by the Dot Product of Geometry's Incoming and Normal (the facing cosine artists
    build by hand): a red ball glossy toward its rim (Fac = (1 - cos)^3 by two Math nodes), a blue
    ball through a Color Ramp of the cosine (0.3 gloss to 0.8 diffuse), a flat-shaded green ico
    sphere by Incoming . True Normal (the faces' own normals), and a floor mixed by the cosine
    itself; a blue world and a sun, as view_dependent_mixes."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.3, 0.4, 0.6, 1.0)

    def facing_mix(name, color, roughness, shape, normal="Normal"):
        m = mix_material(name, ("ShaderNodeBsdfDiffuse", {"Color": color + (1.0,)}),
                         ("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9, 1.0), "Roughness": roughness}), 0.5)
        nt = m.node_tree
        geometry = nt.nodes.new("ShaderNodeNewGeometry")
        dot = nt.nodes.new("ShaderNodeVectorMath")
        dot.operation = "DOT_PRODUCT"
        nt.links.new(geometry.outputs["Incoming"], dot.inputs[0])
        nt.links.new(geometry.outputs[normal], dot.inputs[1])
        mix = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeMixShader")
        nt.links.new(shape(nt, dot.outputs["Value"]), mix.inputs["Fac"])
        return m

    def rim_cubed(nt, cosine):
        flip = nt.nodes.new("ShaderNodeMath")
        flip.operation = "SUBTRACT"
        flip.inputs[0].default_value = 1.0
        nt.links.new(cosine, flip.inputs[1])
        cube = nt.nodes.new("ShaderNodeMath")
        cube.operation = "POWER"
        cube.inputs[1].default_value = 3.0
        nt.links.new(flip.outputs["Value"], cube.inputs[0])
        return cube.outputs["Value"]

    def ramp(nt, cosine):
        r = nt.nodes.new("ShaderNodeValToRGB")
        els = r.color_ramp.elements
        els[0].position, els[0].color = 0.3, (1.0, 1.0, 1.0, 1.0)  # glossy where the surface turns away
        els[1].position, els[1].color = 0.8, (0.0, 0.0, 0.0, 1.0)
        nt.links.new(cosine, r.inputs["Fac"])
        return r.outputs["Color"]
    plane("Floor", 6.0, facing_mix("FloorMat", (0.5, 0.45, 0.4), 0.15, lambda nt, c: c))
    smooth_ball("RimBall", (-0.9, 0, 0.35), 0.35, facing_mix("Rim", (0.8, 0.2, 0.1), 0.2, rim_cubed))
    smooth_ball("RampBall", (0.0, 0, 0.35), 0.35, facing_mix("Ramp", (0.1, 0.3, 0.8), 0.1, ramp))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=0.35, location=(0.9, 0, 0.35))
    bpy.context.active_object.data.materials.append(
        facing_mix("Facets", (0.2, 0.7, 0.2), 0.25, rim_cubed, normal="True Normal"))
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(40), 0, math.radians(-30)), angle=math.radians(5))
    camera_looking_at((0, -3.0, 1.0), (0, 0, 0.3), 32)
    return scene


def sky_world(sky_type):
    """A 128 x 64 scene whose World's Background takes a Sky Texture of sky_type (linked by the
    caller): (scene, world node tree, Background node, Sky Texture node)."""
    scene = reset(64)
    scene.render.resolution_x = 128
    nt = scene.world.node_tree
    sky = nt.nodes.new("ShaderNodeTexSky")
    sky.sky_type = sky_type
    return scene, nt, nt.nodes["Background"], sky


def nishita_sky():
    """Blender's default sky (Sky Texture, Nishita: sun 15 degrees up, its disc on), the sun turned
    by its rotation (70 degrees): a diffuse and a glossy ball on a grey floor, the horizon and the
    glow around the sun in view (its disc out of the frame, its light and shadows in it). A Mapping
    node (Z 40 degrees) on the sky's Vector, which Cycles 3.4 ignores for a Nishita sky (measured:
    the image is bit-identical with Z 0 or 90, X 90, or the Mapping's input unlinked)."""
    scene, nt, bg, sky = sky_world("NISHITA")
    sky.sun_rotation = math.radians(70)
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(40))
    nt.links.new(nt.nodes.new("ShaderNodeTexCoord").outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], sky.inputs["Vector"])
    nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 0.05  # the sky is bright: W / m^2 in Blender's units
    plane("Floor", 8.0, diffuse_material("FloorMat", (0.5, 0.5, 0.5)))
    smooth_ball("DiffuseBall", (-0.6, 0, 0.5), 0.5, diffuse_material("BallMat", (0.8, 0.3, 0.2)))
    smooth_ball("GlossyBall", (0.6, 0, 0.5), 0.5, glossy_material("Gloss", 0.2, (0.9, 0.9, 0.9)))
    camera_looking_at((0, -4.0, 1.2), (0, 0, 0.6), 35)
    return scene


def ray_type_material(name, output, first, second):
    """Mix Shader (Fac = Light Path's `output`) of two stock shader nodes ((node type, inputs)
    each): rays of that type see the second."""
    m = mix_material(name, first, second, 0.5)
    nt = m.node_tree
    mix = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeMixShader")
    nt.links.new(nt.nodes.new("ShaderNodeLightPath").outputs[output], mix.inputs["Fac"])
    return m


def camera_backdrop(scene, lit_color, lit_strength, backdrop_color):
    """The World: Mix Shader (Fac = Light Path > Is Camera Ray) of a Background that lights the
    scene and one the camera sees."""
    nt = scene.world.node_tree
    out = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputWorld")
    lit, backdrop = nt.nodes["Background"], nt.nodes.new("ShaderNodeBackground")
    lit.inputs["Color"].default_value = lit_color + (1.0,)
    lit.inputs["Strength"].default_value = lit_strength
    backdrop.inputs["Color"].default_value = backdrop_color + (1.0,)
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(nt.nodes.new("ShaderNodeLightPath").outputs["Is Camera Ray"], mix.inputs["Fac"])
    nt.links.new(lit.outputs[0], mix.inputs[1])
    nt.links.new(backdrop.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])


def light_path_rays():
    """Light Path > Is Camera Ray, as artists use it: the World lights warm and shows the camera
    a dark blue backdrop; a ball green to the camera and red to every other ray (its
    reflection in the glossy floor, its bounce light); a glowing card the camera sees through
    (Emission, Transparent to camera rays) lighting the scene from the frame's top left."""
    scene = reset(64)
    scene.render.resolution_x = 128
    camera_backdrop(scene, (1.0, 0.9, 0.8), 0.6, (0.05, 0.1, 0.3))
    floor = node_material("FloorMat", "ShaderNodeBsdfPrincipled", {"Base Color": (0.5, 0.5, 0.5, 1.0),
                                                                   "Roughness": 0.3}, output="BSDF")
    plane("Floor", 6.0, floor)
    smooth_ball("CameraGreenBall", (-0.3, 0, 0.4), 0.4, ray_type_material(
        "GreenToCamera", "Is Camera Ray", ("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.15, 0.1, 1.0)}),
        ("ShaderNodeBsdfDiffuse", {"Color": (0.15, 0.7, 0.15, 1.0)})))
    card = ray_type_material("HiddenGlow", "Is Camera Ray", ("ShaderNodeEmission", {"Color": (1, 1, 1, 1),
                                                                                    "Strength": 6.0}),
                             ("ShaderNodeBsdfTransparent", {"Color": (1, 1, 1, 1)}))
    quad_object("GlowCard", 0.8, 0.5, (0.7, 0.2, 1.1), (60, 0, 20), card)
    camera_looking_at((0, -3.2, 1.1), (0, 0, 0.45), 30)
    return scene


def light_path_shadow_rays():
    """Light Path > Is Shadow Ray: a smooth glass ball whose shadow rays pass (Mix Shader of
    Glass and, for shadow rays, Transparent) and a diffuse ball beside it, under a point lamp
    (radius 0) on a floor; the World lights nothing and shows the camera a blue backdrop.
    Refractive caustics off: Cycles' path tracer cannot find a point lamp through glass, which
    BDPT can. A light that rays can hit, shining through the glass, would be a case where
    Cycles weighs the unblocked shadow ray and the refracted ray by their MIS weights, which
    the engine does not (docs/scene-format.md, Ray visibility)."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.cycles.caustics_refractive = False
    camera_backdrop(scene, (0.0, 0.0, 0.0), 1.0, (0.1, 0.15, 0.35))
    plane("Floor", 6.0, diffuse_material("FloorMat", (0.6, 0.6, 0.6)))
    glass = ray_type_material("ShadowlessGlass", "Is Shadow Ray",
                              ("ShaderNodeBsdfGlass", {"Color": (1, 1, 1, 1), "Roughness": 0.0, "IOR": 1.45}),
                              ("ShaderNodeBsdfTransparent", {"Color": (1, 1, 1, 1)}))
    next(n for n in glass.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfGlass").distribution = "SHARP"
    smooth_ball("ShadowlessGlassBall", (0.5, 0, 0.4), 0.4, glass)
    smooth_ball("DiffuseBall", (-0.6, 0, 0.4), 0.4, diffuse_material("BallMat", (0.7, 0.4, 0.2)))
    light("POINT", "Key", 150.0, (0.9, -0.6, 2.4), shadow_soft_size=0.0)
    camera_looking_at((0, -3.2, 1.1), (0, 0, 0.45), 30)
    return scene


def mesh_derived_attributes():
    """Geometry > Pointiness and Random Per Island, which Cycles derives from the evaluated mesh:
    a subdivided Suzanne and a torus glowing by their Pointiness through a Color Ramp (0.47 to
    0.53: ridges white, hollows black), and one mesh of twelve separate cubes (twelve islands,
    two of them sharing a vertex position but no edge: still two) glowing by Random Per Island
    through a three-colour ramp; emission only, so the values are what the image shows."""
    scene = reset(64)
    scene.render.resolution_x = 128

    def glow(name, output, stops):
        m = emission_material(name, strength=1.0)
        nt = m.node_tree
        ramp = nt.nodes.new("ShaderNodeValToRGB")
        els = ramp.color_ramp.elements
        for i, (pos, color) in enumerate(stops):
            el = els[i] if i < len(els) else els.new(pos)
            el.position, el.color = pos, color + (1.0,)
        nt.links.new(nt.nodes.new("ShaderNodeNewGeometry").outputs[output], ramp.inputs["Fac"])
        nt.links.new(ramp.outputs["Color"], nt.nodes["Emission"].inputs["Color"])
        return m
    edges = glow("Edges", "Pointiness", ((0.47, (0.0, 0.0, 0.0)), (0.53, (1.0, 0.9, 0.7))))
    bpy.ops.mesh.primitive_monkey_add(size=1.0, location=(-1.3, 0, 0.5), rotation=(0, 0, math.radians(20)))
    monkey = bpy.context.active_object
    monkey.modifiers.new("Subdivision", "SUBSURF").levels = 1
    bpy.ops.object.shade_smooth()
    monkey.data.materials.append(edges)
    bpy.ops.mesh.primitive_torus_add(major_radius=0.45, minor_radius=0.15, location=(0, 0, 0.5),
                                     rotation=(math.radians(60), 0, 0))
    bpy.context.active_object.data.materials.append(edges)
    islands = glow("Islands", "Random Per Island", ((0.0, (0.9, 0.1, 0.1)), (0.5, (0.1, 0.8, 0.2)),
                                                    (1.0, (0.1, 0.2, 0.9))))
    verts, faces = [], []
    for i in range(12):
        x, y = 0.9 + 0.3 * (i % 4), 0.25 - 0.3 * (i // 4)
        if i == 5:  # shares a corner position with cube 4, no edge: Cycles welds neither for islands
            x -= 0.05
        base = len(verts)
        verts += [(x + dx * 0.25, y + dy * 0.25, 0.3 + dz * 0.25) for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)]
        faces += [tuple(base + k for k in f) for f in ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6),
                                                        (0, 2, 6, 4), (1, 5, 7, 3))]
    me = bpy.data.meshes.new("CubesMesh")
    me.from_pydata(verts, [], faces)
    me.update()
    cubes = link(bpy.data.objects.new("Cubes", me))
    cubes.data.materials.append(islands)
    camera_looking_at((0, -4.0, 2.0), (0, 0, 0.45), 40)
    return scene


def wireframe_parametric():
    """Wireframe and Geometry > Parametric, computed from the hit's triangle (Blender's
    triangulation: quads show their diagonals): emission tiles seen from above, a subdivided
    tile (wires 0.03 wide), a rotated and scaled ico sphere (wires 0.05, in world units after
    the object's scale), Parametric as the colour of a triangulated tile, and wires over it."""
    def wires(size):
        def build(nt, _):
            w = nt.nodes.new("ShaderNodeWireframe")
            w.inputs["Size"].default_value = size
            return w.outputs["Fac"]
        return build

    def parametric(nt, _):
        return nt.nodes.new("ShaderNodeNewGeometry").outputs["Parametric"]

    def parametric_wires(nt, _):
        mix = nt.nodes.new("ShaderNodeMixRGB")
        mix.blend_type = "ADD"
        mix.inputs["Fac"].default_value = 1.0
        nt.links.new(nt.nodes.new("ShaderNodeNewGeometry").outputs["Parametric"], mix.inputs["Color1"])
        nt.links.new(wires(0.04)(nt, None), mix.inputs["Color2"])
        return mix.outputs["Color"]
    emission_tiles((("Wires", wires(0.03)), ("Parametric", parametric), ("ParametricWires", parametric_wires),
                    ("SphereWires", wires(0.05))), rows=1)
    for name, cuts in (("Wires", 3), ("Parametric", 1), ("ParametricWires", 2)):
        ob = bpy.data.objects[name]
        bpy.context.view_layer.objects.active = ob
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.mesh.subdivide(number_cuts=cuts)
        bpy.ops.object.mode_set(mode="OBJECT")
    sphere_tile = bpy.data.objects["SphereWires"]
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.4, location=sphere_tile.location)
    sphere = bpy.context.active_object
    sphere.data.materials.append(sphere_tile.active_material)
    sphere.rotation_euler = (0.4, 0.3, 0.2)
    sphere.scale = (1.0, 1.2, 0.8)
    bpy.data.objects.remove(sphere_tile, do_unlink=True)


def ambient_occlusion():
    """The Ambient Occlusion node, emission only (no light): a floor, a cube, an inner corner of
    two walls and an open box glowing by AO's Color (white, Distance 0.5: darker near where they
    meet; the box's insides are the backs of its faces); a
    torus through a Color Ramp of AO (0.3 black to 0.9 orange, the dirt masks artists build);
    a cube with Only Local (the floor under it does not darken it, Distance 1) and a ball with
    Inside (8 samples, Distance 0.3)."""
    scene = reset(64)
    scene.render.resolution_x = 128

    def glow(name, build):
        m = emission_material(name, strength=1.0)
        nt = m.node_tree
        ao = nt.nodes.new("ShaderNodeAmbientOcclusion")
        nt.links.new(build(nt, ao), nt.nodes["Emission"].inputs["Color"])
        return m, ao

    def ao_color(distance):
        def build(nt, ao):
            ao.inputs["Distance"].default_value = distance
            return ao.outputs["Color"]
        return build

    def dirt(nt, ao):
        ao.inputs["Distance"].default_value = 0.4
        ramp = nt.nodes.new("ShaderNodeValToRGB")
        els = ramp.color_ramp.elements
        els[0].position, els[0].color = 0.3, (0.0, 0.0, 0.0, 1.0)
        els[1].position, els[1].color = 0.9, (1.0, 0.6, 0.2, 1.0)
        nt.links.new(ao.outputs["AO"], ramp.inputs["Fac"])
        return ramp.outputs["Color"]
    plain, _ = glow("AoColor", ao_color(0.5))
    plane("Floor", 6.0, plain)
    bpy.ops.mesh.primitive_cube_add(size=0.6, location=(-1.2, 0.2, 0.3))
    bpy.context.active_object.data.materials.append(plain)
    for name, size, location, rotation in (("WallA", (1.2, 0.8), (0.2, 0.9, 0.4), (90, 0, 0)),
                                           ("WallB", (1.2, 0.8), (-0.4, 0.3, 0.4), (90, 0, 90))):
        quad_object(name, size[0], size[1], location, rotation, plain)
    dirty, _ = glow("AoDirt", dirt)
    bpy.ops.mesh.primitive_torus_add(major_radius=0.35, minor_radius=0.12, location=(0.3, -0.3, 0.13))
    bpy.context.active_object.data.materials.append(dirty)
    local, ao = glow("AoLocal", ao_color(1.0))
    ao.only_local = True
    bpy.ops.mesh.primitive_cube_add(size=0.5, location=(1.3, 0.3, 0.25))
    bpy.context.active_object.data.materials.append(local)
    # An open box seen from above: the camera sees the backs of its walls and floor (their
    # normals point out), and Cycles turns the normal toward the camera's ray: dark inner corners.
    verts = [(x, y, z) for z in (0.0, 0.4) for y in (-1.25, -0.75) for x in (-0.55, -0.05)]
    faces = [(0, 2, 3, 1), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]  # no top
    me = bpy.data.meshes.new("OpenBoxMesh")
    me.from_pydata(verts, [], faces)
    me.update()
    open_box = link(bpy.data.objects.new("OpenBox", me))
    open_box.data.materials.append(plain)
    inside, ao = glow("AoInside", ao_color(0.3))
    ao.inside, ao.samples = True, 8
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(1.0, -0.7, 0.3))
    bpy.context.active_object.data.materials.append(inside)
    camera_looking_at((0, -4.0, 2.4), (0, 0, 0.3), 35)
    return scene


def mapped_normals():
    """Shading normals moved by Bump and Normal Map nodes, lit by a sun and a dim sky: a diffuse
    ball bumped by a Noise texture (strength 0.6), a glossy floor bumped by a finer Noise
    (roughness 0.35, strength 0.4) and a glossy ball whose Normal Map (tangent space, strength
    0.7, Blender's MikkTSpace tangents) reads a Noise texture's colour mixed halfway toward a
    flat normal map's (0.5, 0.5, 1), as normal maps' colours are. (With the Noise's colour
    itself, blue near 0.5, the normals lie near the surface, where Cycles lets light through
    a mapped normal that the engine does not: README.) Cycles shadows diffuse closures under a moved normal and
    bends normals that would reflect below the surface; both engines must agree for path
    tracing and BDPT (whose light paths see the surface as camera paths do)."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.1, 0.12, 0.16, 1.0)

    def bumped(name, shader, inputs, noise_scale, strength, distance=0.1):
        m, nt, out, bsdf = shader_material(name, shader, inputs)
        noise = nt.nodes.new("ShaderNodeTexNoise")
        noise.inputs["Scale"].default_value = noise_scale
        bump = nt.nodes.new("ShaderNodeBump")
        bump.inputs["Strength"].default_value = strength
        bump.inputs["Distance"].default_value = distance
        nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
        nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
        nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
        return m
    plane("Floor", 8.0, bumped("BumpedGloss", "ShaderNodeBsdfGlossy", {"Color": (0.6, 0.6, 0.6, 1.0), "Roughness": 0.35},
                               12.0, 0.4))
    smooth_ball("BumpedBall", (-0.7, 0, 0.5), 0.5, bumped("BumpedDiffuse", "ShaderNodeBsdfDiffuse",
                                                         {"Color": (0.8, 0.4, 0.2, 1.0)}, 6.0, 0.6))
    m, nt, out = empty_material("NormalMapped")
    bsdf = nt.nodes.new("ShaderNodeBsdfGlossy")
    bsdf.inputs["Color"].default_value = (0.7, 0.8, 0.9, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.25
    noise = nt.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 4.0
    nmap = nt.nodes.new("ShaderNodeNormalMap")
    nmap.inputs["Strength"].default_value = 0.7
    # A normal map's colours: blue near 1 (the normal mostly kept), red and green around 0.5.
    flat = nt.nodes.new("ShaderNodeMixRGB")
    flat.inputs["Fac"].default_value = 0.5
    flat.inputs["Color2"].default_value = (0.5, 0.5, 1.0, 1.0)
    nt.links.new(noise.outputs["Color"], flat.inputs["Color1"])
    nt.links.new(flat.outputs["Color"], nmap.inputs["Color"])
    nt.links.new(nmap.outputs["Normal"], bsdf.inputs["Normal"])
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    # Low-poly (12 x 8), smooth shaded: its tangents vary across each face, as MikkTSpace
    # interpolates them, where one face's UV derivatives would be constant.
    ball = uv_sphere(segments=12, ring_count=8, radius=0.5, location=(0.7, 0, 0.5))
    ball.name = "NormalMappedBall"
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(m)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(45), 0, math.radians(30)), angle=math.radians(3))
    camera_looking_at((0, -3.6, 1.4), (0, 0, 0.4), 35)
    return scene


def bevel():
    """Bevel nodes rounding hard edges in the shading, lit by a sun and a dim sky: a rotated
    cube, Principled (roughness 0.35), its Normal from a Bevel (radius 0.1, 8 samples); a cube
    whose Bump (a fine Noise) takes its Normal from a Bevel (radius 0.06); a faceted (flat-shaded,
    12-sided) glossy cylinder whose facets' edges a Bevel (radius 0.05) rounds; all on a near-mirror
    floor (roughness 0.05) that shows the bevelled edges. Cycles skips the Bevel after diffuse
    and rough bounces (a bounce density below 8); the engine keeps it for every ray, so on a
    floor of roughness 0.15 the cylinder's reflection differs (README)."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.1, 0.12, 0.16, 1.0)

    def bevelled(name, shader, inputs, radius, samples=8, noise_scale=None):
        m, nt, out, bsdf = shader_material(name, shader, inputs)
        bev = nt.nodes.new("ShaderNodeBevel")
        bev.samples = samples
        bev.inputs["Radius"].default_value = radius
        normal = bev.outputs["Normal"]
        if noise_scale is not None:
            noise = nt.nodes.new("ShaderNodeTexNoise")
            noise.inputs["Scale"].default_value = noise_scale
            bump = nt.nodes.new("ShaderNodeBump")
            bump.inputs["Strength"].default_value = 0.3
            bump.inputs["Distance"].default_value = 0.05
            nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
            nt.links.new(normal, bump.inputs["Normal"])
            normal = bump.outputs["Normal"]
        nt.links.new(normal, bsdf.inputs["Normal"])
        nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
        return m
    m, nt, out = empty_material("FloorGloss")
    gloss = nt.nodes.new("ShaderNodeBsdfGlossy")
    gloss.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1.0)
    gloss.inputs["Roughness"].default_value = 0.05
    nt.links.new(gloss.outputs[0], out.inputs["Surface"])
    plane("Floor", 8.0, m)
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(-0.95, 0.1, 0.4), rotation=(0, 0, math.radians(30)))
    bpy.context.active_object.data.materials.append(
        bevelled("BevelPrincipled", "ShaderNodeBsdfPrincipled", {"Base Color": (0.8, 0.3, 0.2, 1.0), "Roughness": 0.35},
                 0.1))
    bpy.ops.mesh.primitive_cube_add(size=0.6, location=(0.05, 0.5, 0.3), rotation=(0, 0, math.radians(-20)))
    bpy.context.active_object.data.materials.append(
        bevelled("BevelBump", "ShaderNodeBsdfDiffuse", {"Color": (0.3, 0.6, 0.8, 1.0)}, 0.06, noise_scale=20.0))
    bpy.ops.mesh.primitive_cylinder_add(vertices=12, radius=0.35, depth=0.7, location=(0.9, -0.1, 0.35))
    bpy.context.active_object.data.materials.append(
        bevelled("BevelGlossy", "ShaderNodeBsdfGlossy", {"Color": (0.9, 0.8, 0.5, 1.0), "Roughness": 0.2}, 0.05))
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(50), 0, math.radians(-35)), angle=math.radians(3))
    camera_looking_at((0.3, -3.4, 1.6), (0, 0, 0.35), 35)
    return scene


def displacement():
    """Displacement into the Material Output, Cycles' default Bump Only (the way texture sets from
    Node Wrangler and asset libraries arrive), lit by a low sun and a dim sky: a Principled floor
    displaced by Wave bands (object space, scale 0.04), a Principled ball scaled 0.45 by its object
    and displaced by a Noise in object space (the scale applies to the offset), and a diffuse ball
    displaced by a Noise in world space whose own Bump (Wave rings, Normal unlinked) bumps the
    displaced normal further."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.1, 0.12, 0.16, 1.0)

    def displaced(name, shader, inputs, texture, texture_inputs, space, scale, bump_rings=None):
        m, nt, out, bsdf = shader_material(name, shader, inputs)
        tex = add_node(nt, texture, texture_inputs)
        disp = add_node(nt, "ShaderNodeDisplacement", {"Scale": scale}, space=space)
        nt.links.new(tex.outputs["Fac"], disp.inputs["Height"])
        nt.links.new(disp.outputs["Displacement"], out.inputs["Displacement"])
        if bump_rings is not None:
            rings = add_node(nt, "ShaderNodeTexWave", {"Scale": bump_rings}, wave_type="RINGS")
            bump = add_node(nt, "ShaderNodeBump", {"Strength": 0.5, "Distance": 0.02})
            nt.links.new(rings.outputs["Fac"], bump.inputs["Height"])
            nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
        nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
        return m
    smooth = {"Detail": 0.0, "Distortion": 0.0}
    plane("Floor", 8.0, displaced("WavyFloor", "ShaderNodeBsdfPrincipled",
                                  {"Base Color": (0.6, 0.6, 0.6, 1.0), "Roughness": 0.3},
                                  "ShaderNodeTexWave", dict(smooth, Scale=1.5), "OBJECT", 0.04))
    ball = smooth_ball("ScaledBall", (-0.6, 0, 0.45), 1.0, displaced(
        "NoisyPrincipled", "ShaderNodeBsdfPrincipled", {"Base Color": (0.8, 0.35, 0.15, 1.0), "Roughness": 0.4},
        "ShaderNodeTexNoise", dict(smooth, Scale=3.0), "OBJECT", 0.15))
    ball.scale = (0.45, 0.45, 0.45)
    smooth_ball("WorldBall", (0.6, 0.1, 0.4), 0.4, displaced(
        "NoisyDiffuse", "ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.45, 0.8, 1.0)},
        "ShaderNodeTexNoise", dict(smooth, Scale=3.0), "WORLD", 0.05, bump_rings=1.0))
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(62), 0, math.radians(-40)), angle=math.radians(3))
    camera_looking_at((0, -3.2, 1.3), (0, 0, 0.35), 35)
    return scene


def true_displacement():
    """Material > Settings > Displacement set to move the surface, lit by a low sun: a 64 x 64
    grid (flat shaded) whose Principled material is Displacement Only, a Noise's height in object
    space (scale 0.3: hills that shadow one another), and a smooth ico sphere scaled 0.5 by its
    object whose material is Displacement and Bump, Wave bands in object space (scale 0.15),
    on it; a UV sphere moved by a Vector Displacement in tangent space (a Noise's colour)."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.1, 0.12, 0.16, 1.0)

    def displaced(name, color, texture, texture_inputs, scale, method):
        m, nt, out, bsdf = shader_material(name, "ShaderNodeBsdfPrincipled",
                                           {"Base Color": color + (1.0,), "Roughness": 0.5})
        m.cycles.displacement_method = method
        tex = add_node(nt, texture, texture_inputs)
        disp = add_node(nt, "ShaderNodeDisplacement", {"Scale": scale})
        nt.links.new(tex.outputs["Fac"], disp.inputs["Height"])
        nt.links.new(disp.outputs["Displacement"], out.inputs["Displacement"])
        nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
        return m
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=64, y_subdivisions=64, size=5.0)
    bpy.context.active_object.data.materials.append(displaced(
        "Hills", (0.55, 0.5, 0.4), "ShaderNodeTexNoise", {"Scale": 3.0, "Detail": 0.0}, 0.8, "DISPLACEMENT"))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=5, radius=1.0, location=(0.3, 0.2, 0.9))
    ball = bpy.context.active_object
    ball.scale = (0.5, 0.5, 0.5)
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(displaced(
        "Banded", (0.2, 0.4, 0.8), "ShaderNodeTexWave", {"Scale": 1.0, "Distortion": 0.0, "Detail": 0.0}, 0.15, "BOTH"))
    # A Vector Displacement in tangent space (Blender's tangents): a Noise's colour, centred.
    m, nt, out, bsdf = shader_material("Knobbly", "ShaderNodeBsdfPrincipled", {"Base Color": (0.7, 0.25, 0.2, 1.0)})
    m.cycles.displacement_method = "DISPLACEMENT"
    noise = add_node(nt, "ShaderNodeTexNoise", {"Scale": 2.0, "Detail": 0.0})
    vdisp = add_node(nt, "ShaderNodeVectorDisplacement", {"Midlevel": 0.5, "Scale": 0.3})
    nt.links.new(noise.outputs["Color"], vdisp.inputs["Vector"])
    nt.links.new(vdisp.outputs["Displacement"], out.inputs["Displacement"])
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    ball = uv_sphere(segments=96, ring_count=48, radius=0.45, location=(-1.2, 0.5, 0.8))
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(m)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(65), 0, math.radians(-50)), angle=math.radians(3))
    camera_looking_at((0, -4.4, 2.2), (0, 0, 0.45), 35)
    return scene


def camera_data():
    """Camera Data's three outputs, as artists use them for depth cues: a floor coloured by a
    Color Ramp of its View Z Depth (through a Map Range from 2 to 9 units), a ball coloured by the
    absolute View Vector, and a cube mixing a diffuse red and a glossy grey by its View Distance;
    under a sun and a grey sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.25, 0.25, 0.3, 1.0)

    def by_camera(name, output, shape):
        """A material whose colour or Mix factor comes from Camera Data's output through shape(nt, socket)."""
        m, nt, out = empty_material(name)
        cam = add_node(nt, "ShaderNodeCameraData")
        nt.links.new(shape(nt, cam.outputs[output]), out.inputs["Surface"])
        return m

    def ramped_depth(nt, depth):
        rng = add_node(nt, "ShaderNodeMapRange", {"From Min": 2.0, "From Max": 9.0})
        ramp = add_node(nt, "ShaderNodeValToRGB")
        ramp.color_ramp.elements[0].color = (0.9, 0.85, 0.7, 1.0)
        ramp.color_ramp.elements[1].color = (0.1, 0.2, 0.5, 1.0)
        diffuse = add_node(nt, "ShaderNodeBsdfDiffuse")
        nt.links.new(depth, rng.inputs["Value"])
        nt.links.new(rng.outputs["Result"], ramp.inputs["Fac"])
        nt.links.new(ramp.outputs["Color"], diffuse.inputs["Color"])
        return diffuse.outputs[0]

    def absolute_vector(nt, vector):
        absolute = add_node(nt, "ShaderNodeVectorMath", operation="ABSOLUTE")
        diffuse = add_node(nt, "ShaderNodeBsdfDiffuse")
        nt.links.new(vector, absolute.inputs[0])
        nt.links.new(absolute.outputs["Vector"], diffuse.inputs["Color"])
        return diffuse.outputs[0]

    def mixed_by_distance(nt, distance):
        rng = add_node(nt, "ShaderNodeMapRange", {"From Min": 3.5, "From Max": 5.0})
        mix = add_node(nt, "ShaderNodeMixShader")
        red = add_node(nt, "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.1, 0.05, 1.0)})
        grey = add_node(nt, "ShaderNodeBsdfGlossy", {"Color": (0.8, 0.8, 0.8, 1.0), "Roughness": 0.3})
        nt.links.new(distance, rng.inputs["Value"])
        nt.links.new(rng.outputs["Result"], mix.inputs["Fac"])
        nt.links.new(red.outputs[0], mix.inputs[1])
        nt.links.new(grey.outputs[0], mix.inputs[2])
        return mix.outputs[0]
    plane("Floor", 16.0, by_camera("DepthFloor", "View Z Depth", ramped_depth))
    smooth_ball("ViewBall", (-0.8, 0.2, 0.5), 0.5, by_camera("ViewVector", "View Vector", absolute_vector))
    bpy.ops.mesh.primitive_cube_add(size=0.9, location=(0.9, 0.6, 0.45), rotation=(0, 0, math.radians(25)))
    bpy.context.active_object.data.materials.append(by_camera("DistanceCube", "View Distance", mixed_by_distance))
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(40), 0, math.radians(30)), angle=math.radians(3))
    camera_looking_at((0.5, -4.0, 1.6), (0, 0.5, 0.3), 35)
    return scene


def light_nodes():
    """Lamps whose node trees colour and scale them, as Cycles multiplies their Emission into the
    lamp: a 120 W point lamp through a Blackbody of 2800 K and a Light Falloff's Quadratic output
    (strength 1.8), and a 1 m square area lamp of 80 W whose Emission is a pale blue at strength 0.6,
    over a grey floor, a white ball and a cube; a dim sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.02, 0.02, 0.03, 1.0)
    plane("Floor", 10.0)
    smooth_ball("Ball", (-0.6, 0.2, 0.5), 0.5, diffuse_material("White", (0.8, 0.8, 0.8)))
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.8, 0.4, 0.4), rotation=(0, 0, math.radians(20)))
    bpy.context.active_object.data.materials.append(diffuse_material("Cube", (0.7, 0.7, 0.6)))

    def lamp_nodes(ob):
        data = ob.data
        data.use_nodes = True
        nt = data.node_tree
        return nt, next(n for n in nt.nodes if n.bl_idname == "ShaderNodeEmission")
    nt, emission = lamp_nodes(light("POINT", "Warm", 120.0, (-1.5, -1.0, 2.2), shadow_soft_size=0.1))
    blackbody = add_node(nt, "ShaderNodeBlackbody", {"Temperature": 2800.0})
    falloff = add_node(nt, "ShaderNodeLightFalloff", {"Strength": 1.8})
    nt.links.new(blackbody.outputs["Color"], emission.inputs["Color"])
    nt.links.new(falloff.outputs["Quadratic"], emission.inputs["Strength"])
    nt, emission = lamp_nodes(light("AREA", "Cool", 80.0, (1.6, -0.8, 1.8), rotation=(math.radians(50), 0, math.radians(60)),
                                    size=1.0))
    emission.inputs["Color"].default_value = (0.4, 0.7, 1.0, 1.0)
    emission.inputs["Strength"].default_value = 0.6
    camera_looking_at((0.2, -4.0, 1.8), (0, 0.3, 0.4), 35)
    return scene


def light_falloff():
    """Light Falloff by the length of the ray the emitted light travels: a 40 W point lamp
    (radius 5 cm) through its Linear output (strength 1.5), a 0.6 m square area lamp of 60 W
    through Quadratic with Smooth 1.0, and an emissive card facing the camera whose Emission
    strength is the Constant output (0.4, so its brightness depends on the camera's distance
    and on each lit point's), over a grey floor with a white ball; a dim sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.02, 0.02, 0.03, 1.0)
    plane("Floor", 10.0)
    smooth_ball("Ball", (-0.3, 0.3, 0.45), 0.45, diffuse_material("White", (0.8, 0.8, 0.8)))

    def falloff_into(nt, emission, output, strength, smooth=0.0):
        falloff = add_node(nt, "ShaderNodeLightFalloff", {"Strength": strength, "Smooth": smooth})
        nt.links.new(falloff.outputs[output], emission.inputs["Strength"])

    def lamp_nodes(ob):
        ob.data.use_nodes = True
        nt = ob.data.node_tree
        return nt, next(n for n in nt.nodes if n.bl_idname == "ShaderNodeEmission")
    falloff_into(*lamp_nodes(light("POINT", "Linear", 40.0, (-1.4, -0.8, 1.2), shadow_soft_size=0.05)), "Linear", 1.5)
    falloff_into(*lamp_nodes(light("AREA", "Smooth", 60.0, (1.3, -0.4, 1.6), rotation=(math.radians(35), 0, math.radians(70)),
                                   size=0.6)), "Quadratic", 1.0, smooth=1.0)
    m, nt, out = empty_material("Card")
    emission = add_node(nt, "ShaderNodeEmission", {"Color": (1.0, 0.75, 0.45, 1.0)})
    falloff_into(nt, emission, "Constant", 0.4)
    nt.links.new(emission.outputs["Emission"], out.inputs["Surface"])
    card = link(bpy.data.objects.new("Card", quad_mesh("CardMesh", 0.5, 0.35)))
    card.location = (0.7, 0.9, 0.6)
    card.rotation_euler = (math.radians(80), 0, math.radians(-10))
    card.data.materials.append(m)
    camera_looking_at((0.2, -4.0, 1.8), (0, 0.3, 0.4), 35)
    return scene


def lamp_image_path():
    d = os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir or "/tmp"
    return os.path.join(d, "rdv_test_lamp_cells.exr")


def lamp_textures():
    """Lamps whose emission varies over them, as Cycles shades the point light leaves from: a
    1.2 x 0.8 m area lamp of 200 W tilted toward the camera, showing a 4 x 3 image of coloured
    cells (Closest) over it through Geometry > Parametric, seen in a glossy floor (Principled,
    roughness 0.08) and lighting it; a spot lamp of 400 W whose colour is a Color Ramp of a
    Gradient of its Parametric (Cycles' spherical map of the direction light leaves by: a seam
    where the direction's azimuth wraps); and a white ball; a dim sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.02, 0.02, 0.03, 1.0)
    floor = node_material("GlossyFloor", "ShaderNodeBsdfPrincipled",
                          {"Base Color": (0.35, 0.35, 0.35, 1.0), "Roughness": 0.08})
    plane("Floor", 10.0, material=floor)
    smooth_ball("Ball", (-0.9, 0.6, 0.4), 0.4, diffuse_material("White", (0.8, 0.8, 0.8)))

    def lamp_nodes(ob):
        ob.data.use_nodes = True
        nt = ob.data.node_tree
        return nt, next(n for n in nt.nodes if n.bl_idname == "ShaderNodeEmission")
    # The image: cells whose colours tell its corners apart (a mirrored or turned image differs).
    import numpy as np
    cells = np.array([[(1.0, 0.1, 0.1), (1.0, 1.0, 1.0), (0.1, 0.1, 1.0), (0.05, 0.05, 0.05)],
                      [(0.1, 1.0, 0.1), (0.05, 0.05, 0.05), (1.0, 1.0, 0.1), (1.0, 0.5, 0.1)],
                      [(0.05, 0.05, 0.05), (0.1, 1.0, 1.0), (1.0, 1.0, 1.0), (1.0, 0.1, 1.0)]], np.float32)
    h, w = cells.shape[:2]
    img = bpy.data.images.new("lamp_cells_src", w, h, float_buffer=True, alpha=False)
    img.pixels.foreach_set(np.concatenate([cells, np.ones((h, w, 1), np.float32)], axis=2).reshape(-1))
    path = lamp_image_path()
    img.filepath_raw = path
    img.file_format = "OPEN_EXR"
    img.save()
    bpy.data.images.remove(img)
    nt, emission = lamp_nodes(light("AREA", "Cells", 200.0, (0.5, 1.2, 1.1), rotation=(math.radians(-40), 0, 0),
                                    shape="RECTANGLE", size=1.2, size_y=0.8))
    geometry = nt.nodes.new("ShaderNodeNewGeometry")
    image = nt.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.load(path)
    image.interpolation = "Closest"
    nt.links.new(geometry.outputs["Parametric"], image.inputs["Vector"])
    nt.links.new(image.outputs["Color"], emission.inputs["Color"])
    nt, emission = lamp_nodes(light("SPOT", "Swirl", 400.0, (-1.0, -0.2, 2.2), rotation=(math.radians(10), 0, 0),
                                    spot_size=math.radians(80), spot_blend=0.1, shadow_soft_size=0.05))
    geometry = nt.nodes.new("ShaderNodeNewGeometry")
    gradient = nt.nodes.new("ShaderNodeTexGradient")
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (1.0, 0.3, 0.05, 1.0)
    ramp.color_ramp.elements[1].color = (0.1, 0.4, 1.0, 1.0)
    nt.links.new(geometry.outputs["Parametric"], gradient.inputs["Vector"])
    nt.links.new(gradient.outputs["Fac"], ramp.inputs["Fac"])
    nt.links.new(ramp.outputs["Color"], emission.inputs["Color"])
    camera_looking_at((0.2, -4.0, 1.5), (0.1, 0.4, 0.0), 35)
    return scene


def ies_text(name, v_angles, h_angles, candela):
    """A Text datablock holding an IES LM-63 profile (type C) of candela(v, h) in degrees."""
    rows = ["IESNA:LM-63-2002", "[TEST] Rendezvous brightness test", "[LUMINAIRE] %s" % name, "TILT=NONE",
            "1 -1 1.0 %d %d 1 2 0.0 0.0 0.0" % (len(v_angles), len(h_angles)), "1.0 1.0 60",
            " ".join("%g" % v for v in v_angles), " ".join("%g" % h for h in h_angles)]
    rows += [" ".join("%.2f" % candela(v, h) for v in v_angles) for h in h_angles]
    old = bpy.data.texts.get(name)  # from an earlier build in this process (reset keeps texts)
    if old is not None:
        bpy.data.texts.remove(old)
    text = bpy.data.texts.new(name)
    text.write("\n".join(rows) + "\n")
    return text


def ies_lamps():
    """Lamps shaped by IES profiles (an IES Texture into the Emission's Strength, as Blender's
    manual wires it): a point lamp turned 30 degrees about z and tipped 25 degrees whose profile
    (all 360 degrees given) throws a bright lobe to one side, also upward; a spot lamp of radius
    0.1 whose quadrant-symmetric downlight profile has a Blackbody colour and Strength 2 on the
    IES node. A grey floor, a back wall, a white ball; a dim sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.02, 0.02, 0.03, 1.0)
    plane("Floor", 10.0)
    quad_object("Wall", 10.0, 4.0, (0, 2.0, 2.0), (90, 0, 0), diffuse_material("WallMat", (0.6, 0.6, 0.6)))
    smooth_ball("Ball", (0.3, 0.3, 0.45), 0.45, diffuse_material("White", (0.8, 0.8, 0.8)))

    def ies_lamp(ob, text, strength=1.0):
        data = ob.data
        data.use_nodes = True
        nt = data.node_tree
        emission = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeEmission")
        ies = add_node(nt, "ShaderNodeTexIES", {"Strength": strength}, mode="INTERNAL", ies=text)
        nt.links.new(ies.outputs["Fac"], emission.inputs["Strength"])
        return nt, emission
    lobe = ies_text("lobe.ies", [0, 15, 30, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180], [0, 45, 90, 135, 180, 225, 270, 315, 360],
                    lambda v, h: (60.0 + 500.0 * math.exp(-((v - 50.0) / 25.0) ** 2)) * (1.2 + math.cos(math.radians(h - 90.0))))
    ies_lamp(light("POINT", "Lobe", 2.0, (-1.2, -0.2, 2.0), rotation=(math.radians(25), 0, math.radians(30)), shadow_soft_size=0.0), lobe)
    down = ies_text("downlight.ies", [0, 10, 20, 30, 40, 50, 60, 70, 80, 90], [0, 30, 60, 90],
                    lambda v, h: max(0.0, 800.0 * math.cos(math.radians(v)) ** 3) * (1.0 + 0.4 * math.sin(math.radians(h)) ** 2))
    nt, emission = ies_lamp(light("SPOT", "Down", 2.0, (1.3, -0.4, 2.4), spot_size=math.radians(100), spot_blend=0.2,
                                  shadow_soft_size=0.1), down, 2.0)
    blackbody = add_node(nt, "ShaderNodeBlackbody", {"Temperature": 3500.0})
    nt.links.new(blackbody.outputs["Color"], emission.inputs["Color"])
    camera_looking_at((0.0, -5.0, 2.2), (0, 0.5, 0.8), 40)
    return scene


def area_spread():
    """Area lamps with Cycles' Spread (a soft box's slats): a 1 m square lamp of 30 W at 60
    degrees, tipped toward a back wall, and a 0.6 m disk of 12 W at 25 degrees straight over the
    floor, which light pools with sharp-edged falloff; a grey floor, the wall, a white ball; a dim
    sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.02, 0.02, 0.03, 1.0)
    plane("Floor", 10.0)
    quad_object("Wall", 10.0, 4.0, (0, 2.0, 2.0), (90, 0, 0), diffuse_material("WallMat", (0.6, 0.6, 0.6)))
    smooth_ball("Ball", (-0.4, 0.4, 0.45), 0.45, diffuse_material("White", (0.8, 0.8, 0.8)))
    light("AREA", "Slats", 30.0, (-1.0, -0.8, 2.2), rotation=(math.radians(40), 0, math.radians(-15)), size=1.0,
          spread=math.radians(60))
    light("AREA", "Pool", 12.0, (1.1, 0.2, 1.8), shape="DISK", size=0.6, spread=math.radians(25))
    camera_looking_at((0.0, -5.0, 2.2), (0, 0.5, 0.8), 40)
    return scene


def object_attributes():
    """Attribute nodes of type Object and Instancer: one material whose colour is the object's
    custom property "tint" and whose mix toward a glossy coat is its property "coat" (an int) on
    three balls: one with both, one with "tint" on its mesh data instead, one with neither
    (black, as Cycles reads a missing name); a cube coloured by the RNA path "color" (Viewport
    Display); two instances of a collection whose cube reads Instancer "tint", set on each
    instancing empty. A grey floor under a sun, a sky."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.3, 0.35, 0.45, 1.0)
    plane("Floor", 10.0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), math.radians(10), math.radians(30)))

    def attribute_material(name, kind, prop, coat=None):
        m, nt, out = empty_material(name)
        attr = add_node(nt, "ShaderNodeAttribute", attribute_type=kind, attribute_name=prop)
        diffuse = add_node(nt, "ShaderNodeBsdfDiffuse")
        nt.links.new(attr.outputs["Color"], diffuse.inputs["Color"])
        if coat is None:
            nt.links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
            return m
        glossy = add_node(nt, "ShaderNodeBsdfGlossy", {"Roughness": 0.2})
        amount = add_node(nt, "ShaderNodeAttribute", attribute_type=kind, attribute_name=coat)
        scale = add_node(nt, "ShaderNodeMath", operation="MULTIPLY")
        scale.inputs[1].default_value = 0.3
        nt.links.new(amount.outputs["Fac"], scale.inputs[0])
        mix = add_node(nt, "ShaderNodeMixShader")
        nt.links.new(scale.outputs["Value"], mix.inputs["Fac"])
        nt.links.new(diffuse.outputs["BSDF"], mix.inputs[1])
        nt.links.new(glossy.outputs["BSDF"], mix.inputs[2])
        nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
        return m
    tinted = attribute_material("Tinted", "OBJECT", "tint", coat="coat")
    both = smooth_ball("Both", (-1.3, 0.3, 0.45), 0.45, tinted)
    both["tint"] = (0.9, 0.25, 0.1)
    both["coat"] = 2
    on_data = smooth_ball("OnData", (0.0, 0.3, 0.45), 0.45, tinted)
    on_data.data["tint"] = (0.1, 0.5, 0.9)
    smooth_ball("Neither", (1.3, 0.3, 0.45), 0.45, tinted)
    bpy.ops.mesh.primitive_cube_add(size=0.5, location=(-0.6, -0.9, 0.25), rotation=(0, 0, math.radians(25)))
    cube = bpy.context.active_object
    cube.data.materials.append(attribute_material("ByDisplayColor", "OBJECT", "color"))
    cube.color = (0.2, 0.8, 0.3, 1.0)
    kit = bpy.data.collections.new("Kit")
    bpy.ops.mesh.primitive_cube_add(size=0.4, location=(0, 0, 0.2))
    part = bpy.context.active_object
    for c in list(part.users_collection):
        c.objects.unlink(part)
    kit.objects.link(part)
    part.data.materials.append(attribute_material("ByInstancer", "INSTANCER", "tint"))
    for name, x, tint in (("KitA", 0.5, (0.95, 0.8, 0.1)), ("KitB", 1.3, (0.6, 0.1, 0.8))):
        empty = link(bpy.data.objects.new(name, None))
        empty.instance_type = "COLLECTION"
        empty.instance_collection = kit
        empty.location = (x, -1.0, 0.0)
        empty["tint"] = tint
    camera_looking_at((0.0, -5.0, 2.4), (0, 0.0, 0.4), 40)
    return scene


def principled_glass_tint():
    """Cycles 3.4's Principled glass with Specular Tint: its reflection runs from the base colour
    (tint 1) at normal incidence to white at grazing. Two orange glass balls (Transmission 1,
    Specular Tint 1; roughness 0.25 and 0) and one with tint 0 on a dark floor under a large
    area lamp that the balls reflect toward the camera, in a dim world."""
    scene = reset(64)
    scene.render.resolution_x = 128
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.05, 0.06, 1.0)
    plane("Floor", 8.0, diffuse_material("FloorMat", (0.1, 0.1, 0.1)))
    for name, x, roughness, tint in (("TintedRough", -1.1, 0.25, 1.0), ("TintedSmooth", 0.0, 0.0, 1.0),
                                     ("UntintedRough", 1.1, 0.25, 0.0)):
        m = node_material(name, "ShaderNodeBsdfPrincipled", {"Base Color": (0.9, 0.35, 0.1, 1.0), "Transmission": 1.0,
                                                             "Roughness": roughness, "Specular Tint": tint},
                          output="BSDF")
        smooth_ball(name + "Ball", (x, 0, 0.5), 0.5, m)
    light("AREA", "Softbox", 300.0, (0.0, -2.5, 3.0), rotation=(math.radians(40), 0, 0), size=2.0)
    camera_looking_at((0, -4.0, 1.3), (0, 0, 0.45), 35)
    return scene


def preetham_sky():
    """Blender's Sky Texture of type Preetham (turbidity 3, the sun 30 degrees up, to the back
    left): a diffuse and a glossy ball on a grey floor, the horizon in view."""
    scene, nt, bg, sky = sky_world("PREETHAM")
    sky.turbidity = 3.0
    elevation, azimuth = math.radians(30), math.radians(130)
    sky.sun_direction = (math.cos(elevation) * math.sin(azimuth), math.cos(elevation) * math.cos(azimuth),
                         math.sin(elevation))
    nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 0.5
    plane("Floor", 8.0, diffuse_material("FloorMat", (0.5, 0.5, 0.5)))
    smooth_ball("DiffuseBall", (-0.6, 0, 0.5), 0.5, diffuse_material("BallMat", (0.8, 0.3, 0.2)))
    smooth_ball("GlossyBall", (0.6, 0, 0.5), 0.5, glossy_material("Gloss", 0.2, (0.9, 0.9, 0.9)))
    camera_looking_at((0, -4.0, 1.2), (0, 0, 0.6), 35)
    return scene


def film_transparent():
    """Film > Transparent: a diffuse ball, a smooth glass ball and a card half Transparent
    BSDF on a floor small enough that the world shows all around them (a blue sky, lit
    also by a sun). The world seen directly, and through the card, is transparent; through
    the glass only with Transparent Glass on."""
    scene = reset(48)
    scene.render.film_transparent = True
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    plane("Floor", 3.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5)))
    for name, x, material in (("Ball", -0.8, diffuse_material("BallMat", (0.8, 0.3, 0.2))),
                              ("GlassBall", 0.8, node_material("Glass", "ShaderNodeBsdfGlass",
                                                               {"Color": (1, 1, 1, 1), "Roughness": 0.0, "IOR": 1.45},
                                                               distribution="SHARP"))):
        smooth_ball(name, (x, 0, 0.5), 0.5, material)
    card = plane("Card", 0.8, mix_material("HalfTransparent", ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.7, 0.3, 1)}),
                                           ("ShaderNodeBsdfTransparent", {"Color": (1, 1, 1, 1)}), 0.5),
                 location=(0.0, 0.6, 1.5))
    card.rotation_euler = (math.radians(90), 0, 0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)))
    camera_looking_at((0, -4.5, 1.6), (0, 0, 0.75), 55)
    return scene


def light_passes():
    """Cycles' light passes: a diffuse, a glossy (GGX 0.3) and a smooth glass ball on a diffuse
    floor under a blue world and a wide sun, a small emissive ball the camera sees, and a cube of
    thin fog in front (Volume Direct / Indirect; Cycles' volume bounces 2). Every light pass
    has something in it."""
    scene = reset(48)
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    plane("Floor", 3.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5)))
    balls = (("DiffuseBall", -1.0, diffuse_material("BallMat", (0.8, 0.3, 0.2))),
             ("GlossyBall", 0.0, glossy_material("Gloss", 0.3, (0.9, 0.8, 0.6))),
             ("GlassBall", 1.0, node_material("Glass", "ShaderNodeBsdfGlass",
                                              {"Color": (1, 1, 1, 1), "Roughness": 0.0, "IOR": 1.45},
                                              distribution="SHARP")))
    for name, x, material in balls:
        smooth_ball(name, (x, 0, 0.45), 0.45, material)
    lamp = uv_sphere(segments=16, ring_count=8, radius=0.15, location=(0.5, 0.9, 1.3))
    lamp.name = "LampBall"
    lamp.data.materials.append(emission_material("Lamp", (1.0, 0.9, 0.7), 5.0))
    fog = link(bpy.data.objects.new("Fog", box_mesh("FogMesh", 0.7)))
    fog.location = (-0.5, -1.3, 0.45)
    fog.data.materials.append(principled_volume_material("FogMat", Density=0.8, Color=(0.9, 0.9, 0.8, 1.0))[0])
    scene.cycles.volume_bounces = 2
    scene.cycles.blur_glossy = 0.0  # Filter Glossy (BDPT has none): caustics as they are
    scene.cycles.sample_clamp_indirect = 0.0  # BDPT clamps per strategy, not per path (README)
    # A 10 degree sun: the glass ball's caustic (Diffuse Indirect) converges in path tracing.
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)), angle=math.radians(10))
    camera_looking_at((0, -4.5, 1.6), (0, 0, 0.55), 50)
    return scene


def data_passes():
    """Mist, Object Index and Material Index: a diffuse ball (object 3, material 7) and a
    glossy ball (object 5, material 2) on a floor (object 1) running into the distance, a card
    40% Transparent BSDF (object 9, material 4: opaque enough for the default alpha threshold)
    in front of the floor, under a sun and a blue world; linear mist from 2 to 8 units."""
    scene = reset(40)
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    scene.world.mist_settings.start = 2.0
    scene.world.mist_settings.depth = 6.0
    scene.world.mist_settings.falloff = "LINEAR"
    floor = plane("Floor", 12.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5)), location=(0, 3.0, 0))
    floor.pass_index = 1
    ball_mat = diffuse_material("BallMat", (0.8, 0.3, 0.2))
    ball_mat.pass_index = 7
    gloss = glossy_material("Gloss", 0.3, (0.9, 0.8, 0.6))
    gloss.pass_index = 2
    smooth_ball("DiffuseBall", (-0.8, 0, 0.6), 0.6, ball_mat).pass_index = 3
    smooth_ball("GlossyBall", (0.9, 1.5, 0.6), 0.6, gloss).pass_index = 5
    card_mat = mix_material("Card", ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.7, 0.3, 1)}),
                            ("ShaderNodeBsdfTransparent", {"Color": (1, 1, 1, 1)}), 0.4)
    card_mat.pass_index = 4
    card = plane("Card", 0.8, card_mat, location=(0.2, -1.2, 0.3))
    card.rotation_euler = (math.radians(90), 0, 0)
    card.pass_index = 9
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)))
    camera_looking_at((0, -4.5, 1.6), (0, 1.0, 0.5), 40)
    return scene


def shader_aovs():
    """Shader AOVs (View Layer > Shader AOV, AOV Output nodes): a colour AOV "tint" and a value
    AOV "height". A ball writes a Noise texture's colour to tint and its Position's z to
    height; a cube writes a constant tint; the floor writes height only (its z, 0, with an
    offset of 0.25); a card 70% Transparent BSDF in front of the ball writes tint green (below
    the alpha threshold, so the ball behind writes too); the world writes tint from its
    direction (Texture Coordinate > Generated) and a height of 7. Under a sun."""
    scene = reset(48)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    world_tree = scene.world.node_tree
    sky_tint = add_node(world_tree, "ShaderNodeOutputAOV", name="tint")
    world_tree.links.new(add_node(world_tree, "ShaderNodeTexCoord").outputs["Generated"], sky_tint.inputs["Color"])
    add_node(world_tree, "ShaderNodeOutputAOV", name="height").inputs["Value"].default_value = 7.0
    remove_shader_aovs()
    layer = bpy.context.view_layer
    for name, kind in (("tint", "COLOR"), ("height", "VALUE")):
        aov = layer.aovs.add()
        aov.name, aov.type = name, kind

    def with_aovs(material, tint=None, height=None):
        nt = material.node_tree
        if tint is not None:
            out = add_node(nt, "ShaderNodeOutputAOV", name="tint")
            if isinstance(tint, tuple):
                out.inputs["Color"].default_value = tint
            else:
                nt.links.new(tint(nt), out.inputs["Color"])
        if height is not None:
            out = add_node(nt, "ShaderNodeOutputAOV", name="height")
            geometry = add_node(nt, "ShaderNodeNewGeometry")
            split = add_node(nt, "ShaderNodeSeparateXYZ")
            plus = add_node(nt, "ShaderNodeMath", operation="ADD")
            plus.inputs[1].default_value = height
            nt.links.new(geometry.outputs["Position"], split.inputs["Vector"])
            nt.links.new(split.outputs["Z"], plus.inputs[0])
            nt.links.new(plus.outputs["Value"], out.inputs["Value"])
        return material
    plane("Floor", 12.0, with_aovs(diffuse_material("FloorMat", (0.6, 0.55, 0.5)), height=0.25))
    noise = lambda nt: add_node(nt, "ShaderNodeTexNoise", {"Scale": 4.0}).outputs["Color"]  # noqa: E731
    smooth_ball("Ball", (-0.5, 0.5, 0.6), 0.6, with_aovs(diffuse_material("BallMat", (0.8, 0.3, 0.2)), noise, 0.0))
    bpy.ops.mesh.primitive_cube_add(size=0.7, location=(1.0, 0.2, 0.35), rotation=(0, 0, math.radians(30)))
    bpy.context.active_object.data.materials.append(
        with_aovs(diffuse_material("CubeMat", (0.3, 0.5, 0.8)), (0.9, 0.6, 0.1, 1.0)))
    # A green card: which closure a sample follows (so whether it passes to write the ball's
    # AOVs) is chosen by the weights' average, as Cycles chooses (by luminance 73% passed, 78% in
    # Cycles: the height AOV behind it 5% low).
    card_mat = mix_material("Card", ("ShaderNodeBsdfDiffuse", {"Color": (0.1, 0.7, 0.15, 1)}),
                            ("ShaderNodeBsdfTransparent", {"Color": (1, 1, 1, 1)}), 0.7)
    card = plane("Card", 0.7, with_aovs(card_mat, (0.0, 1.0, 0.0, 1.0)), location=(-0.4, -1.0, 0.6))
    card.rotation_euler = (math.radians(90), 0, 0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)))
    camera_looking_at((0, -4.5, 1.6), (0, 0.5, 0.5), 40)
    return scene


def cryptomatte():
    """View Layer > Passes > Cryptomatte (Object, Material, Asset; 6 levels): a ball with a cube
    parented to it (the cube's asset is the ball), a second ball sharing the first one's
    material, a cone without a material (Cycles' default_surface), a floor, and a card 70%
    opaque (30% Transparent BSDF) in front of the ball, under a sun and a blue world."""
    scene = reset(48)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    layer = bpy.context.view_layer
    layer.use_pass_cryptomatte_object = layer.use_pass_cryptomatte_material = True
    layer.use_pass_cryptomatte_asset = True
    layer.pass_cryptomatte_depth = 6
    plane("Floor", 12.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5)))
    red = diffuse_material("Red", (0.8, 0.3, 0.2))
    ball = smooth_ball("Ball", (-0.5, 0.5, 0.6), 0.6, red)
    smooth_ball("Ball2", (1.6, 1.2, 0.4), 0.4, red)
    bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.5, 0.2, 0.25), rotation=(0, 0, math.radians(30)))
    cube = bpy.context.active_object
    cube.name = "Cube"
    cube.data.materials.append(diffuse_material("Blue", (0.3, 0.5, 0.8)))
    cube.parent = ball
    cube.matrix_parent_inverse = ball.matrix_world.inverted()
    bpy.ops.mesh.primitive_cone_add(radius1=0.3, depth=0.8, location=(-1.6, 0.2, 0.4))
    bpy.context.active_object.name = "Cone"
    card_mat = mix_material("Card", ("ShaderNodeBsdfDiffuse", {"Color": (0.5, 0.5, 0.5, 1)}),
                            ("ShaderNodeBsdfTransparent", {"Color": (1, 1, 1, 1)}), 0.3)
    card = plane("CardPlane", 0.7, card_mat, location=(-0.4, -1.0, 0.6))
    card.rotation_euler = (math.radians(90), 0, 0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)))
    camera_looking_at((0, -4.5, 1.6), (0, 0.5, 0.5), 40)
    return scene


def view_layer_attributes():
    """Attribute nodes of type View Layer, which Cycles reads once for the render from the view
    layer, else the scene, else the world: a ball coloured by "tint" (set on the view layer and,
    differently, on the scene: the view layer's wins), a ball by "scene_tint" (the scene's only), a
    ball by a name set nowhere (black), a cube whose mix toward a glossy coat is the scene's
    "gloss" (Fac), a cube grey by the RNA path "render.resolution_percentage" (Fac x 0.005), and a
    world coloured by the world's own "sky". A grey floor under a sun."""
    scene = reset(64)
    scene.render.resolution_x = 128
    layer = bpy.context.view_layer
    layer["tint"] = (0.9, 0.3, 0.1)
    scene["tint"] = (0.0, 1.0, 0.0)
    scene["scene_tint"] = (0.1, 0.5, 0.9)
    scene["gloss"] = 0.6
    scene.world["sky"] = (0.25, 0.3, 0.5)
    wt = scene.world.node_tree
    sky = add_node(wt, "ShaderNodeAttribute", attribute_type="VIEW_LAYER", attribute_name="sky")
    wt.links.new(sky.outputs["Color"], wt.nodes["Background"].inputs["Color"])
    plane("Floor", 10.0)
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), math.radians(10), math.radians(30)))

    def attribute_material(name, prop, output="Color", coat=False, scale=None):
        m, nt, out = empty_material(name)
        attr = add_node(nt, "ShaderNodeAttribute", attribute_type="VIEW_LAYER", attribute_name=prop)
        diffuse = add_node(nt, "ShaderNodeBsdfDiffuse")
        value = attr.outputs[output]
        if scale is not None:
            times = add_node(nt, "ShaderNodeMath", operation="MULTIPLY")
            times.inputs[1].default_value = scale
            nt.links.new(value, times.inputs[0])
            value = times.outputs["Value"]
        if not coat:
            nt.links.new(value, diffuse.inputs["Color"])
            nt.links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
            return m
        mix = add_node(nt, "ShaderNodeMixShader")
        nt.links.new(value, mix.inputs["Fac"])
        nt.links.new(diffuse.outputs["BSDF"], mix.inputs[1])
        nt.links.new(add_node(nt, "ShaderNodeBsdfGlossy", {"Roughness": 0.2}).outputs["BSDF"], mix.inputs[2])
        nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
        return m
    smooth_ball("LayerTint", (-1.3, 0.3, 0.45), 0.45, attribute_material("ByTint", "tint"))
    smooth_ball("SceneTint", (0.0, 0.3, 0.45), 0.45, attribute_material("BySceneTint", "scene_tint"))
    smooth_ball("Missing", (1.3, 0.3, 0.45), 0.45, attribute_material("ByMissing", "no_such_property"))
    for name, x, material in (("Gloss", -0.7, attribute_material("ByGloss", "gloss", "Fac", coat=True)),
                              ("Percentage", 0.7, attribute_material("ByPercentage", "render.resolution_percentage",
                                                                     "Fac", scale=0.005))):
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(x, -0.9, 0.25), rotation=(0, 0, math.radians(25)))
        bpy.context.active_object.name = name
        bpy.context.active_object.data.materials.append(material)
    camera_looking_at((0, -4.2, 2.0), (0, 0.0, 0.3), 40)
    return scene


def remove_cryptomatte():
    """The view layer's Cryptomatte passes (cryptomatte turns them on) off again, for a scene
    built after it in the same process (not in reset: see remove_shader_aovs)."""
    layer = bpy.context.view_layer
    layer.use_pass_cryptomatte_object = layer.use_pass_cryptomatte_material = False
    layer.use_pass_cryptomatte_asset = False


def denoising_data():
    """Cycles' denoising data: a smooth glass ball (IOR 1.5) and a diffuse ball on a diffuse
    floor, a tinted mirror (Glossy BSDF, roughness 0) standing behind them and a blue wall
    behind the camera's view, under a sun and a blue world: the ball and the mirror show
    the albedo and normal of what they refract and reflect, the depth along the way."""
    scene = reset(40)
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    plane("Floor", 12.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5)))
    smooth_ball("GlassBall", (0.5, 0, 0.6), 0.6,
                node_material("Glass", "ShaderNodeBsdfGlass", {"Color": (1, 1, 1, 1), "Roughness": 0.0, "IOR": 1.5},
                              distribution="SHARP"))
    smooth_ball("DiffuseBall", (-0.9, -0.3, 0.45), 0.45, diffuse_material("BallMat", (0.8, 0.3, 0.2)))
    mirror = plane("Mirror", 2.4, glossy_material("Mirror", 0.0, (0.9, 0.8, 0.7)), location=(-0.3, 1.6, 1.2))
    mirror.rotation_euler = (math.radians(80), 0, math.radians(-15))
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)))
    camera_looking_at((0.3, -4.0, 1.8), (0, 0.5, 0.6), 40)
    return scene


def denoising_fog():
    """Cycles' denoising data in fog: a cube of grey fog (Principled Volume, density 1.5, colour
    0.8: albedo 0.8, transmittance exp(-1.8) across) in front of a diffuse wall, a diffuse ball
    and the floor, the rest of the view without fog, under a sun and a blue world. Samples
    that scatter in the fog end there; all add albedo x (1 - transmittance) of the fog."""
    scene = reset(40)
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    plane("Floor", 12.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5)))
    wall = plane("Wall", 3.0, diffuse_material("WallMat", (0.5, 0.6, 0.4)), location=(0, 1.5, 1.5))
    wall.rotation_euler = (math.radians(90), 0, 0)
    smooth_ball("DiffuseBall", (0.4, 0.6, 0.5), 0.5, diffuse_material("BallMat", (0.8, 0.3, 0.2)))
    fog = link(bpy.data.objects.new("Fog", box_mesh("FogMesh", 1.2)))
    fog.location = (-0.4, -1.0, 0.9)
    fog.data.materials.append(principled_volume_material("FogMat", Density=1.5, Color=(0.8, 0.8, 0.8, 1.0))[0])
    light("SUN", "Sun", 3.0, (0, 0, 5), rotation=(math.radians(35), 0, math.radians(30)))
    camera_looking_at((0, -4.0, 1.5), (0, 0.5, 0.9), 40)
    return scene


def shadow_catcher():
    """Object > Visibility > Shadow Catcher: a floor that is a shadow catcher under a red
    diffuse ball and a green card standing on it (ordinary objects), lit by a point lamp
    and a blue world; the camera sees the world past the floor's far edge. The catcher pass
    is 1 where nothing shadows the floor, below 1 in the ball's and card's shadows."""
    scene = reset(48)
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.4, 0.5, 0.7, 1.0)
    bg.inputs["Strength"].default_value = 0.5
    plane("Floor", 4.0, diffuse_material("FloorMat", (0.6, 0.55, 0.5))).is_shadow_catcher = True
    smooth_ball("Ball", (-0.5, 0.2, 0.45), 0.45, diffuse_material("BallMat", (0.8, 0.3, 0.2)))
    card = plane("Card", 0.6, diffuse_material("CardMat", (0.2, 0.7, 0.3)), location=(0.7, -0.2, 0.3))
    card.rotation_euler = (math.radians(90), 0, math.radians(20))
    light("POINT", "Point", 150.0, (0.8, -0.6, 2.2), shadow_soft_size=0.3)
    camera_looking_at((0, -4.5, 1.8), (0, 0.3, 0.3), 45)
    return scene


LIGHT_PATH_SCENES = ["light_paths_diffuse", "light_paths_mirror", "light_paths_caustics", "light_paths_clamp",
                     "light_paths_filter_glossy", "light_paths_transparent", "light_paths_lamp_bounces",
                     "light_paths_principled", "light_paths_principled_caustics", "light_paths_transmission"]


# ---- motion blur (tests/blender/test_motion_blur.py) ----------------------------------------
MOTION_SIZE = 48
MOTION_FRAME = 2


def matte_material(name, color):
    """A Principled BSDF of this base colour without specular reflection."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*color, 1.0)
    m.node_tree.nodes["Principled BSDF"].inputs["Specular"].default_value = 0.0
    return m


def keyframe_linear(ob, path, values_by_frame):
    """Keyframes ob.<path> at each (frame, value), interpolated linearly between them."""
    for frame, value in values_by_frame:
        setattr(ob, path, value)
        ob.keyframe_insert(path, frame=frame)
    for fc in ob.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"


def motion_blur(variant):
    """The motion blur scenes: a grey floor under an area lamp (48x48, motion blur on), and
    square: a red square keyframed to slide 4.8 m between frames 1 and 3 (shutter 1, Center);
    camera: a static ball seen from a camera keyframed to pan (shutter 0.5, Start);
    deform: a square sheared by a shape key (deformation blur);
    deform_instanced: that square seen only through two collection instances;
    deform_smooth: a smooth ball a shape key squashes and slides (its normals turn);
    emitters: two glowing planes, one keyframed and one a shape key slides, light the floor."""
    scene = reset(MOTION_SIZE)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.08, 0.09, 0.1, 1.0)
    bpy.ops.mesh.primitive_plane_add(size=6, location=(0, 0, 0))
    bpy.context.object.data.materials.append(matte_material("Floor", (0.7, 0.7, 0.7)))
    light("AREA", "Lamp", 200, (0.5, -1.0, 3.2), size=1.0)
    cam = link(bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera")))
    cam.data.lens = 35
    cam.location = (0, -4.5, 2.6)
    look_at(cam, (0, 0, 0.3))
    scene.camera = cam
    scene.render.use_motion_blur = True
    if variant == "square":
        bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0, 0, 0.6))
        square = bpy.context.object
        square.rotation_euler = (1.2, 0, 0)  # facing the camera
        square.data.materials.append(matte_material("Red", (0.8, 0.15, 0.1)))
        keyframe_linear(square, "location", [(MOTION_FRAME - 1, (-2.4, 0, 0.6)), (MOTION_FRAME + 1, (2.4, 0, 0.6))])
        scene.render.motion_blur_shutter = 1.0
        scene.cycles.motion_blur_position = "CENTER"
    elif variant == "deform":
        # Deformation blur: the square's vertices move (a shape key), not its transform; its
        # top edge slides 6 m and its bottom edge 3.6 m between frames 1 and 3, so the
        # shutter sees a sheared smear no transform gives.
        bpy.ops.mesh.primitive_plane_add(size=1.0, location=(-2.4, 0, 0.6))
        square = bpy.context.object
        square.rotation_euler = (1.2, 0, 0)  # facing the camera
        square.data.materials.append(matte_material("Red", (0.8, 0.15, 0.1)))
        offsets = [(6.0 if v.co.y > 0 else 3.6, 0.0, 0.0) for v in square.data.vertices]
        shape_key_animation(square, offsets, [(MOTION_FRAME - 1, 0.0), (MOTION_FRAME + 1, 1.0)])
        scene.render.motion_blur_shutter = 1.0
        scene.cycles.motion_blur_position = "CENTER"
    elif variant == "deform_instanced":
        # Deformation blur on instanced copies: the sheared square of `deform` lives only in a
        # collection excluded from the view layer, seen through two collection instances.
        source = bpy.data.collections.new("Sheared")
        scene.collection.children.link(source)
        bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0, 0, 0))
        square = bpy.context.object
        for c in list(square.users_collection):
            c.objects.unlink(square)
        source.objects.link(square)
        square.rotation_euler = (1.2, 0, 0)  # facing the camera
        square.data.materials.append(matte_material("Red", (0.8, 0.15, 0.1)))
        offsets = [(6.0 if v.co.y > 0 else 3.6, 0.0, 0.0) for v in square.data.vertices]
        shape_key_animation(square, offsets, [(MOTION_FRAME - 1, 0.0), (MOTION_FRAME + 1, 1.0)])
        bpy.context.view_layer.layer_collection.children["Sheared"].exclude = True
        for name, location in (("Copy low", (-2.4, 0.4, 0.5)), ("Copy high", (-2.4, -0.4, 1.5))):
            copy = link(bpy.data.objects.new(name, None))
            copy.location = location
            copy.instance_type = "COLLECTION"
            copy.instance_collection = source
        scene.render.motion_blur_shutter = 1.0
        scene.cycles.motion_blur_position = "CENTER"
    elif variant == "deform_smooth":
        # Deformation blur with smooth normals: a smooth ball a shape key squashes to 40% of its
        # height, widens by 60% and slides 3.6 m between frames 1 and 3, so its vertex normals
        # turn over the shutter.
        uv_sphere(radius=0.5, location=(-1.2, 0, 0.5), segments=32, ring_count=16)
        bpy.ops.object.shade_smooth()
        ball = bpy.context.object
        ball.data.materials.append(matte_material("Red", (0.8, 0.15, 0.1)))
        offsets = [(0.6 * v.co.x + 3.6, 0.0, -0.6 * (v.co.z + 0.5)) for v in ball.data.vertices]
        shape_key_animation(ball, offsets, [(MOTION_FRAME - 1, 0.0), (MOTION_FRAME + 1, 1.0)])
        scene.render.motion_blur_shutter = 1.0
        scene.cycles.motion_blur_position = "CENTER"
    elif variant == "emitters":
        # Emitting meshes move with their light: a glowing plane keyframed to slide 4.8 m and
        # one a shape key slides 3.6 m (deformation blur), both facing the floor at 1.2 m, the
        # area lamp dimmed so that they light most of it.
        bpy.data.objects["Lamp"].data.energy = 20
        glow = matte_material("Glow", (0.0, 0.0, 0.0))
        glow.node_tree.nodes["Principled BSDF"].inputs["Emission"].default_value = (1.0, 0.9, 0.8, 1.0)
        glow.node_tree.nodes["Principled BSDF"].inputs["Emission Strength"].default_value = 30.0
        bpy.ops.mesh.primitive_plane_add(size=0.6, location=(0, -0.6, 1.2), rotation=(3.14159265, 0, 0))
        sliding = bpy.context.object
        sliding.name = "Sliding glow"
        sliding.data.materials.append(glow)
        keyframe_linear(sliding, "location", [(MOTION_FRAME - 1, (-2.4, -0.6, 1.2)), (MOTION_FRAME + 1, (2.4, -0.6, 1.2))])
        bpy.ops.mesh.primitive_plane_add(size=0.6, location=(-1.8, 0.8, 1.2), rotation=(3.14159265, 0, 0))
        deforming = bpy.context.object
        deforming.name = "Deforming glow"
        deforming.data.materials.append(glow)
        shape_key_animation(deforming, [(3.6, 0.0, 0.0)] * len(deforming.data.vertices),
                            [(MOTION_FRAME - 1, 0.0), (MOTION_FRAME + 1, 1.0)])
        scene.render.motion_blur_shutter = 1.0
        scene.cycles.motion_blur_position = "CENTER"
    elif variant == "camera":
        uv_sphere(radius=0.5, location=(0, 0, 0.5), segments=48, ring_count=24)
        bpy.ops.object.shade_smooth()
        bpy.context.object.data.materials.append(matte_material("Red", (0.8, 0.15, 0.1)))
        keyframe_linear(cam, "location", [(MOTION_FRAME - 1, (-0.8, -4.5, 2.6)), (MOTION_FRAME + 1, (0.8, -4.5, 2.6))])
        scene.render.motion_blur_shutter = 0.5
        scene.cycles.motion_blur_position = "START"
    else:
        raise ValueError("unknown variant %r" % variant)
    scene.frame_set(MOTION_FRAME)
    return scene



SCENES = {
    "cornell_lamp_near_ceiling": cornell_lamp_near_ceiling,
    "view_dependent_mixes": view_dependent_mixes,
    "nishita_sky": nishita_sky,
    "light_path_rays": light_path_rays,
    "light_path_shadow_rays": light_path_shadow_rays,
    "mesh_derived_attributes": mesh_derived_attributes,
    "principled_glass_tint": principled_glass_tint,
    "wireframe_parametric": wireframe_parametric,
    "ambient_occlusion": ambient_occlusion,
    "bevel": bevel,
    "incoming_facing": incoming_facing,
    "mapped_normals": mapped_normals,
    "displacement": displacement,
    "true_displacement": true_displacement,
    "camera_data": camera_data,
    "light_nodes": light_nodes,
    "light_falloff": light_falloff,
    "lamp_textures": lamp_textures,
    "shader_aovs": shader_aovs,
    "cryptomatte": cryptomatte,
    "view_layer_attributes": view_layer_attributes,
    "ies_lamps": ies_lamps,
    "area_spread": area_spread,
    "object_attributes": object_attributes,
    "preetham_sky": preetham_sky,
    "plane_point": plane_point,
    "plane_spot": plane_spot,
    "plane_sun": plane_sun,
    "plane_area": plane_area,
    "plane_area_disk_scaled": plane_area_disk_scaled,
    "world_color": world_color,
    "emissive_mesh": emissive_mesh,
    "hdri": hdri,
    "principled_plane": principled_plane,
    "grazing_gloss": grazing_gloss,
    "noise_texture": noise_texture,
    "procedural_textures": procedural_textures,
    "curves_and_ramps": curves_and_ramps,
    "math_nodes": math_nodes,
    "object_info": object_info,
    "geometry_coordinates": geometry_coordinates,
    "color_nodes": color_nodes,
    "emissive_textured": emissive_textured,
    "volume_blackbody": volume_blackbody,
    "volume_tinted": volume_tinted,
    "bad_input": bad_input,
    "materials_instances": materials_instances,
    "showcase": showcase,
    "veach_point": veach_point,
    "veach_spot": veach_spot,
    "veach_sun": veach_sun,
    "veach_area_square": veach_area_square,
    "veach_area_disk": veach_area_disk,
    "light_paths_diffuse": light_paths_diffuse,
    "light_paths_mirror": light_paths_mirror,
    "light_paths_caustics": light_paths_caustics,
    "light_paths_clamp": light_paths_clamp,
    "light_paths_filter_glossy": light_paths_filter_glossy,
    "light_paths_transmission": light_paths_transmission,
    "light_paths_transparent": light_paths_transparent,
    "light_paths_lamp_bounces": light_paths_lamp_bounces,
    "light_paths_principled": light_paths_principled,
    "light_paths_principled_caustics": light_paths_principled_caustics,
    "alpha_leaves": alpha_leaves,
    "film_transparent": film_transparent,
    "light_passes": light_passes,
    "data_passes": data_passes,
    "denoising_data": denoising_data,
    "denoising_fog": denoising_fog,
    "shadow_catcher": shadow_catcher,
    "motion_square": lambda: motion_blur("square"),
    "motion_camera": lambda: motion_blur("camera"),
    "motion_deform": lambda: motion_blur("deform"),
    "motion_deform_smooth": lambda: motion_blur("deform_smooth"),
    "motion_deform_instanced": lambda: motion_blur("deform_instanced"),
    "motion_emitters": lambda: motion_blur("emitters"),
}

# Scenes whose brightness must agree with Cycles.
BRIGHTNESS_SCENES = ["plane_point", "plane_spot", "plane_sun", "plane_area", "plane_area_disk_scaled",
                     "world_color", "emissive_mesh", "hdri", "principled_plane", "grazing_gloss", "noise_texture", "procedural_textures", "curves_and_ramps", "math_nodes", "object_info", "color_nodes", "geometry_coordinates", "view_dependent_mixes", "nishita_sky", "light_path_rays", "light_path_shadow_rays", "mesh_derived_attributes", "principled_glass_tint", "wireframe_parametric", "ambient_occlusion", "bevel", "incoming_facing", "mapped_normals", "displacement", "true_displacement", "camera_data", "light_nodes", "light_falloff", "lamp_textures", "ies_lamps", "area_spread", "object_attributes", "view_layer_attributes", "preetham_sky", "emissive_textured",
                     "volume_blackbody"]


def build(name):
    SCENES[name]()
    bpy.context.view_layer.update()
    return bpy.context.scene


def main(argv):
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("names", nargs="*")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    for name in a.names or list(SCENES):
        build(name)
        path = os.path.join(os.path.abspath(a.out), name + ".blend")
        bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
        print("wrote", path)
        remove_shader_aovs()
        remove_cryptomatte()


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
