"""Lowering: the engine-neutral description -> the engine's material JSON.

This is the ONE place that knows the engine's material format (docs/scene-format.md):
closure types ``diffuse``, ``emission``, ``glossy``, ``glass``, ``refraction``,
``principled``, ``transparent``, ``translucent``, ``sheen``, ``mix``, ``add`` (nested to any
depth), per-material ``volume`` media (``"type": "volume"`` for a surface-less boundary),
and texture graphs (``{"node": ...}``) for every colour/float input.

IR values that do not vary over the surface are folded into constants when the folding is
exact; everything else becomes an engine texture node.  A node that cannot be represented
exactly (an image without a readable file, Toon/Hair BSDFs, ...) is
replaced by its best constant/closure and recorded, and the caller gets ONE warning per
material naming those nodes.
"""

import math
from .ir import Const, Expr, Closure
from .issues import Issues
from .evaluate import Evaluator, is_constant, PROCEDURAL_TEXTURES, VARYING_OPS
from .graph import LUMINANCE
from .nodes.converter import falloff_at

ENGINE_TYPES = ("diffuse", "emission", "glossy", "glass", "refraction", "principled", "transparent",
                "translucent", "sheen", "mix", "add", "volume")

DEFAULT_SURFACE = {"type": "diffuse", "color": [0.8, 0.8, 0.8]}

# Name under which the exporter stores a mesh's default (active render) colour attribute,
# for Color Attribute nodes that leave the layer empty.
DEFAULT_COLOR_ATTRIBUTE = "__rdv_default_color"

PRINCIPLED_KEYS = ("base_color", "subsurface", "subsurface_radius", "subsurface_color", "metallic", "specular",
                   "specular_tint", "roughness", "anisotropic", "anisotropic_rotation", "sheen", "sheen_tint",
                   "clearcoat", "clearcoat_roughness", "ior", "transmission", "transmission_roughness", "alpha")
COLOR_KEYS = {"base_color", "subsurface_color", "color", "subsurface_radius"}

# Texture Coordinate's Normal is the object-space normal (Cycles' object_inverse_normal_transform);
# Geometry's Position, Normal and True Normal are world space.
TEXCOORD_OUTPUTS = {"Generated": "generated", "UV": "uv", "Object": "object", "Normal": "object_normal"}
GEOMETRY_OUTPUTS = {"Position": "position", "Normal": "normal", "True Normal": "true_normal", "Parametric": "parametric",
                    "Tangent": "tangent"}


def luminance(c):
    return LUMINANCE[0] * c[0] + LUMINANCE[1] * c[1] + LUMINANCE[2] * c[2]


def _clamp01(x):
    return 0.0 if x < 0.0 else 1.0 if x > 1.0 else x


def _num(v):
    if isinstance(v, float):
        return v
    return [float(x) for x in v]


def _constant(v, color):
    """A constant as the engine reads it; into a colour input without negative parts."""
    v = _num(v)
    if not color:
        return v
    return max(v, 0.0) if isinstance(v, float) else [max(x, 0.0) for x in v]


