"""Constant evaluation of IR values.

Exact for constants and the arithmetic nodes (Math, Mix, Invert, Color Ramp, ...);
values that vary over the surface (textures, coordinates) are replaced by a
representative constant (a texture's average colour) and the node is recorded as
approximated, so lowering can warn about it.
"""

from .ir import Const, Expr, Closure
from .issues import Issues
from .registry import EVALUATORS
from .graph import to_float

MAGENTA = (1.0, 0.0, 1.0)


class Evaluator:
    def __init__(self, issues=None, image_average=None, ray_length=None):
        self.issues = issues if issues is not None else Issues()
        self.image_average = image_average
        # The length of the ray that reached the point, where it is the same everywhere (0 on
        # the world and in volumes, as Cycles 3.4); None: not known (Light Falloff).
        self.ray_length = ray_length
        self._memo = {}

    def approx(self, expr, reason):
        self.issues.add(expr.node, reason)

    def value(self, ir):
        if ir is None:
            return 0.0
        if isinstance(ir, Const):
            return ir.value
        if isinstance(ir, Closure):
            return 0.0
        key = id(ir)
        if key in self._memo:
            return self._memo[key][1]
        fn = EVALUATORS.get(ir.op)
        if fn is None:
            self.approx(ir, "cannot evaluate '%s', using 0.5" % ir.op)
            v = 0.5
        else:
            v = fn(self, ir)
        self._memo[key] = (ir, v)  # keep ir alive so id() stays unique
        return v

    def assume(self, ir, value):
        """Evaluate as if ir's value were value (a node's output held fixed, e.g. to tabulate
        what the nodes after it make of it)."""
        self._memo[id(ir)] = (ir, value)

    def float(self, ir):
        v = self.value(ir)
        return v if isinstance(v, float) else to_float(v)

    def color(self, ir):
        v = self.value(ir)
        if isinstance(v, float):
            return (v, v, v)
        return tuple(v)

    def arg(self, expr, name, default=0.0):
        a = expr.args.get(name)
        return self.value(a) if a is not None else default


def is_constant(ir):
    """True when the IR value does not vary over the surface (no textures/coordinates)."""
    seen = set()
    stack = [ir]
    while stack:
        x = stack.pop()
        if x is None or isinstance(x, Const):
            continue
        if id(x) in seen:
            continue
        seen.add(id(x))
        if isinstance(x, Expr):
            if x.op in VARYING_OPS:
                return False
            stack.extend(x.args.values())
    return True


# Blender's procedural textures the engine computes as Blender does, beyond Checker, Noise
# and Gradient.
PROCEDURAL_TEXTURES = ("tex_voronoi", "tex_musgrave", "tex_wave", "tex_magic", "tex_brick", "tex_white_noise")

VARYING_OPS = {
    *PROCEDURAL_TEXTURES,
    "tex_image", "tex_environment", "tex_checker", "tex_noise", "tex_gradient", "tex_ies",
    "texcoord", "uvmap", "normal_map", "bump", "bevel", "displacement", "vector_displacement", "vertex_color", "attribute", "geometry", "object_info", "camera_data", "blackbody",
    "wavelength", "wireframe", "ao",
    "fresnel", "layer_weight",
}


# ---- evaluators shared by several families -------------------------------------
from .registry import evaluates  # noqa: E402


@evaluates("to_float")
def _to_float(ev, e):
    v = ev.arg(e, "value")
    return v if isinstance(v, float) else to_float(v, e.props.get("from", "RGBA"))


@evaluates("to_vec3")
def _to_vec3(ev, e):
    v = ev.arg(e, "value")
    return (v, v, v) if isinstance(v, float) else tuple(v)
