"""Stand-in node trees with the attributes shaders_map reads from bpy."""

from node_specs import SPECS

# Nodes the dump did not cover (layout of Blender 3.4.1).
EXTRA_SPECS = {
    "ShaderNodeOutputMaterial": ([("Surface", "Surface", "SHADER", None), ("Volume", "Volume", "SHADER", None),
                                  ("Displacement", "Displacement", "VECTOR", (0.0, 0.0, 0.0)),
                                  ("Thickness", "Thickness", "VALUE", 0.0)], []),
    "ShaderNodeDisplacement": ([("Height", "Height", "VALUE", 0.0), ("Midlevel", "Midlevel", "VALUE", 0.5),
                                ("Scale", "Scale", "VALUE", 1.0), ("Normal", "Normal", "VECTOR", (0.0, 0.0, 0.0))],
                               [("Displacement", "Displacement", "VECTOR", (0.0, 0.0, 0.0))]),
    "ShaderNodeVectorDisplacement": ([("Vector", "Vector", "RGBA", (0.0, 0.0, 0.0, 0.0)),
                                      ("Midlevel", "Midlevel", "VALUE", 0.0), ("Scale", "Scale", "VALUE", 1.0)],
                                     [("Displacement", "Displacement", "VECTOR", (0.0, 0.0, 0.0))]),
    "ShaderNodeCameraData": ([], [("View Vector", "View Vector", "VECTOR", (0.0, 0.0, 0.0)),
                                  ("View Z Depth", "View Z Depth", "VALUE", 0.0),
                                  ("View Distance", "View Distance", "VALUE", 0.0)]),
    "ShaderNodeOutputAOV": ([("Color", "Color", "RGBA", (0.0, 0.0, 0.0, 1.0)), ("Value", "Value", "VALUE", 0.0)], []),
    "ShaderNodeTexIES": ([("Vector", "Vector", "VECTOR", (0.0, 0.0, 0.0)), ("Strength", "Strength", "VALUE", 1.0)],
                         [("Fac", "Fac", "VALUE", 0.0)]),
    "ShaderNodeBlackbody": ([("Temperature", "Temperature", "VALUE", 1500.0)], [("Color", "Color", "RGBA", (0.0, 0.0, 0.0, 0.0))]),
    "ShaderNodeOutputLight": ([("Surface", "Surface", "SHADER", None)], []),
    "ShaderNodeLightFalloff": ([("Strength", "Strength", "VALUE", 100.0), ("Smooth", "Smooth", "VALUE", 0.0)],
                               [("Quadratic", "Quadratic", "VALUE", 0.0), ("Linear", "Linear", "VALUE", 0.0),
                                ("Constant", "Constant", "VALUE", 0.0)]),
    "ShaderNodeWireframe": ([("Size", "Size", "VALUE", 0.01)], [("Fac", "Fac", "VALUE", 0.0)]),
    "ShaderNodeHueSaturation": ([("Hue", "Hue", "VALUE", 0.5), ("Saturation", "Saturation", "VALUE", 1.0),
                                 ("Value", "Value", "VALUE", 1.0), ("Fac", "Fac", "VALUE", 1.0),
                                 ("Color", "Color", "RGBA", (0.8, 0.8, 0.8, 1.0))],
                                [("Color", "Color", "RGBA", (0.0, 0.0, 0.0, 0.0))]),
    "ShaderNodeVolumePrincipled": ([("Color", "Color", "RGBA", (0.5, 0.5, 0.5, 1.0)),
                                    ("Color Attribute", "Color Attribute", "STRING", ""),
                                    ("Density", "Density", "VALUE", 1.0),
                                    ("Density Attribute", "Density Attribute", "STRING", "density"),
                                    ("Anisotropy", "Anisotropy", "VALUE", 0.0),
                                    ("Absorption Color", "Absorption Color", "RGBA", (0.0, 0.0, 0.0, 1.0)),
                                    ("Emission Strength", "Emission Strength", "VALUE", 0.0),
                                    ("Emission Color", "Emission Color", "RGBA", (1.0, 1.0, 1.0, 1.0)),
                                    ("Blackbody Intensity", "Blackbody Intensity", "VALUE", 0.0),
                                    ("Blackbody Tint", "Blackbody Tint", "RGBA", (1.0, 1.0, 1.0, 1.0)),
                                    ("Temperature", "Temperature", "VALUE", 1000.0),
                                    ("Temperature Attribute", "Temperature Attribute", "STRING", "temperature"),
                                    ("Weight", "Weight", "VALUE", 0.0)],
                                   [("Volume", "Volume", "SHADER", None)]),
    "ShaderNodeVolumeScatter": ([("Color", "Color", "RGBA", (0.8, 0.8, 0.8, 1.0)), ("Density", "Density", "VALUE", 1.0),
                                 ("Anisotropy", "Anisotropy", "VALUE", 0.0), ("Weight", "Weight", "VALUE", 0.0)],
                                [("Volume", "Volume", "SHADER", None)]),
    "ShaderNodeVolumeAbsorption": ([("Color", "Color", "RGBA", (0.8, 0.8, 0.8, 1.0)),
                                    ("Density", "Density", "VALUE", 1.0), ("Weight", "Weight", "VALUE", 0.0)],
                                   [("Volume", "Volume", "SHADER", None)]),
    "ShaderNodeAttribute": ([], [("Color", "Color", "RGBA", (0.0, 0.0, 0.0, 0.0)),
                                 ("Vector", "Vector", "VECTOR", (0.0, 0.0, 0.0)), ("Fac", "Fac", "VALUE", 0.0),
                                 ("Alpha", "Alpha", "VALUE", 0.0)]),
    "ShaderNodeFancyUnknownBsdf": ([("Color", "Color", "RGBA", (0.3, 0.6, 0.9, 1.0))],
                                   [("BSDF", "BSDF", "SHADER", None)]),
}