class _Lowerer:
    def __init__(self, issues, image_average, image_file, context, volume_grids=False):
        self.issues = issues
        self.ev = Evaluator(issues, image_average)
        self.image_average = image_average
        self.image_file = image_file
        self.context = context  # "surface" or "world"
        self.volume_grids = volume_grids  # the material fills a Volume object: attributes name its grids
        # Lowering what an emitter emits (an Emission's colour and strength, a lamp's tree): the
        # engine knows how far that light travels there, so a Light Falloff stays a node.
        self.emitting = False
        self._memo = {}
        if context == "world":  # Cycles 3.4 shades the world with a ray length of 0
            self.ev.ray_length = 0.0

    def approx(self, node, reason):
        self.issues.add(node, reason)

    # ---- values ------------------------------------------------------------------
    def fold(self, ir):
        """The constant value of ir when it is constant and folds exactly, else None."""
        if ir is None:
            return None
        if isinstance(ir, Const):
            return ir.value
        if isinstance(ir, Closure) or not is_constant(ir):
            return None
        scratch = Issues()
        v = Evaluator(scratch, self.image_average, self.ev.ray_length).value(ir)
        return None if scratch else v

    def const(self, ir, what=None):
        """A constant, approximating varying values (recorded)."""
        v = self.ev.value(ir)
        if what and isinstance(ir, Expr) and not is_constant(ir):
            self.approx(ir.node, what)
        return v

    def value(self, ir, color=False):
        """IR value -> number, [r,g,b] or a texture node object. color: the value feeds a
        colour input, where the engine refuses negative constants (Cycles clamps them)."""
        if ir is None:
            return 0.0
        v = self.fold(ir)
        if v is not None:
            return _constant(v, color)
        # The same IR may be lowered as a vector and as a colour: both forms are kept. The
        # memo holds ir itself, so its id is not reused while the key lives.
        key = (id(ir), color, self.emitting)
        if key in self._memo:
            return self._memo[key][1]
        if not self._varies(ir):
            # Only approximated leaves (images without a file, ...): one constant, recorded.
            out = _constant(self.ev.value(ir), color)
        else:
            out = self._node(ir)
        self._memo[key] = (ir, out)
        return out

    def _varies(self, ir, depth=0):
        """True when the engine texture graph for ir really varies over the surface."""
        if not isinstance(ir, Expr) or depth > 200:
            return False
        op = ir.op
        if op in ("tex_image", "tex_environment"):
            return op == "tex_image" and self._image_file(ir) is not None
        if op in ("texcoord", "uvmap", "tex_checker", "tex_noise", "tex_gradient", "tex_ies", "vertex_color",
                  "normal_map", "bump", "bevel", "displacement", "vector_displacement", "object_info", "camera_data", "blackbody", "wavelength", "geometry", "wireframe",
                  "ao") + PROCEDURAL_TEXTURES:
            return True
        if op == "light_falloff" and self.emitting:  # by the ray's length unless Quadratic without Smooth
            if ir.props.get("output") != "QUADRATIC" or self.fold(ir.args.get("smooth")) != 0.0:
                return True
        if op == "attribute":  # a mesh's attribute, or an object's own value (Object / Instancer)
            return ir.props.get("attribute_type", "GEOMETRY") in ("GEOMETRY", "OBJECT", "INSTANCER") and \
                bool(ir.props.get("attribute_name"))
        return any(self._varies(a, depth + 1) for a in ir.args.values())

    def _const_node(self, e):
        return _num(self.ev.value(e))

    def _node(self, e):
        if not isinstance(e, Expr):
            return 0.0
        fn = getattr(self, "_n_" + e.op, None)
        if fn is None:
            return self._const_node(e)  # the evaluator records the approximation
        return fn(e)

    def _vector(self, d, e, key="vector"):
        a = e.args.get(key)
        if a is not None and not isinstance(a, Const):
            d[key] = self.value(a, False)
        elif isinstance(a, Const) and key != "vector":
            d[key] = _num(a.value)
        return d

    def _n_to_float(self, e):
        inner = e.args["value"]
        if e.props.get("from") == "VECTOR":
            v = self.value(inner)
            sep = [{"node": "separate_rgb", "color": v, "output": o} for o in ("r", "g", "b")]
            s = {"node": "math", "operation": "ADD", "value1": sep[0], "value2": sep[1]}
            s = {"node": "math", "operation": "ADD", "value1": s, "value2": sep[2]}
            return {"node": "math", "operation": "MULTIPLY", "value1": s, "value2": 1.0 / 3.0}
        return {"node": "rgb_to_bw", "color": self.value(inner, True)}

    def _n_to_vec3(self, e):
        return self.value(e.args["value"])

    def _image_file(self, e):
        """What the engine reads for the node's image: a path, a dict ({"file": path[,
        "frame" | "tiles"]} or {"buffer": name}), or None (its average colour is used)."""
        image = e.props.get("image")
        if image is None or self.image_file is None:
            return None
        try:
            user = e.props.get("image_user")
            return self.image_file(image) if user is None else self.image_file(image, user)
        except Exception:  # never let a bad image stop the export
            return None

    def _n_tex_image(self, e):
        source = self._image_file(e)
        if source is None:
            return self._const_node(e)  # average colour, recorded by the evaluator
        d = {"node": "image"}
        d.update({"file": source} if isinstance(source, str) else source)
        if e.props.get("image_name"):
            d["name"] = e.props["image_name"]
        if e.props.get("colorspace") and "buffer" not in d:  # a buffer carries its own
            d["colorspace"] = e.props["colorspace"]
        d["interpolation"] = e.props.get("interpolation", "Linear")
        d["extension"] = e.props.get("extension", "REPEAT")
        if e.props.get("projection", "FLAT") != "FLAT":
            self.approx(e.node, "%s projection approximated as flat" % e.props["projection"])
        self._vector(d, e)
        if e.props.get("output") == "Alpha":
            d["output"] = "alpha"
        return d

    def _n_light_falloff(self, e):
        strength, smooth = e.args["strength"], e.args["smooth"]
        if self.emitting:
            return {"node": "light_falloff", "output": e.props.get("output", "QUADRATIC"),
                    "strength": self.value(strength), "smooth": self.value(smooth)}
        if self.ev.ray_length is not None:  # the world: Cycles 3.4's ray length there, a factor of Strength
            smooth_value = self.fold(smooth)
            factor = falloff_at(e.props.get("output", "QUADRATIC"), 1.0,
                                1.0 if smooth_value is None else smooth_value, self.ev.ray_length)
            return self.value(strength) if factor else 0.0  # (0 or 1 at a ray length of 0)
        what = e.props.get("name") or "%s falloff" % e.props.get("output", "QUADRATIC").title()
        self.approx(e.node, "%s outside an emitter's colour or strength: the ray's length is not known there; "
                    "its Strength used" % what)
        return self.value(strength)

    def _n_tex_environment(self, e):
        self.approx(e.node, "environment texture in a material approximated by its average")
        return self._const_node(e)

    def _n_tex_checker(self, e):
        d = {"node": "checker", "color1": self.value(e.args["color1"], True),
             "color2": self.value(e.args["color2"], True), "scale": self.value(e.args["scale"])}
        self._vector(d, e)
        if e.props.get("output") == "Fac":
            d["output"] = "fac"
        return d

    def _n_tex_ies(self, e):
        d = {"node": "ies", "strength": self.value(e.args["strength"])}
        self._vector(d, e)
        d.update({k: e.props[k] for k in ("profile", "file") if k in e.props})
        return d

    def _texture(self, e, node, keys, colors=(), props=()):
        """A procedural texture node: its inputs (numbers or nodes), its Vector when linked,
        and the named properties."""
        d = {"node": node}
        for k in keys:
            d[k] = self.value(e.args[k], k in colors)
        self._vector(d, e)
        for k in props:
            d[k] = e.props[k]
        return d

    def _n_tex_noise(self, e):
        d = self._texture(e, "noise", ("scale", "detail", "roughness", "distortion"))
        dims = e.props.get("dimensions", "3D")
        if dims != "3D":
            d["dimensions"] = dims
        if dims in ("1D", "4D"):
            d["w"] = self.value(e.args["w"])
        if d["distortion"] == 0.0:
            del d["distortion"]
        d["output"] = "color" if e.props.get("output") == "Color" else "fac"
        return d

    def _n_tex_voronoi(self, e):
        d = self._texture(e, "voronoi", ("w", "scale", "smoothness", "exponent", "randomness"),
                          props=("dimensions", "feature", "distance"))
        d["output"] = e.props.get("output", "Distance").lower()
        return d

    def _n_tex_musgrave(self, e):
        return self._texture(e, "musgrave", ("w", "scale", "detail", "dimension", "lacunarity", "offset", "gain"),
                             props=("dimensions", "musgrave_type"))

    def _n_tex_wave(self, e):
        d = self._texture(e, "wave", ("scale", "distortion", "detail", "detail_scale", "detail_roughness", "phase"),
                          props=("wave_type", "direction", "profile"))
        d["output"] = "color" if e.props.get("output") == "Color" else "fac"
        return d

    def _n_tex_magic(self, e):
        d = self._texture(e, "magic", ("scale", "distortion"), props=("depth",))
        d["output"] = "fac" if e.props.get("output") == "Fac" else "color"
        return d

    def _n_tex_brick(self, e):
        d = self._texture(e, "brick", ("color1", "color2", "mortar", "scale", "mortar_size", "mortar_smooth", "bias",
                                       "brick_width", "row_height"), colors=("color1", "color2", "mortar"),
                          props=("offset", "offset_frequency", "squash", "squash_frequency"))
        d["output"] = "fac" if e.props.get("output") == "Fac" else "color"
        return d

    def _n_tex_white_noise(self, e):
        d = self._texture(e, "white_noise", ("w",), props=("dimensions",))
        v = e.args.get("vector")
        if isinstance(v, Const):  # unlinked: Blender hashes the socket's own vector, not a coordinate
            d["vector"] = _num(v.value)
        d["output"] = "color" if e.props.get("output") == "Color" else "value"
        return d

    def _n_tex_gradient(self, e):
        d = {"node": "gradient", "gradient_type": e.props.get("gradient_type", "LINEAR")}
        self._vector(d, e)
        d["output"] = "color" if e.props.get("output") == "Color" else "fac"
        return d

    def _n_mix_color(self, e):
        if not e.props.get("clamp_factor", True):
            self.approx(e.node, "unclamped factor clamped")
        return {"node": "mix", "blend_type": e.props.get("blend_type", "MIX"), "fac": self.value(e.args["fac"]),
                "color1": self.value(e.args["a"]), "color2": self.value(e.args["b"]),
                "clamp": bool(e.props.get("clamp_result", False))}

    def _n_mix_value(self, e):
        fac = e.args["fac"]
        if e.props.get("data_type") == "VECTOR" and not isinstance(self.fold(fac), (float, type(None))):
            self.approx(e.node, "non-uniform factor approximated by its luminance")
        return {"node": "mix", "blend_type": "MIX", "fac": self.value(fac), "color1": self.value(e.args["a"]),
                "color2": self.value(e.args["b"])}

    def _n_math(self, e):
        d = {"node": "math", "operation": e.props.get("operation", "ADD")}
        for k, name in (("a", "value1"), ("b", "value2"), ("c", "value3")):
            if k in e.args:
                d[name] = self.value(e.args[k])
        if e.props.get("use_clamp"):
            d["clamp"] = True
        return d

    def _n_clamp(self, e):
        v, lo, hi = (self.value(e.args[k]) for k in ("value", "min", "max"))
        if e.props.get("clamp_type") == "RANGE":
            lo, hi = ({"node": "math", "operation": "MINIMUM", "value1": lo, "value2": hi},
                      {"node": "math", "operation": "MAXIMUM", "value1": lo, "value2": hi})
        return {"node": "math", "operation": "MINIMUM", "value2": hi,
                "value1": {"node": "math", "operation": "MAXIMUM", "value1": v, "value2": lo}}

    def _n_map_range(self, e):
        d = {"node": "map_range", "interpolation_type": e.props.get("interpolation_type", "LINEAR"),
             "clamp": bool(e.props.get("clamp", True))}
        if e.props.get("vector"):
            d["data_type"] = "FLOAT_VECTOR"
        for k in ("value", "from_min", "from_max", "to_min", "to_max", "steps"):
            d[k] = self.value(e.args[k])
        return d

    def _n_vector_math(self, e):
        d = {"node": "vector_math", "operation": e.props.get("operation", "ADD")}
        for k, key in (("a", "vector1"), ("b", "vector2"), ("c", "vector3")):
            if k in e.args:
                d[key] = self.value(e.args[k])
        if "scale" in e.args:
            d["scale"] = self.value(e.args["scale"])
        if e.props.get("output") == "Value":
            d["output"] = "value"
        return d

    def _n_invert(self, e):
        return {"node": "invert", "fac": self.value(e.args["fac"]), "color": self.value(e.args["color"], True)}

    def _n_color_ramp(self, e):
        els = [{"position": p, "color": list(c) + [a]} for p, c, a in (e.props.get("elements") or [])]
        if not els:
            return self._const_node(e)
        if e.props.get("table"):  # Blender's own evaluation, baked as Cycles bakes it
            d = {"node": "color_ramp", "fac": self.value(e.args["fac"]),
                 "table": [list(c) for c in e.props["table"]],
                 "interpolation": "CONSTANT" if e.props.get("interpolation") == "CONSTANT" else "LINEAR"}
            if e.props.get("output") == "Alpha":
                d["output"] = "alpha"
            return d
        if e.props.get("color_mode", "RGB") != "RGB":
            self.approx(e.node, "%s colour mode approximated as RGB" % e.props.get("color_mode"))
        interp = e.props.get("interpolation", "LINEAR")
        if interp not in ("LINEAR", "CONSTANT", "EASE"):
            self.approx(e.node, "%s interpolation approximated as linear" % interp)
            interp = "LINEAR"
        d = {"node": "color_ramp", "fac": self.value(e.args["fac"]), "interpolation": interp, "elements": els}
        if e.props.get("output") == "Alpha":
            d["output"] = "alpha"
        return d

    def _n_curves(self, e):
        kind = e.props["kind"]
        d = {"node": "float_curve" if kind == "float" else "rgb_curves", "fac": self.value(e.args["fac"]),
             "table": [float(v) if kind == "float" else list(v) for v in e.props["table"]],
             "min_x": e.props["min_x"], "max_x": e.props["max_x"], "extrapolate": bool(e.props["extrapolate"])}
        d["value" if kind == "float" else "color"] = self.value(e.args["value"], kind == "rgb")
        return d

    def _n_gamma(self, e):
        return {"node": "gamma", "color": self.value(e.args["color"], True), "gamma": self.value(e.args["gamma"])}

    def _n_bright_contrast(self, e):
        return {"node": "bright_contrast", "color": self.value(e.args["color"], True),
                "bright": self.value(e.args["bright"]), "contrast": self.value(e.args["contrast"])}

    def _n_hue_saturation(self, e):
        d = {"node": "hue_saturation", "color": self.value(e.args["color"], True), "fac": self.value(e.args["fac"])}
        for k in ("hue", "saturation", "value"):
            if k in e.args:
                d[k] = self.value(e.args[k])
        return d

    def _n_separate(self, e):
        return {"node": "separate_rgb", "color": self.value(e.args["value"]),
                "output": "rgb"[e.props.get("index", 0)]}

    def _n_combine(self, e):
        return {"node": "combine_rgb", "r": self.value(e.args["x"]), "g": self.value(e.args["y"]),
                "b": self.value(e.args["z"])}

    def _n_texcoord(self, e):
        out = e.props.get("output", "Generated")
        o = TEXCOORD_OUTPUTS.get(out)
        if o is None:
            self.approx(e.node, "%s coordinates approximated by generated ones" % out)
            o = "generated"
        if o == "object" and e.props.get("object"):
            self.approx(e.node, "object '%s' ignored, own object space used" % e.props["object"])
        return {"node": "texture_coordinate", "output": o}

    def _n_blackbody(self, e):
        return {"node": "blackbody", "temperature": self.value(e.args["temperature"])}

    def _n_wavelength(self, e):
        return {"node": "wavelength", "wavelength": self.value(e.args["wavelength"])}

    def _n_ao(self, e):
        if e.props.get("normal_linked"):
            self.approx(e.node, "its Normal input ignored (the shading normal used)")
        samples = min(max(int(e.props.get("samples", 16)), 1), 128)
        if samples != e.props.get("samples", 16):
            self.approx(e.node, "Samples kept to 1..128")
        return {"node": "ambient_occlusion", "color": self.value(e.args["color"]),
                "distance": self.value(e.args["distance"]), "samples": samples,
                "inside": bool(e.props.get("inside")), "only_local": bool(e.props.get("only_local")),
                "output": e.props.get("output", "color")}

    def _n_wireframe(self, e):
        if e.props.get("pixel_size"):
            self.approx(e.node, "Pixel Size widths from the ray's footprint along the surface (Cycles' faces the viewer)")
        return {"node": "wireframe", "size": self.value(e.args["size"]), "pixel_size": bool(e.props.get("pixel_size"))}

    def _n_color_space(self, e):
        return {"node": "color_space", "convert": e.props["convert"], "color": self.value(e.args["color"])}

    def _n_geometry(self, e):
        out = GEOMETRY_OUTPUTS.get(e.props.get("output"))
        if out is None:
            return self._const_node(e)  # the evaluator records the approximation
        return {"node": "texture_coordinate", "output": out}

    def _n_camera_data(self, e):
        return {"node": "camera_data", "output": e.props.get("output", "view_vector")}

    def _n_object_info(self, e):
        return {"node": "object_info", "output": e.props.get("output", "random")}

    def _n_uvmap(self, e):
        return {"node": "uv", "layer": e.props.get("uv_map", "") or ""}

    def _n_mapping(self, e):
        d = {"node": "mapping", "type": e.props.get("vector_type", "POINT")}
        self._vector(d, e)
        for k in ("location", "rotation", "scale"):
            a = e.args.get(k)
            v = self.fold(a)
            if v is None:
                v = self.const(a, "textured mapping %s evaluated as a constant" % k)
            d[k] = list(v) if not isinstance(v, float) else [v, v, v]
        return d

    def _n_normal_map(self, e):
        space = e.props.get("space", "TANGENT")
        if space.startswith("BLENDER_"):
            self.approx(e.node, "%s space approximated as %s" % (space, space[8:]))
            space = space[8:]
        if e.props.get("uv_map"):
            self.approx(e.node, "tangents from the default UV map, not '%s'" % e.props["uv_map"])
        return {"node": "normal_map", "space": space, "color": self.value(e.args["color"], True),
                "strength": self.value(e.args["strength"])}

    def _n_bump(self, e):
        d = {"node": "bump", "height": self.value(e.args["height"]), "strength": self.value(e.args["strength"]),
             "distance": self.value(e.args["distance"]), "invert": bool(e.props.get("invert", False))}
        n = self.normal(e.args.get("normal"), e.node)
        if n is not None:
            d["normal"] = n
        return d

    def _n_displacement(self, e):
        d = {"node": "displacement", "space": e.props.get("space", "OBJECT")}
        for k in ("height", "midlevel", "scale"):
            d[k] = self.value(e.args[k])
        if "normal" in e.args:
            d["normal"] = self.value(e.args["normal"])
        return d

    def _n_vector_displacement(self, e):
        return {"node": "vector_displacement", "space": e.props.get("space", "TANGENT"),
                "vector": self.value(e.args["vector"]), "midlevel": self.value(e.args["midlevel"]),
                "scale": self.value(e.args["scale"])}

    def displacement(self, desc):
        """The Material Output's Displacement as the material's Settings > Displacement has Cycles
        render it: {} without one; Bump Only (Cycles' default; shader_graph.cpp,
        bump_from_displacement): a bump of height offset . normal as the "surface_normal" (Cycles'
        SetNormal: the normal of every shader and Bump without one of their own); Displacement
        Only: the offset as "displacement", moving the vertices (the engine's
        scene/displacement.cpp); Displacement and Bump: both, the bump taken in object space."""
        if desc.displacement is None:
            return {}
        method = desc.displacement_method
        constant = self.fold(desc.displacement)
        if constant is not None:  # moves the surface, bumps nothing
            v = [float(x) for x in (constant if isinstance(constant, (list, tuple)) else [constant] * 3)][:3]
            return {"displacement": v, "displacement_method": "true"} if method != "BUMP" and any(v) else {}
        out = {}
        if method != "DISPLACEMENT":
            height = {"node": "vector_math", "operation": "DOT_PRODUCT", "vector1": self.value(desc.displacement),
                      "vector2": {"node": "texture_coordinate", "output": "normal"}, "output": "value"}
            out["surface_normal"] = {"node": "bump", "height": height, "strength": 1.0, "distance": 1.0}
            if method == "BOTH":
                out["surface_normal"]["space"] = "OBJECT"
        if method != "BUMP":
            out["displacement"] = self.value(desc.displacement)
            out["displacement_method"] = "true" if method == "DISPLACEMENT" else "both"
        return out

    def _n_bevel(self, e):
        samples = min(max(int(e.props.get("samples", 4)), 0), 128)
        if samples != e.props.get("samples", 4):
            self.approx(e.node, "Samples kept to 0..128")
        d = {"node": "bevel", "radius": self.value(e.args["radius"]), "samples": samples}
        n = self.normal(e.args.get("normal"), e.node)
        if n is not None:
            d["normal"] = n
        return d

    def _n_vertex_color(self, e):
        d = {"node": "vertex_color", "layer": e.props.get("layer_name") or DEFAULT_COLOR_ATTRIBUTE}
        if e.props.get("output") == "Alpha":
            d["output"] = "alpha"
        return d

    def _n_attribute(self, e):
        kind = e.props.get("attribute_type", "GEOMETRY")
        if kind not in ("GEOMETRY", "OBJECT", "INSTANCER") or not e.props.get("attribute_name"):
            return self._const_node(e)
        out = {"Color": "color", "Vector": "vector", "Fac": "fac", "Alpha": "alpha"}.get(e.props.get("output"),
                                                                                         "color")
        d = {"node": "attribute", "name": e.props["attribute_name"], "output": out}
        if kind != "GEOMETRY":  # the object's own value, which the exporter sends per instance
            d["attribute_type"] = kind
        return d

    def normal(self, ir, owner):
        """A Normal input -> a normal_map/bump/bevel node, or None (the shading normal)."""
        if ir is None or isinstance(ir, Const):
            return None
        x = ir
        while isinstance(x, Expr) and x.op == "to_vec3":
            x = x.args.get("value")
        if isinstance(x, Expr) and x.op in ("normal_map", "bump", "bevel"):
            return self.value(x)
        if isinstance(x, Expr):
            self.approx(owner, "normal input from %s ignored" % x.node)
        return None

    # ---- closures -----------------------------------------------------------------
    def _with_normal(self, d, c, key="normal"):
        n = self.normal(c.params.get("normal"), c.node)
        if n is not None:
            d[key] = n
        return d

    def _const_color(self, ir, node, what):
        v = self.fold(ir)
        if v is None:
            v = self.ev.value(ir)
            self.approx(node, "textured %s evaluated as a constant" % what)
        v = (v, v, v) if isinstance(v, float) else v
        return [max(float(x), 0.0) for x in v]

    def _const_float(self, ir, node, what):
        v = self.fold(ir)
        if v is None:
            v = self.ev.float(ir)
            self.approx(node, "textured %s evaluated as a constant" % what)
        if not isinstance(v, float):
            v = luminance(v)
        return float(v)

    def shader(self, c, depth=0):
        """A Closure -> an engine material object (without name), or None (black)."""
        if c is None or depth > 200:
            return None
        k = c.kind
        p = c.params
        if k == "mix":
            a, b = (c.children + [None, None])[:2]
            fac = p.get("fac", Const(0.5))
            # Fresnel / Layer Weight straight into the factor: evaluated per pair of directions.
            # Textured factors above an emission too: the engine evaluates them per point.
            f = self._view_factor(fac) if self.context == "surface" else None
            if f is None:
                f = self.value(fac)
            if isinstance(f, float):
                f = _clamp01(f)
            s1, s2 = self.shader(a, depth + 1), self.shader(b, depth + 1)
            if isinstance(f, float) and f <= 0.0:
                return s1
            if isinstance(f, float) and f >= 1.0:
                return s2
            if isinstance(f, float):
                merged = _merge(_weighted(s1, 1.0 - f), _weighted(s2, f))
                if merged is not None:
                    return merged
            if s1 is None and s2 is None:
                return None
            d = {"type": "mix", "fac": f}
            if s1 is not None:
                d["shader1"] = s1
            if s2 is not None:
                d["shader2"] = s2
            return d
        if k == "add":
            ch = [self.shader(x, depth + 1) for x in c.children[:2]]
            ch = [x for x in ch if x is not None]
            if not ch:
                return None
            if len(ch) == 1:
                return ch[0]
            merged = _merge(ch[0], ch[1])
            if merged is not None:
                return merged
            return {"type": "add", "shader1": ch[0], "shader2": ch[1]}
        if k in ("emission", "background"):
            if k == "background" and self.context == "surface":
                self.approx(c.node, "Background shader in a material treated as emission")
            col, s = self._emitted(p["color"], p.get("strength", Const(1.0)))
            if (isinstance(col, list) and max(col) <= 0.0) or s == 0.0:
                return None
            return {"type": "emission", "color": col, "strength": s}
        if k == "diffuse":
            d = {"type": "diffuse", "color": self.value(p["color"], True)}
            r = p.get("roughness")
            if r is not None and self.fold(r) != 0.0:
                d["roughness"] = self.value(r)
            return self._with_normal(d, c)
        if k in ("glossy", "anisotropic"):
            dist = c.props.get("distribution", "GGX")
            smooth = self.fold(p.get("roughness", Const(0.5))) == 0.0  # the distribution does not matter
            if dist in ("BECKMANN", "ASHIKHMIN_SHIRLEY") and smooth:
                dist = "GGX"
            elif dist in ("BECKMANN", "ASHIKHMIN_SHIRLEY"):
                self.approx(c.node, "%s distribution approximated as GGX" % dist)
            d = {"type": "glossy", "color": self.value(p["color"], True),
                 "roughness": self.value(p.get("roughness", Const(0.5))), "distribution": dist}
            an = p.get("anisotropy")
            if an is not None and self.fold(an) != 0.0:
                d["anisotropy"] = self.value(an)
                d["rotation"] = self.value(p.get("rotation", Const(0.0)))
            if c.props.get("tangent_linked"):
                self.approx(c.node, "tangent input ignored (default UV map's u)")
            return self._with_normal(d, c)
        if k in ("glass", "refraction"):
            dist = c.props.get("distribution", "BECKMANN")
            if dist == "BECKMANN" and self.fold(p["roughness"]) == 0.0:
                dist = "GGX"  # smooth: the distribution does not matter
            elif dist == "BECKMANN":
                self.approx(c.node, "BECKMANN distribution approximated as GGX")
                dist = "GGX"
            elif dist == "MULTI_GGX" and k == "glass":
                self.approx(c.node, "MULTI_GGX glass approximated as GGX")
                dist = "GGX"
            d = {"type": k, "color": self.value(p["color"], True), "roughness": self.value(p["roughness"]),
                 "ior": self.value(p["ior"]), "distribution": dist}
            return self._with_normal(d, c)
        if k == "principled":
            return self._principled(c)
        if k == "transparent":
            return {"type": "transparent", "color": self.value(p["color"], True)}
        if k in ("translucent", "sheen"):
            return self._with_normal({"type": k, "color": self.value(p["color"], True)}, c)
        if k == "holdout":
            return {"type": "holdout"}  # black, and a hole in the alpha where the camera sees it
        if k == "unsupported":
            idname = c.props.get("bl_idname", "?")
            if idname == "ShaderNodeBsdfVelvet":
                self.approx(c.node, "Velvet approximated by the Principled sheen lobe")
                return self._with_normal({"type": "sheen", "color": self.value(p["color"], True)}, c)
            self.approx(c.node, "unsupported shader %s, shown as diffuse" % idname)
            return {"type": "diffuse", "color": self.value(p["color"], True)}
        if k == "volume":
            self.approx(c.node, "volume shader on a surface ignored")
            return None
        self.approx(c.node, "unknown closure '%s' ignored" % k)
        return None

    def _view_factor(self, fac):
        """The engine's view factor for a Mix Shader's factor that is a Fresnel / Layer Weight /
        Geometry > Backfacing node or the Dot Product of Geometry's Incoming and Normal, or one
        through nodes of constant settings (Color Ramp, Math, curves: baked into a table over the
        node's [0, 1]; scene-format.md); else None."""
        view = self._view_leaf(fac)
        if view is None:
            return None
        table = None
        if view is not fac:
            table = self._view_table(fac, view)
            if table is None:
                return None
        if view.props.get("normal_linked"):
            self.approx(view.node, "Normal input approximated by the interpolated normal")
        if view.op == "vector_math":  # Incoming . Normal: |cos| = 1 - Layer Weight's Facing at blend 0.5
            normals = {self._unwrap(view.args.get(k)).props.get("output") for k in ("a", "b")}
            if "True Normal" in normals:
                self.approx(view.node, "Incoming . True Normal approximated with the interpolated normal (the same on "
                                       "flat-shaded faces)")
            d = {"node": "layer_weight", "output": "facing", "blend": 0.5}
            d["table"] = self._view_table(fac, view, of=lambda y: 1.0 - y)
            return d if d["table"] is not None else None
        if view.op == "geometry":
            d = {"node": "backfacing"}
        elif view.op == "fresnel":
            d = {"node": "fresnel", "ior": self.value(view.args.get("ior", Const(1.45)))}
        else:
            d = {"node": "layer_weight", "output": view.props.get("output", "fresnel"),
                 "blend": self.value(view.args.get("blend", Const(0.5)))}
        if table is not None:
            d["table"] = table
        return d

    @classmethod
    def _is_view_node(cls, x):
        return (x.op in ("fresnel", "layer_weight") or (x.op == "geometry" and x.props.get("output") == "Backfacing")
                or cls._is_incoming_cosine(x))

    @staticmethod
    def _unwrap(x):
        while isinstance(x, Expr) and x.op == "to_vec3":
            x = x.args.get("value")
        return x

    @classmethod
    def _is_incoming_cosine(cls, x):
        """Vector Math's Dot Product of Geometry's Incoming and its Normal (or True Normal): the
        cosine of the viewing direction, |cos| as Cycles flips the normal toward the viewer."""
        if x.op != "vector_math" or x.props.get("operation") != "DOT_PRODUCT":
            return False
        outputs = []
        for k in ("a", "b"):
            arg = cls._unwrap(x.args.get(k))
            if not (isinstance(arg, Expr) and arg.op == "geometry"):
                return False
            outputs.append(arg.props.get("output"))
        return "Incoming" in outputs and ({"Normal", "True Normal"} & set(outputs)) != set()

    @classmethod
    def _view_leaf(cls, fac):
        """The one Fresnel / Layer Weight / Geometry > Backfacing node fac depends on, if nothing
        else in it varies."""
        views, seen, stack = [], set(), [fac]
        while stack:
            x = stack.pop()
            if not isinstance(x, Expr) or id(x) in seen:
                if isinstance(x, Closure):
                    return None
                continue
            seen.add(id(x))
            if cls._is_view_node(x):
                views.append(x)  # its own inputs (IOR, Blend) may vary: the engine evaluates them
                continue
            if x.op in VARYING_OPS:
                return None
            stack.extend(x.args.values())
        return views[0] if len(views) == 1 else None

    def _view_table(self, fac, view, n=256, of=lambda y: y):
        """fac as a function of the engine's factor y in [0, 1] (view's output of(y)), at n points
        (None if some node on the way cannot be evaluated exactly)."""
        table = []
        for i in range(n):
            issues = Issues()
            ev = Evaluator(issues, self.image_average)
            ev.assume(view, of(i / (n - 1.0)))
            v = ev.float(fac)
            if issues or not math.isfinite(v):
                return None
            table.append(round(min(max(v, 0.0), 1.0), 6))
        return table

    def _principled(self, c):
        p = c.params
        d = {"type": "principled"}
        for key in PRINCIPLED_KEYS:
            if key in p:
                d[key] = self.value(p[key], key in COLOR_KEYS)
        dist = c.props.get("distribution", "GGX")
        d["distribution"] = dist if dist in ("GGX", "MULTI_GGX") else "GGX"
        # Match the Blender the node comes from: 3.x's Principled adds its layers
        # (Cycles 3.4), 4.x's conserves energy (the engine's own default).
        d["layering"] = "energy_conserving" if c.props.get("blender4") else "additive"
        sub = self.fold(p.get("subsurface", Const(0.0)))
        if sub is None or sub > 0.0:
            self.approx(c.node, "subsurface approximated by diffuse")
        em, em_strength = self._emitted(p.get("emission", Const(0.0)), p.get("emission_strength", Const(1.0)))
        if not isinstance(em, list) or max(em) > 0.0:
            d["emission"] = em
            d["emission_strength"] = em_strength
        self._with_normal(d, c)
        cn = p.get("clearcoat_normal")
        if cn is not None and not isinstance(cn, Const):
            cc = self.fold(p.get("clearcoat", Const(0.0)))
            if cc is None or cc > 0.0:
                self.approx(c.node, "clearcoat normal ignored (main normal used)")
        if c.props.get("tangent_linked"):
            self.approx(c.node, "tangent input ignored (default UV map's u)")
        for note in c.props.get("approximated", ()):
            self.approx(c.node, note)
        return d

    # ---- volumes --------------------------------------------------------------------
    def grid_factor(self, ir):
        """(grid name, constant factor) when ir is an Attribute node's value (Fac, or Color /
        Vector made a float: one value for a float grid), possibly through Math Multiply by
        constants; else None."""
        factor = 1.0
        x = ir
        for _ in range(50):
            if isinstance(x, Expr) and x.op == "to_float":
                x = x.args.get("value")
            if not isinstance(x, Expr):
                return None
            if x.op == "attribute":
                name = x.props.get("attribute_name")
                if x.props.get("attribute_type", "GEOMETRY") != "GEOMETRY" or not name or \
                        x.props.get("output") == "Alpha":
                    return None
                return name, factor
            if x.op != "math" or x.props.get("operation") != "MULTIPLY" or x.props.get("use_clamp"):
                return None
            a, b = self.fold(x.args.get("a")), self.fold(x.args.get("b"))
            if isinstance(a, float):
                factor, x = factor * a, x.args.get("b")
            elif isinstance(b, float):
                factor, x = factor * b, x.args.get("a")
            else:
                return None
        return None

    def _volume_part(self, c):
        """One volume shader -> engine medium keys, grid references as {"name": ...} (the
        exporter of a Volume object adds the file; volumes.attach_grids)."""
        m = {}
        for k, v in c.params.items():
            grid_key = GRID_OF_SOCKET.get(k)
            gf = self.grid_factor(v) if grid_key and self.volume_grids else None
            if gf is not None:
                m[grid_key], m[k] = {"name": gf[0]}, gf[1]
            elif k.endswith("color") or k == "blackbody_tint":
                m[k] = self._const_color(v, c.node, "volume " + k.replace("_", " "))
            else:
                m[k] = self._const_float(v, c.node, "volume " + k.replace("_", " "))
        if c.props.get("absorption_color_sqrt") and "absorption_color" in m:
            m["absorption_color"] = [math.sqrt(max(x, 0.0)) for x in m["absorption_color"]]
        if self.volume_grids:
            # Cycles multiplies the density / temperature by these grids where the object has them.
            for prop, key, what in (("density_attribute", "grid", "density"),
                                    ("temperature_attribute", "temperature_grid", "temperature")):
                name = c.props.get(prop)
                if not name:
                    continue
                if key in m:  # Cycles would multiply both grids
                    self.approx(c.node, "%s from grid '%s' and from the attribute grid '%s': only '%s' used"
                                % (what, m[key]["name"], name, m[key]["name"]))
                else:
                    m[key] = {"name": name}
            if c.props.get("color_attribute"):
                self.approx(c.node, "Color Attribute '%s' ignored (colour grids are not read)"
                            % c.props["color_attribute"])
        if not m.get("blackbody_intensity", 0.0) > 0.0:
            for k in ("blackbody_intensity", "blackbody_tint", "temperature", "temperature_grid"):
                m.pop(k, None)
        if not m.get("emission_strength", 0.0) > 0.0 or max(m.get("emission_color", [1.0])) <= 0.0:
            m.pop("emission_grid", None)
        if not m.get("density", 0.0) > 0.0:
            m.pop("grid", None)
        return m

    def volume(self, c, depth=0):
        """A Volume closure -> list of (weight, medium keys) parts, or [] for none."""
        if c is None or depth > 50:
            return []
        if c.kind == "mix":
            f = _clamp01(self._const_float(c.params.get("fac", Const(0.5)), c.node, "volume mix factor"))
            a, b = (c.children + [None, None])[:2]
            return ([(w * (1 - f), m) for w, m in self.volume(a, depth + 1)]
                    + [(w * f, m) for w, m in self.volume(b, depth + 1)])
        if c.kind == "add":
            return [x for ch in c.children for x in self.volume(ch, depth + 1)]
        if c.kind == "volume":
            return [(1.0, self._volume_part(c))]
        if c.kind == "emission":
            col = self._const_color(c.params["color"], c.node, "emission colour")
            s = self._const_float(c.params.get("strength", Const(1.0)), c.node, "emission strength")
            return [(1.0, {"density": 0.0, "emission_color": col, "emission_strength": s})]
        self.approx(c.node, "%s shader in a Volume socket ignored" % c.kind)
        return []

    def _emitted(self, color, strength):
        """An emitter's colour and strength, lowered where the ray's length is known."""
        was, self.emitting = self.emitting, True
        try:
            return self.value(color, True), self.value(strength)
        finally:
            self.emitting = was

    def medium(self, c):
        # Cycles 3.4 shades volumes with a ray length of 0 (Light Falloff's value there).
        ev, self.ev = self.ev, Evaluator(self.issues, self.image_average, ray_length=0.0)
        try:
            return self._medium(c)
        finally:
            self.ev = ev

    def _medium(self, c):
        parts = [(w, m) for w, m in self.volume(c) if w > 0.0]
        if not parts:
            return None
        if len(parts) == 1 and parts[0][0] == 1.0 and parts[0][1].get("density", 0.0) > 0.0:
            return parts[0][1]
        # Several media (or emission only): sum physical coefficients.
        sa, ss, em = [0.0] * 3, [0.0] * 3, [0.0] * 3
        g_num = g_den = 0.0
        for w, m in parts:
            dens = m.get("density", 0.0) * w
            col = m.get("color", [0.5, 0.5, 0.5])
            acol = m.get("absorption_color", [0.0, 0.0, 0.0])
            for i in range(3):
                s = col[i] * dens
                ss[i] += s
                sa[i] += (1 - acol[i]) * (1 - col[i]) * dens
                em[i] += m.get("emission_color", [1, 1, 1])[i] * m.get("emission_strength", 0.0) * w
            g_num += m.get("anisotropy", 0.0) * luminance([col[i] * dens for i in range(3)])
            g_den += luminance([col[i] * dens for i in range(3)])
        out = {"sigma_a": sa, "sigma_s": ss, "anisotropy": g_num / g_den if g_den > 0 else 0.0}
        if max(em) > 0.0:
            out["emission"] = em
        # Grids shape the summed coefficients as a whole: exact when every part that has
        # the quantity uses the same grid.
        for key, what, has in (("grid", "density", lambda m: m.get("density", 0.0) > 0.0),
                               ("emission_grid", "emission", lambda m: m.get("emission_strength", 0.0) > 0.0)):
            users = [m for w, m in parts if has(m)]
            names = [m[key]["name"] for m in users if key in m]
            if not names:
                continue
            out[key] = {"name": names[0]}
            if len(set(names)) > 1 or len(names) < len(users):
                self.approx(c.node, "added/mixed volumes with different %s grids: '%s' used for all" % (what, names[0]))
        blackbody = [(w, m) for w, m in parts if "blackbody_intensity" in m]
        if blackbody:
            w, m = blackbody[0]
            out.update({k: m[k] for k in ("blackbody_intensity", "temperature", "temperature_grid") if k in m})
            out["blackbody_tint"] = [x * w for x in m.get("blackbody_tint", [1.0, 1.0, 1.0])]
            if len(blackbody) > 1:
                self.approx(c.node, "several blackbody volumes: only the first one emits")
        return out


