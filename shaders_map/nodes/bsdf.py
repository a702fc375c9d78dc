"""BSDF nodes: Principled, Diffuse, Glossy/Anisotropic, Glass, Refraction,
Transparent, Translucent, Velvet, Toon, Sheen (as closures with their inputs)."""

from ..ir import Closure, Const, Expr
from ..registry import maps

# Principled inputs: our key -> socket identifiers/names, 3.x first, then 4.x.
PRINCIPLED_INPUTS = {
    "base_color": ("Base Color",),
    "subsurface": ("Subsurface", "Subsurface Weight"),
    "subsurface_radius": ("Subsurface Radius",),
    "subsurface_color": ("Subsurface Color",),
    "metallic": ("Metallic",),
    "specular": ("Specular", "Specular IOR Level"),
    "specular_tint": ("Specular Tint",),
    "roughness": ("Roughness",),
    "anisotropic": ("Anisotropic",),
    "anisotropic_rotation": ("Anisotropic Rotation",),
    "sheen": ("Sheen", "Sheen Weight"),
    "sheen_tint": ("Sheen Tint",),
    "clearcoat": ("Clearcoat", "Coat Weight", "Coat"),
    "clearcoat_roughness": ("Clearcoat Roughness", "Coat Roughness"),
    "ior": ("IOR",),
    "transmission": ("Transmission", "Transmission Weight"),
    "transmission_roughness": ("Transmission Roughness",),
    "emission": ("Emission", "Emission Color"),
    "emission_strength": ("Emission Strength",),
    "alpha": ("Alpha",),
    "normal": ("Normal",),
    "clearcoat_normal": ("Clearcoat Normal", "Coat Normal"),
}

PRINCIPLED_DEFAULTS = {
    "base_color": (0.8, 0.8, 0.8), "subsurface": 0.0, "subsurface_radius": (1.0, 0.2, 0.1),
    "subsurface_color": (0.8, 0.8, 0.8), "metallic": 0.0, "specular": 0.5, "specular_tint": 0.0,
    "roughness": 0.5, "anisotropic": 0.0, "anisotropic_rotation": 0.0, "sheen": 0.0,
    "sheen_tint": 0.5, "clearcoat": 0.0, "clearcoat_roughness": 0.03, "ior": 1.45,
    "transmission": 0.0, "transmission_roughness": 0.0, "emission": (0.0, 0.0, 0.0),
    "emission_strength": 1.0, "alpha": 1.0, "normal": (0.0, 0.0, 0.0),
    "clearcoat_normal": (0.0, 0.0, 0.0),
}


@maps("ShaderNodeBsdfPrincipled")
def principled(ctx, node, socket):
    params = {}
    for key, names in PRINCIPLED_INPUTS.items():
        if ctx.has_input(node, *names):
            params[key] = ctx.input(node, *names)
        elif key == "emission_strength" and ctx.has_input(node, "Emission", "Emission Color"):
            params[key] = Const(1.0)
        else:
            params[key] = Const(PRINCIPLED_DEFAULTS[key])
    if not ctx.has_input(node, "Subsurface Color"):
        params["subsurface_color"] = params["base_color"]  # Blender 4.x: subsurface takes the base colour
    props = {"distribution": getattr(node, "distribution", "GGX"),
             "subsurface_method": getattr(node, "subsurface_method", "RANDOM_WALK"),
             "tangent_linked": ctx.is_linked(node, "Tangent")}
    # Blender 4.x's node has sockets that 3.x lacks.
    props["blender4"] = ctx.has_input(node, "Specular IOR Level") or ctx.has_input(node, "Coat Weight")
    if props["blender4"]:
        props["approximated"] = _blender4_principled(ctx, node, params)
    return Closure("principled", ctx.label(node), params, props=props)