class Socket:
    def __init__(self, node, identifier, name, type_, default, is_output):
        self.node = node
        self.identifier = identifier
        self.name = name
        self.type = type_
        self.enabled = True
        self.is_output = is_output
        if isinstance(default, tuple):
            default = list(default)
        self.default_value = default

    def __repr__(self):
        return "<Socket %s.%s>" % (self.node.name, self.identifier)


class InternalLink:
    def __init__(self, from_socket, to_socket):
        self.from_socket = from_socket
        self.to_socket = to_socket


class Link:
    def __init__(self, from_socket, to_socket):
        self.from_socket = from_socket
        self.to_socket = to_socket
        self.from_node = from_socket.node
        self.to_node = to_socket.node
        self.is_muted = False
        self.is_valid = True


class Element:
    def __init__(self, position, color):
        self.position = position
        self.color = list(color)


class Ramp:
    def __init__(self, elements, interpolation="LINEAR"):
        self.elements = [Element(p, c) for p, c in elements]
        self.interpolation = interpolation
        self.color_mode = "RGB"


class EvaluatingRamp(Ramp):
    """A ramp with Blender's ColorRamp.evaluate (here: fn(position) -> (r, g, b, a))."""

    def __init__(self, elements, fn, interpolation="B_SPLINE"):
        super().__init__(elements, interpolation)
        self._fn = fn

    def evaluate(self, position):
        return self._fn(position)


class CurvePoint:
    def __init__(self, x, y):
        self.location = (x, y)


class Curve:
    def __init__(self, points, fn):
        self.points = [CurvePoint(x, y) for x, y in points]
        self.fn = fn


class CurveMapping:
    """Blender's CurveMapping as the exporter reads it: curves (their points' x range) and
    evaluate(curve, x), here each curve's fn(x)."""

    def __init__(self, curves, extend="EXTRAPOLATED"):
        self.curves = curves
        self.extend = extend
        self.initialized = False

    def initialize(self):
        self.initialized = True

    def update(self):
        pass

    def evaluate(self, curve, x):
        assert self.initialized, "Blender needs initialize() before evaluate()"
        return curve.fn(x)