# Principled Volume sockets whose value may come from a grid (an Attribute node), and the
# engine key of that grid.
GRID_OF_SOCKET = {"density": "grid", "emission_strength": "emission_grid", "temperature": "temperature_grid"}


_LINEAR_TYPES = ("diffuse", "glossy", "glass", "refraction", "transparent", "translucent", "sheen")


def _is_list(v):
    return isinstance(v, list) and len(v) == 3 and all(isinstance(x, float) for x in v)


def _weighted(d, w):
    """A closure scaled by a constant weight, when its colour is a constant multiplier (else None)."""
    if d is None:
        return False  # black: nothing to scale
    t = d.get("type")
    if t == "emission":
        return dict(d, strength=d["strength"] * w) if isinstance(d["strength"], float) else None
    if t in _LINEAR_TYPES and _is_list(d.get("color")) and "emission" not in d:
        return dict(d, color=[x * w for x in d["color"]])
    return None


def _constant_emission(d):
    return _is_list(d["color"]) and isinstance(d["strength"], float)


def _merge(a, b):
    """Sum of two (weighted) closures as one engine closure when that is exact, else None."""
    if a is None or b is None:
        return None
    if a is False or b is False:
        other = b if a is False else a
        return None if other is False else other
    if a["type"] == "emission" and b["type"] != "emission":
        a, b = b, a
    if any(x["type"] == "emission" and not _constant_emission(x) for x in (a, b)):
        return None
    if b["type"] == "emission":
        rad = [x * b["strength"] for x in b["color"]]
        if a["type"] == "emission":
            rad = [x * a["strength"] + y for x, y in zip(a["color"], rad)]
            m = max(rad)
            return {"type": "emission", "color": [x / m for x in rad] if m > 0 else rad, "strength": m}
        if a["type"] in ("diffuse", "glossy") and "emission" not in a:
            m = max(rad)
            return dict(a, emission=[x / m for x in rad] if m > 0 else rad, emission_strength=m)
        return None
    if a["type"] == b["type"] and a["type"] in _LINEAR_TYPES and _is_list(a.get("color")) and \
            _is_list(b.get("color")):
        ka = {k: v for k, v in a.items() if k != "color"}
        kb = {k: v for k, v in b.items() if k != "color"}
        if ka == kb:
            return dict(a, color=[x + y for x, y in zip(a["color"], b["color"])])
    return None