def _blender4_principled(ctx, node, params):
    """Blender 4.x semantics on the engine's 3.4-style inputs; returns what is approximated.

    4.x reflects F0(IOR) x 2 x Specular IOR Level at normal incidence; the engine's
    specular s reflects 0.08 s, so s = level x 25 F0(IOR) (exact for a constant IOR)."""
    notes = []
    ior = ctx.input_const(node, "IOR", default=1.5)
    if ior is None:
        notes.append("textured IOR: specular reflection from Specular IOR Level alone")
    else:
        k = 25.0 * ((ior - 1.0) / (ior + 1.0)) ** 2
        level = params["specular"]
        params["specular"] = (Const(level.value * k) if isinstance(level, Const) else
                              Expr("math", ctx.label(node), {"a": level, "b": Const(k)}, {"operation": "MULTIPLY"}))

    def used(weight):  # a layer weight that is not a constant 0
        w = ctx.input_const(node, weight, default=0.0)
        return w is None or w != 0.0

    def differs(name, default):  # linked, or not at its default
        v = ctx.input_const(node, name, default=default)
        return v is None or (v != default if isinstance(v, float) else tuple(v)[:3] != default)

    if used("Coat Weight") and differs("Coat IOR", 1.5):
        notes.append("Coat IOR ignored (coat f0 0.04)")
    if used("Coat Weight") and differs("Coat Tint", (1.0, 1.0, 1.0)):
        notes.append("Coat Tint ignored (white coat)")
    if used("Sheen Weight") and differs("Sheen Roughness", 0.5):
        notes.append("Sheen Roughness ignored (Cycles 3.4 sheen lobe)")
    if ctx.has_input(node, "Thin Film Thickness") and differs("Thin Film Thickness", 0.0):
        notes.append("thin film ignored")
    return notes


@maps("ShaderNodeBsdfDiffuse")
def diffuse(ctx, node, socket):
    return Closure("diffuse", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "roughness": ctx.input(node, "Roughness", default=0.0),
        "normal": ctx.input(node, "Normal", default=(0.0, 0.0, 0.0)),
    })


@maps("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic")
def glossy(ctx, node, socket):
    params = {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "roughness": ctx.input(node, "Roughness", default=0.5),
        "normal": ctx.input(node, "Normal", default=(0.0, 0.0, 0.0)),
    }
    # 4.x merged Anisotropic into Glossy: the sockets exist on both there.
    if ctx.has_input(node, "Anisotropy"):
        params["anisotropy"] = ctx.input(node, "Anisotropy")
        params["rotation"] = ctx.input(node, "Rotation")
    kind = "anisotropic" if getattr(node, "bl_idname", "") == "ShaderNodeBsdfAnisotropic" else "glossy"
    return Closure(kind, ctx.label(node), params,
                   props={"distribution": getattr(node, "distribution", "GGX"),
                          "tangent_linked": ctx.is_linked(node, "Tangent")})


@maps("ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction")
def glass(ctx, node, socket):
    kind = "glass" if getattr(node, "bl_idname", "") == "ShaderNodeBsdfGlass" else "refraction"
    return Closure(kind, ctx.label(node), {
        "color": ctx.input(node, "Color", default=(1.0, 1.0, 1.0)),
        "roughness": ctx.input(node, "Roughness", default=0.0),
        "ior": ctx.input(node, "IOR", default=1.45),
        "normal": ctx.input(node, "Normal", default=(0.0, 0.0, 0.0)),
    }, props={"distribution": getattr(node, "distribution", "BECKMANN")})


@maps("ShaderNodeBsdfTransparent")
def transparent(ctx, node, socket):
    return Closure("transparent", ctx.label(node),
                   {"color": ctx.input(node, "Color", default=(1.0, 1.0, 1.0))})


@maps("ShaderNodeBsdfTranslucent")
def translucent(ctx, node, socket):
    return Closure("translucent", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "normal": ctx.input(node, "Normal", default=(0.0, 0.0, 0.0)),
    })


@maps("ShaderNodeBsdfSheen")
def sheen(ctx, node, socket):
    """Blender 4.x Sheen BSDF (the engine's Principled sheen lobe)."""
    return Closure("sheen", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "normal": ctx.input(node, "Normal", default=(0.0, 0.0, 0.0)),
    })


@maps("ShaderNodeBsdfVelvet", "ShaderNodeBsdfToon",
      "ShaderNodeSubsurfaceScattering", "ShaderNodeBsdfHair", "ShaderNodeBsdfHairPrincipled")
def other_bsdf(ctx, node, socket):
    """BSDFs with no neutral model yet: kept by name so lowering can fall back and warn."""
    color = ctx.input(node, "Color", "Base Color", default=(0.8, 0.8, 0.8))
    return Closure("unsupported", ctx.label(node), {"color": color},
                   props={"bl_idname": getattr(node, "bl_idname", "?")})