class Node:
    def __init__(self, tree, bl_idname, name, inputs, outputs):
        self.tree = tree
        self.bl_idname = bl_idname
        self.name = name
        self.mute = False
        self.inputs = [Socket(self, *s, is_output=False) for s in inputs]
        self.outputs = [Socket(self, *s, is_output=True) for s in outputs]
        self.internal_links = []

    def set(self, **props):
        for k, v in props.items():
            setattr(self, k, v)
        return self

    def inp(self, ident):
        for s in self.inputs:
            if s.identifier == ident:
                return s
        for s in self.inputs:
            if s.name == ident:
                return s
        raise KeyError(ident)

    def out(self, ident=None):
        if ident is None:
            return self.outputs[0]
        for s in self.outputs:
            if s.identifier == ident or s.name == ident:
                return s
        raise KeyError(ident)

    def mute_with_passthrough(self):
        """Mute like Blender: the first input of the output's type passes through."""
        self.mute = True
        self.internal_links = []
        for o in self.outputs:
            for i in self.inputs:
                if i.type == o.type or (o.type in ("RGBA", "VECTOR") and i.type in ("RGBA", "VECTOR")):
                    self.internal_links.append(InternalLink(i, o))
                    break
        return self


class Tree:
    def __init__(self, name="tree"):
        self.name = name
        self.nodes = []
        self.links = []

    def new(self, bl_idname, name=None, **props):
        spec = SPECS.get(bl_idname) or EXTRA_SPECS.get(bl_idname)
        if spec is None:
            raise KeyError(bl_idname)
        inputs, outputs = spec
        n = Node(self, bl_idname, name or bl_idname, inputs, outputs)
        if bl_idname.startswith("ShaderNodeOutput"):
            n.is_active_output = True
            n.target = "ALL"
        n.set(**props)
        self.nodes.append(n)
        return n

    def link(self, from_socket, to_socket):
        link = Link(from_socket, to_socket)
        self.links.append(link)
        return link

    def output(self):
        return self.new("ShaderNodeOutputMaterial", "Material Output")

    def group_node(self, inner, name="Group"):
        """A group node whose sockets mirror the inner tree's Group Input/Output."""
        gin = next((n for n in inner.nodes if n.bl_idname == "NodeGroupInput"), None)
        gout = next((n for n in inner.nodes if n.bl_idname == "NodeGroupOutput"), None)
        ins = [(s.identifier, s.name, s.type, s.default_value) for s in (gin.outputs if gin else [])]
        outs = [(s.identifier, s.name, s.type, None) for s in (gout.inputs if gout else [])]
        n = Node(self, "ShaderNodeGroup", name, ins, outs)
        n.node_tree = inner
        self.nodes.append(n)
        return n


def group_tree(name, inputs, outputs):
    """inputs/outputs: [(identifier, name, type, default)]; returns (tree, gin, gout)."""
    t = Tree(name)
    gin = Node(t, "NodeGroupInput", "Group Input", [], inputs)
    gout = Node(t, "NodeGroupOutput", "Group Output", [(i, n, ty, d) for i, n, ty, d in outputs], [])
    gout.is_active_output = True
    t.nodes += [gin, gout]
    return t, gin, gout


class Material:
    def __init__(self, name, tree=None, use_nodes=True, diffuse_color=(0.8, 0.8, 0.8, 1.0), displacement_method=None):
        self.name = name
        if displacement_method is not None:  # Blender 3.x: the Cycles add-on's material settings
            self.cycles = type("CyclesMaterialSettings", (), {"displacement_method": displacement_method})()
        self.node_tree = tree
        self.use_nodes = use_nodes
        self.diffuse_color = list(diffuse_color)


class World:
    def __init__(self, name, tree=None, use_nodes=True, color=(0.05, 0.05, 0.05)):
        self.name = name
        self.node_tree = tree
        self.use_nodes = use_nodes
        self.color = list(color)


class Image:
    def __init__(self, name, filepath="//tex.png", average=((0.25, 0.5, 0.75), 1.0), missing=False):
        self.name = name
        self.filepath = filepath
        self.average = average
        self.missing = missing


def image_average(image):
    return "missing" if image.missing else image.average