def lower_surface(desc, image_average=None, image_file=None, volume_grids=False):
    """MaterialDescription -> (engine params dict, Issues).  volume_grids: the material is a
    Volume object's, whose attribute names refer to its grids (else they are ignored, as
    Cycles ignores attributes a mesh does not have)."""
    low = _Lowerer(desc.issues, image_average, image_file, "surface", volume_grids)
    medium = low.medium(desc.volume) if desc.volume is not None else None
    if desc.surface is None:
        if medium is not None:
            params = {"type": "volume"}  # Cycles: volume only = a transparent boundary
        else:
            params = {"type": "diffuse", "color": [0.0, 0.0, 0.0]}  # Cycles: no closure = black
    else:
        params = low.shader(desc.surface)
        if params is None:
            params = {"type": "diffuse", "color": [0.0, 0.0, 0.0]}
        else:
            params.update(low.displacement(desc))
    if medium is not None:
        params["volume"] = medium
    aovs = getattr(desc, "aovs", ())
    if aovs:  # the engine writes the one its pass's type names (color or value)
        params["aovs"] = {name: {"color": low.value(color, True), "value": low.value(value)} for name, color, value in aovs}
    return params, desc.issues


def _unwrap(x):
    while isinstance(x, Expr) and x.op == "to_vec3":
        x = x.args.get("value")
    return x


def _mapping_rotation(low, col):
    """The constant rotation of a Mapping node on an environment's Vector input (None: none),
    with warnings for what else the vector does."""
    vec = _unwrap(col.args.get("vector"))
    rotation = None
    if isinstance(vec, Expr) and vec.op == "mapping":
        rot = low.fold(vec.args.get("rotation"))
        loc, scale = low.fold(vec.args.get("location")), low.fold(vec.args.get("scale"))
        if rot is None or vec.props.get("vector_type", "POINT") not in ("POINT", "VECTOR"):
            low.approx(vec.node, "only a constant rotation is supported here")
        else:
            rotation = list(rot) if not isinstance(rot, float) else [rot] * 3
        if (loc is not None and any(abs(x) > 1e-9 for x in _num(loc))) or \
                (scale is not None and any(abs(x - 1.0) > 1e-9 for x in _num(scale))):
            low.approx(vec.node, "location/scale ignored (rotation only)")
        inner = _unwrap(vec.args.get("vector"))
        if inner is not None and not isinstance(inner, Const) and \
                not (isinstance(inner, Expr) and inner.op == "texcoord" and inner.props.get("output") == "Generated"):
            low.approx(vec.node, "input vector ignored (view direction used)")
    elif vec is not None and not isinstance(vec, Const) and \
            not (isinstance(vec, Expr) and vec.op == "texcoord" and vec.props.get("output") == "Generated"):
        low.approx(col.node, "vector input ignored (view direction used)")
    return rotation


def _sky(low, c, col):
    """Background(color = Sky Texture, Nishita or Preetham [via Mapping]) -> world params, or None."""
    s = low._const_float(c.params.get("strength", Const(1.0)), c.node, "background strength")
    if col.props.get("sky_type", "NISHITA") == "PREETHAM":
        # Preetham reads its Vector (the view direction unless linked): a linked one is ignored.
        vec = _unwrap(col.args.get("vector"))
        if vec is not None and not isinstance(vec, Const) and \
                not (isinstance(vec, Expr) and vec.op == "texcoord" and vec.props.get("output") == "Generated"):
            low.approx(col.node, "vector input ignored (view direction used)")
        sky = {"type": "preetham", "sun_direction": list(col.props.get("sun_direction", [0.0, 0.0, 1.0])),
               "turbidity": float(col.props.get("turbidity", 2.2))}
        return {"sky": sky, "color": [1.0, 1.0, 1.0], "strength": s}
    if col.props.get("sky_type", "NISHITA") != "NISHITA":
        return None  # Hosek-Wilkie: the constant, with the evaluator's warning
    sky = {"type": "nishita"}
    for k in ("sun_disc", "sun_size", "sun_intensity", "sun_elevation", "sun_rotation", "altitude",
              "air_density", "dust_density", "ozone_density"):
        if k in col.props:
            sky[k] = bool(col.props[k]) if k == "sun_disc" else float(col.props[k])
    # Its Vector input is not read: Cycles 3.4 renders a Nishita sky by the view direction whatever
    # is linked there (measured: a Mapping's rotation changes nothing in its image).
    return {"sky": sky, "color": [1.0, 1.0, 1.0], "strength": s}


def _environment(low, c):
    """Background(color = Environment Texture or Nishita Sky Texture [via Mapping]) -> world
    params, or None."""
    if c is None or c.kind != "background":
        return None
    col = _unwrap(c.params.get("color"))
    if isinstance(col, Expr) and col.op == "tex_sky":
        return _sky(low, c, col)
    if not isinstance(col, Expr) or col.op != "tex_environment" or col.props.get("output") == "Alpha":
        return None
    path = low._image_file(col)
    if isinstance(path, dict) and set(path) == {"file"}:
        path = path["file"]  # a sequence's frame
    if not isinstance(path, str):
        return None  # no file (average colour), a movie or UDIM tiles: not as an environment
    env = {"file": path}
    if col.props.get("colorspace"):
        env["colorspace"] = col.props["colorspace"]
    if col.props.get("projection", "EQUIRECTANGULAR") != "EQUIRECTANGULAR":
        low.approx(col.node, "%s projection approximated as equirectangular" % col.props.get("projection"))
    rotation = _mapping_rotation(low, col)
    if rotation is not None:
        env["rotation"] = rotation
    s = low._const_float(c.params.get("strength", Const(1.0)), c.node, "background strength")
    return {"environment": env, "color": [1.0, 1.0, 1.0], "strength": s}


def lower_world(desc, image_average=None, image_file=None):
    """WorldDescription -> ({"color", "strength"[, "environment", "volume"]}, Issues)."""
    low = _Lowerer(desc.issues, image_average, image_file, "world")
    medium = low.medium(desc.volume) if desc.volume is not None else None
    params = _environment(low, desc.surface)
    if params is None:
        radiance = _world_radiance(low, desc.surface)
        m = max(radiance)
        params = ({"color": [x / m for x in radiance], "strength": m} if m > 1.0
                  else {"color": radiance, "strength": 1.0})
    if medium is not None:
        params["volume"] = medium
    aovs = getattr(desc, "aovs", ())
    if aovs:  # the engine writes the one its pass's type names (color or value)
        params["aovs"] = {name: {"color": low.value(color, True), "value": low.value(value)} for name, color, value in aovs}
    return params, desc.issues


def _world_radiance(low, c, depth=0):
    """Constant radiance of a world surface closure (mix/add of backgrounds)."""
    if c is None or depth > 50:
        return [0.0, 0.0, 0.0]
    if c.kind == "mix":
        f = _clamp01(low.ev.float(c.params.get("fac", Const(0.5))))
        a, b = (c.children + [None, None])[:2]
        ra, rb = _world_radiance(low, a, depth + 1), _world_radiance(low, b, depth + 1)
        return [(1 - f) * x + f * y for x, y in zip(ra, rb)]
    if c.kind == "add":
        rs = [_world_radiance(low, x, depth + 1) for x in c.children]
        return [sum(r[i] for r in rs) for i in range(3)]
    if c.kind in ("emission", "background"):
        col = low.ev.color(c.params["color"])
        s = low.ev.float(c.params.get("strength", Const(1.0)))
        return [max(x * s, 0.0) for x in col]
    low.approx(c.node, "%s shader on the world ignored" % c.kind)
    return [0.0, 0.0, 0.0]


# Nodes whose value is the same all over a lamp (no texture coordinates, images or geometry):
# a light's Emission may use them, the engine evaluating them once (Blackbody, Wavelength).
_LAMP_CONSTANT_LEAVES = {"blackbody", "wavelength"}
# What a lamp's shader sees vary: the direction light leaves it by (Cycles' normal on a lamp).
_LAMP_DIRECTION_OUTPUTS = {"texcoord": {"Normal"}, "geometry": {"Normal", "True Normal"}}
# ... and, but for a sun, the point light leaves it from: Cycles 3.4's lamp has no object, so
# Position, Object and Generated are that point in the world, UV (any UV map) is 0, and
# Parametric runs over an area lamp from 0 to 1 along its X and Y (lights/lamp_emission.h).
_LAMP_POINT_OUTPUTS = {"texcoord": {"Generated", "Object", "UV"}, "geometry": {"Position", "Parametric"}}
_LAMP_TEXTURES = {*PROCEDURAL_TEXTURES, "tex_image", "tex_checker", "tex_noise", "tex_gradient", "uvmap"}


def _lamp_evaluates(ir, points, depth=0):
    """Whether the engine evaluates ir on a lamp as Cycles does: the same all over it, or varying
    with the direction light leaves by (IES Texture, Texture Coordinate / Geometry normals), and
    with points: with the point it leaves from (textures of the point's coordinates)."""
    if not isinstance(ir, Expr) or depth > 200:
        return not isinstance(ir, Closure)
    output = ir.props.get("output")
    if ir.op == "tex_ies" or output in _LAMP_DIRECTION_OUTPUTS.get(ir.op, ()):
        pass
    elif points and (ir.op in _LAMP_TEXTURES or output in _LAMP_POINT_OUTPUTS.get(ir.op, ())):
        if ir.op == "texcoord" and ir.props.get("object"):
            return False  # another object's space: not a lamp's
    elif ir.op in VARYING_OPS and ir.op not in _LAMP_CONSTANT_LEAVES:
        return False
    return all(_lamp_evaluates(a, points, depth + 1) for a in ir.args.values())


def lower_light(desc, image_average=None, image_file=None, sun=False):
    """A light's node tree (Cycles multiplies its Emission's Color and Strength into the lamp's
    colour and power) -> ({"color": value, "strength": value} or None, Issues). The engine
    evaluates what varies with the direction light leaves by (an IES Texture), with the
    distance it travels (a Light Falloff) and, but for a sun, with the point it leaves from (an
    image over an area lamp); values that vary otherwise (a Fresnel, Object Info) are taken
    as constants, named."""
    low = _Lowerer(desc.issues, image_average, image_file, "light")
    low.emitting = True
    c = desc.surface
    if c is None:
        return None, desc.issues
    if not (isinstance(c, Closure) and c.kind == "emission"):
        low.approx(getattr(c, "node", desc.output_label), "only an Emission shader is used by a light; ignored")
        return None, desc.issues
    out = {}
    for key, color in (("color", True), ("strength", False)):
        ir = c.params.get(key)
        if ir is not None and not _lamp_evaluates(ir, points=not sun):
            out[key] = low.const(ir, "varies over the lamp: taken as a constant")
            out[key] = _constant(out[key], color)
        else:
            out[key] = low.value(ir, color) if ir is not None else (1.0 if not color else [1.0, 1.0, 1.0])
    return out, desc.issues
