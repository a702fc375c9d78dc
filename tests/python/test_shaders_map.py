"""shaders_map with stand-in nodes: run with `python3 -m unittest discover -s tests/python`
(from the repository root; the repository root must be importable)."""

import json
import os
import sys
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, ROOT)

import shaders_map as sm  # noqa: E402
from fakenodes import (Tree, Material, World, Image, Ramp, EvaluatingRamp, Curve, CurveMapping, Socket,  # noqa: E402
                       group_tree, image_average)


def material_with(build, name="M", image_average_fn=image_average):
    """build(tree) returns the socket to plug into the output's Surface."""
    t = Tree(name)
    out = t.output()
    sock = build(t)
    if sock is not None:
        t.link(sock, out.inp("Surface"))
    return sm.convert_material(Material(name, t), image_average=image_average_fn)


def _diamond(t, source, n, operation):
    """A Diffuse BSDF coloured by n Math nodes, each fed twice by the one before (from source)."""
    prev = source
    for i in range(n):
        m = t.new("ShaderNodeMath", "M%d" % i, operation=operation, use_clamp=False)
        t.link(prev.out(), m.inputs[0])
        t.link(prev.out(), m.inputs[1])
        prev = m
    d = t.new("ShaderNodeBsdfDiffuse", "D")
    t.link(prev.out(), d.inp("Color"))
    return d.out()


def close(a, b, tol=1e-5):
    if isinstance(a, (int, float)):
        return abs(a - b) <= tol
    return all(abs(x - y) <= tol for x, y in zip(a, b)) and len(a) == len(b)


class TestBsdfs(unittest.TestCase):
    def test_diffuse_exact(self):
        p, w = material_with(lambda t: t.new("ShaderNodeBsdfDiffuse", "D").set().out()
                             if False else _diffuse(t, (0.2, 0.4, 0.6)).out())
        self.assertEqual(p["type"], "diffuse")
        self.assertTrue(close(p["color"], (0.2, 0.4, 0.6)))
        self.assertIsNone(w)

    def test_microfacets_follow_blender_version(self):
        # Cycles before 3.5: separable GGX shadowing, glass split at the shading normal (README).
        def tree():
            t = Tree("M")
            g = t.new("ShaderNodeBsdfGlossy", "Shiny", distribution="GGX")
            t.link(g.out(), t.output().inp("Surface"))
            return Material("M", t)
        for version, expected in (((3, 4, 1), "cycles_3.4"), ((3, 5, 0), None), ((4, 2, 0), None), (None, None)):
            p, _ = sm.convert_material(tree(), blender_version=version)
            self.assertEqual(p.get("microfacets"), expected, version)

    def test_diffuse_roughness_is_oren_nayar(self):
        def b(t):
            d = _diffuse(t, (0.5, 0.5, 0.5))
            d.inp("Roughness").default_value = 0.5
            return d.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "diffuse")
        self.assertEqual(p["roughness"], 0.5)
        self.assertIsNone(w)

    def test_glossy(self):
        def b(t):
            g = t.new("ShaderNodeBsdfGlossy", "Shiny", distribution="GGX")
            g.inp("Color").default_value = [0.9, 0.8, 0.7, 1.0]
            g.inp("Roughness").default_value = 0.3
            return g.out()
        p, w = material_with(b)
        self.assertEqual(p, {"type": "glossy", "color": p["color"], "roughness": p["roughness"],
                             "distribution": "GGX"})
        self.assertTrue(close(p["color"], (0.9, 0.8, 0.7)))
        self.assertTrue(close(p["roughness"], 0.3))
        self.assertIsNone(w)

    def test_glossy_beckmann_warns(self):
        p, w = material_with(lambda t: t.new("ShaderNodeBsdfGlossy", "B", distribution="BECKMANN").out())
        self.assertEqual(p["type"], "glossy")
        self.assertIn("Glossy BSDF 'B'", w)
        self.assertIn("BECKMANN", w)

    def test_anisotropic(self):
        def b(t):
            a = t.new("ShaderNodeBsdfAnisotropic", "Aniso", distribution="GGX")
            return a.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "glossy")
        self.assertEqual(p["anisotropy"], 0.5)  # Blender 3.4's default
        self.assertIsNone(w)

    def test_bsdfs_keep_their_engine_type(self):
        for idname, kind in (("ShaderNodeBsdfGlass", "glass"), ("ShaderNodeBsdfRefraction", "refraction"),
                             ("ShaderNodeBsdfTranslucent", "translucent"),
                             ("ShaderNodeBsdfTransparent", "transparent")):
            with self.subTest(idname):
                p, w = material_with(lambda t: t.new(idname, "X", distribution="GGX").out())
                self.assertEqual(p["type"], kind)
                self.assertIsNone(w)

    def test_emission(self):
        def b(t):
            e = t.new("ShaderNodeEmission", "Glow")
            e.inp("Color").default_value = [1.0, 0.5, 0.25, 1.0]
            e.inp("Strength").default_value = 4.0
            return e.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "emission")
        radiance = [c * p["strength"] for c in p["color"]]
        self.assertTrue(close(radiance, (4.0, 2.0, 1.0)))
        self.assertIsNone(w)

    def test_principled_default_is_principled(self):
        p, w = material_with(lambda t: t.new("ShaderNodeBsdfPrincipled", "Principled BSDF").out())
        self.assertEqual(p["type"], "principled")
        self.assertTrue(close(p["base_color"], (0.8, 0.8, 0.8)))
        self.assertEqual((p["specular"], p["roughness"], p["ior"]), (0.5, 0.5, 1.45))
        self.assertIsNone(w)

    def test_principled_metal(self):
        def b(t):
            n = t.new("ShaderNodeBsdfPrincipled", "P")
            n.inp("Base Color").default_value = [0.9, 0.6, 0.2, 1.0]
            n.inp("Metallic").default_value = 1.0
            n.inp("Roughness").default_value = 0.2
            return n.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "principled")
        self.assertTrue(close(p["base_color"], (0.9, 0.6, 0.2)))
        self.assertEqual(p["metallic"], 1.0)
        self.assertTrue(close(p["roughness"], 0.2))
        self.assertIsNone(w)

    def test_principled_emission_4x_socket_name(self):
        """Blender 4.x calls the socket 'Emission Color' and defaults it to white."""
        def b(t):
            n = t.new("ShaderNodeBsdfPrincipled", "P")
            n.inp("Emission").identifier = "Emission Color"
            n.inp("Emission Color").name = "Emission Color"
            n.inp("Emission Color").default_value = [1.0, 1.0, 1.0, 1.0]
            n.inp("Emission Strength").default_value = 10.0
            n.inp("Specular").default_value = 0.0
            return n.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "principled")
        self.assertTrue(close(p["base_color"], (0.8, 0.8, 0.8)))
        self.assertTrue(close([c * p["emission_strength"] for c in p["emission"]], (10.0, 10.0, 10.0)))
        self.assertIsNone(w)


    def test_principled_4x_subsurface_takes_the_base_colour(self):
        """Blender 4.x has no Subsurface Color: its subsurface is coloured by the base colour."""
        def b(t):
            n = t.new("ShaderNodeBsdfPrincipled", "P")
            n.inp("Subsurface").identifier = n.inp("Subsurface").name = "Subsurface Weight"
            n.inputs = [s for s in n.inputs if s.name != "Subsurface Color"]
            n.inp("Subsurface Weight").default_value = 1.0
            n.inp("Base Color").default_value = [0.9, 0.1, 0.1, 1.0]
            return n.out()
        p, w = material_with(b)
        self.assertTrue(close(p["subsurface_color"], (0.9, 0.1, 0.1)))
        self.assertIn("subsurface approximated by diffuse", w)


    def _principled_4x(self, t, **values):
        """A Principled stand-in with Blender 4.x's socket names (and a few 4.x-only sockets)."""
        n = t.new("ShaderNodeBsdfPrincipled", "P")
        for old, new in (("Specular", "Specular IOR Level"), ("Clearcoat", "Coat Weight"), ("Sheen", "Sheen Weight")):
            n.inp(old).identifier = n.inp(old).name = new
        n.inputs += [Socket(n, k, k, t_, d, False) for k, t_, d in (("Coat IOR", "VALUE", 1.5),
                                                                   ("Coat Tint", "RGBA", (1.0, 1.0, 1.0, 1.0)),
                                                                   ("Sheen Roughness", "VALUE", 0.5))]
        n.inp("IOR").default_value = 1.5  # 4.x's default
        for k, v in values.items():
            n.inp(k).default_value = v
        return n

    def test_principled_4x_specular_follows_the_ior(self):
        """4.x reflects F0(IOR) x 2 x Specular IOR Level: the engine's specular is f0 / 0.08."""
        p, w = material_with(lambda t: self._principled_4x(t).out())
        self.assertTrue(close(p["specular"], 0.5))  # IOR 1.5, level 0.5: f0 0.04, as 3.4's default
        self.assertEqual(p["layering"], "energy_conserving")
        self.assertIsNone(w)
        p, w = material_with(lambda t: self._principled_4x(t, IOR=1.33, **{"Specular IOR Level": 0.8}).out())
        self.assertTrue(close(p["specular"], 0.8 * 25 * (0.33 / 2.33) ** 2))
        self.assertIsNone(w)

    def test_principled_4x_ignored_inputs_warn(self):
        p, w = material_with(lambda t: self._principled_4x(
            t, **{"Coat Weight": 0.5, "Coat IOR": 1.8, "Sheen Weight": 1.0, "Sheen Roughness": 0.2}).out())
        self.assertIn("Coat IOR ignored", w)
        self.assertIn("Sheen Roughness ignored", w)
        self.assertNotIn("Coat Tint", w)  # at its default


def _diffuse(t, color, name="D"):
    d = t.new("ShaderNodeBsdfDiffuse", name)
    d.inp("Color").default_value = list(color) + [1.0]
    return d


class TestCombinators(unittest.TestCase):
    def test_mix_two_diffuse_is_exact(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            m.inp("Fac").default_value = 0.25
            t.link(_diffuse(t, (1, 0, 0), "A").out(), m.inp("Shader"))
            t.link(_diffuse(t, (0, 0, 1), "B").out(), m.inp("Shader_001"))
            return m.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.75, 0.0, 0.25)))
        self.assertIsNone(w)

    def _mix_by(self, build_fac):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            t.link(build_fac(t), m.inp("Fac"))
            t.link(_diffuse(t, (0.8, 0.2, 0.1), "D").out(), m.inp("Shader"))
            t.link(t.new("ShaderNodeBsdfGlossy", "G", distribution="GGX").out(), m.inp("Shader_001"))
            return m.out()
        return material_with(b)

    @staticmethod
    def _geometry_into_color(output):
        """The warning of a Diffuse BSDF whose Color is Geometry's `output`."""
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(t.new("ShaderNodeNewGeometry", "G").out(output), d.inp("Color"))
            return d.out()
        return material_with(b)[1]

    def test_fresnel_and_layer_weight_factors_go_to_the_engine(self):
        # Straight into a Mix Shader's Fac: the engine evaluates them per pair of directions.
        def fresnel(t):
            f = t.new("ShaderNodeFresnel", "F")
            f.inp("IOR").default_value = 1.6
            return f.out()
        p, w = self._mix_by(fresnel)
        self.assertEqual(p["fac"], {"node": "fresnel", "ior": 1.6})
        self.assertEqual((p["shader1"]["type"], p["shader2"]["type"]), ("diffuse", "glossy"))
        self.assertIsNone(w)
        for out, engine_out in (("Fresnel", "fresnel"), ("Facing", "facing")):
            with self.subTest(out):
                def layer(t, out=out):
                    n = t.new("ShaderNodeLayerWeight", "LW")
                    n.inp("Blend").default_value = 0.3
                    return n.out(out)
                p, w = self._mix_by(layer)
                self.assertEqual(p["fac"]["node"], "layer_weight")
                self.assertEqual(p["fac"]["output"], engine_out)
                self.assertAlmostEqual(p["fac"]["blend"], 0.3, places=6)
                self.assertIsNone(w)
        # A textured IOR goes along as a texture node.
        def textured(t):
            f = t.new("ShaderNodeFresnel", "F")
            t.link(t.new("ShaderNodeTexChecker", "Chk").out("Fac"), f.inp("IOR"))
            return f.out()
        p, w = self._mix_by(textured)
        self.assertEqual(p["fac"]["ior"]["node"], "checker")
        # A linked Normal is approximated by the interpolated normal, named.
        def with_normal(t):
            f = t.new("ShaderNodeFresnel", "F")
            t.link(t.new("ShaderNodeNewGeometry", "G").out("Normal"), f.inp("Normal"))
            return f.out()
        p, w = self._mix_by(with_normal)
        self.assertEqual(p["fac"]["node"], "fresnel")
        self.assertIn("Normal input", w)

    def test_wavelength_goes_to_the_engine(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            w = t.new("ShaderNodeWavelength", "W")
            w.inp("Wavelength").default_value = 532.0
            t.link(w.out(), d.inp("Color"))
            return d.out()
        p, w = material_with(b)
        self.assertEqual(p["color"], {"node": "wavelength", "wavelength": 532.0})
        self.assertIsNone(w)

    def test_backfacing_factor_makes_a_two_sided_material(self):
        p, w = self._mix_by(lambda t: t.new("ShaderNodeNewGeometry", "G").out("Backfacing"))
        self.assertEqual(p["fac"], {"node": "backfacing"})
        self.assertIsNone(w)
        # Into a colour: the front's 0, named.
        self.assertIn("Backfacing", self._geometry_into_color("Backfacing"))

    def test_incoming_dot_normal_is_a_view_factor(self):
        # Vector Math's Dot Product of Geometry > Incoming and Normal (either order), through a
        # Math node: |cos| = 1 - Layer Weight's Facing at blend 0.5, the Math baked over it.
        for first, second in (("Incoming", "Normal"), ("Normal", "Incoming"), ("Incoming", "True Normal")):
            with self.subTest(first=first, second=second):
                def dot(t, first=first, second=second):
                    g = t.new("ShaderNodeNewGeometry", "G")
                    d = t.new("ShaderNodeVectorMath", "Dot", operation="DOT_PRODUCT")
                    t.link(g.out(first), d.inp("Vector"))
                    t.link(g.out(second), d.inp("Vector_001"))
                    m = t.new("ShaderNodeMath", "Square", operation="POWER", use_clamp=False)
                    t.link(d.out("Value"), m.inp("Value"))
                    m.inp("Value_001").default_value = 2.0
                    return m.out()
                p, w = self._mix_by(dot)
                fac = p["fac"]
                self.assertEqual((fac["node"], fac["output"], fac["blend"]), ("layer_weight", "facing", 0.5))
                table = fac["table"]
                self.assertEqual(len(table), 256)
                for i in (0, 51, 255):  # the table at facing y: (1 - y)^2
                    self.assertAlmostEqual(table[i], (1.0 - i / 255.0) ** 2, places=5)
                if "True Normal" in (first, second):
                    self.assertIn("True Normal approximated", w)
                else:
                    self.assertIsNone(w)
        # Straight into the Fac (no node between): the table is the cosine itself.
        def bare(t):
            g = t.new("ShaderNodeNewGeometry", "G")
            d = t.new("ShaderNodeVectorMath", "Dot", operation="DOT_PRODUCT")
            t.link(g.out("Incoming"), d.inp("Vector"))
            t.link(g.out("Normal"), d.inp("Vector_001"))
            return d.out("Value")
        p, w = self._mix_by(bare)
        self.assertAlmostEqual(p["fac"]["table"][64], 1.0 - 64 / 255.0, places=5)
        self.assertIsNone(w)
        # Incoming elsewhere (a colour) stays a constant, named.
        self.assertIn("Incoming", self._geometry_into_color("Incoming"))

    def test_view_factor_through_constant_nodes_is_baked(self):
        # Fresnel through a Math node of constant settings: the node's function of the
        # factor, baked over [0, 1] for the engine.
        def through_math(t):
            m = t.new("ShaderNodeMath", "Pow", operation="POWER", use_clamp=False)
            t.link(t.new("ShaderNodeFresnel", "F").out(), m.inputs[0])
            m.inputs[1].default_value = 2.0
            return m.out()
        p, w = self._mix_by(through_math)
        self.assertIsNone(w)
        self.assertEqual(p["fac"]["node"], "fresnel")
        table = p["fac"]["table"]
        self.assertEqual(len(table), 256)
        for i in (0, 17, 128, 255):
            self.assertAlmostEqual(table[i], (i / 255.0) ** 2, places=5)

    def test_view_factors_elsewhere_are_their_mean(self):
        # Into a colour, or mixed with a texture on the way to the Fac: the cosine-weighted mean,
        # with a warning naming the node.
        def into_color(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(t.new("ShaderNodeFresnel", "F").out(), d.inp("Color"))
            return d.out()
        p, w = material_with(into_color)
        mean = sm.nodes.inputs.view_factor_mean("fresnel", 1.45)
        self.assertTrue(0.05 < mean < 0.15, mean)
        self.assertTrue(close(p["color"], (mean,) * 3), p)
        self.assertIn("Fresnel 'F'", w)
        self.assertIn("viewing direction", w)
        def with_texture(t):
            m = t.new("ShaderNodeMath", "Mul", operation="MULTIPLY", use_clamp=False)
            t.link(t.new("ShaderNodeFresnel", "F").out(), m.inputs[0])
            t.link(t.new("ShaderNodeTexChecker", "Chk").out("Fac"), m.inputs[1])
            return m.out()
        p, w = self._mix_by(with_texture)
        self.assertIn("Fresnel 'F'", w)
        self.assertNotIn("table", str(p["fac"]))
        # Layer Weight's Facing at blend 0.5: 1 - cos, whose cosine-weighted mean is 1/3.
        self.assertAlmostEqual(sm.nodes.inputs.view_factor_mean("layer_weight", 0.5, "facing"), 1.0 / 3.0, places=4)

    def test_add_two_diffuse_sums(self):
        def b(t):
            a = t.new("ShaderNodeAddShader", "Add")
            t.link(_diffuse(t, (0.25, 0.0, 0.0), "A").out(), a.inp("Shader"))
            t.link(_diffuse(t, (0.0, 0.5, 0.0), "B").out(), a.inp("Shader_001"))
            return a.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.25, 0.5, 0.0)))

    def test_mix_diffuse_emission_is_emissive_diffuse(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            m.inp("Fac").default_value = 0.5
            e = t.new("ShaderNodeEmission", "Lamp")
            e.inp("Strength").default_value = 10.0
            t.link(_diffuse(t, (0.5, 0.5, 0.5), "Matte").out(), m.inp("Shader"))
            t.link(e.out(), m.inp("Shader_001"))
            return m.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "diffuse")
        self.assertTrue(close(p["color"], (0.25, 0.25, 0.25)))
        self.assertTrue(close([c * p["emission_strength"] for c in p["emission"]], (5.0, 5.0, 5.0)))
        self.assertIsNone(w)

    def test_mix_diffuse_glossy_is_a_mix(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            m.inp("Fac").default_value = 0.3
            g = t.new("ShaderNodeBsdfGlossy", "Coat", distribution="GGX")
            t.link(_diffuse(t, (0.5, 0.5, 0.5), "Matte").out(), m.inp("Shader"))
            t.link(g.out(), m.inp("Shader_001"))
            return m.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "mix")
        self.assertTrue(close(p["fac"], 0.3))
        self.assertEqual((p["shader1"]["type"], p["shader2"]["type"]), ("diffuse", "glossy"))
        self.assertIsNone(w)

    def test_mix_with_linked_fac_is_evaluated(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            v = t.new("ShaderNodeValue", "V")
            v.out().default_value = 1.0
            t.link(v.out(), m.inp("Fac"))
            t.link(_diffuse(t, (1, 0, 0), "A").out(), m.inp("Shader"))
            t.link(_diffuse(t, (0, 1, 0), "B").out(), m.inp("Shader_001"))
            return m.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0, 1, 0)))
        self.assertIsNone(w)

    def test_color_into_shader_socket_is_emission(self):
        def b(t):
            rgb = t.new("ShaderNodeRGB", "RGB")
            rgb.out().default_value = [0.5, 0.25, 1.0, 1.0]
            return rgb.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "emission")
        self.assertTrue(close([c * p["strength"] for c in p["color"]], (0.5, 0.25, 1.0)))

    def test_no_surface_is_black(self):
        p, w = material_with(lambda t: None)
        self.assertEqual(p, {"type": "diffuse", "color": [0.0, 0.0, 0.0]})
        self.assertIsNone(w)

    def test_holdout_lowers_to_holdout(self):
        p, w = material_with(lambda t: t.new("ShaderNodeHoldout", "H").out())
        self.assertEqual(p, {"type": "holdout"})
        self.assertIsNone(w)


class TestValues(unittest.TestCase):
    def _color_into_diffuse(self, build):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(build(t), d.inp("Color"))
            return d.out()
        return material_with(b)

    def test_rgb_and_value(self):
        def b(t):
            rgb = t.new("ShaderNodeRGB", "RGB")
            rgb.out().default_value = [0.1, 0.2, 0.3, 1.0]
            return rgb.out()
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.1, 0.2, 0.3)))
        self.assertIsNone(w)

    def test_value_to_color_broadcasts(self):
        def b(t):
            v = t.new("ShaderNodeValue", "V")
            v.out().default_value = 0.3
            return v.out()
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.3, 0.3, 0.3)))

    def test_mix_rgb_modes(self):
        cases = {"MIX": (0.5, 0.35, 0.3), "MULTIPLY": (0.2 * (0.5 + 0.5 * 0.8), 0.5 * (0.5 + 0.5 * 0.2), 0.3 * (0.5 + 0.5 * 0.3)),
                 "ADD": (0.2 + 0.4, 0.5 + 0.1, 0.3 + 0.15), "SUBTRACT": (0.0, 0.5 - 0.1, 0.3 - 0.15)}  # the engine takes no negative colour
        for mode, expect in cases.items():
            with self.subTest(mode):
                def b(t):
                    m = t.new("ShaderNodeMixRGB", "MixRGB", blend_type=mode, use_clamp=False)
                    m.inp("Fac").default_value = 0.5
                    m.inp("Color1").default_value = [0.2, 0.5, 0.3, 1.0]
                    m.inp("Color2").default_value = [0.8, 0.2, 0.3, 1.0]
                    return m.out()
                p, w = self._color_into_diffuse(b)
                self.assertTrue(close(p["color"], expect), (mode, p["color"], expect))
                self.assertIsNone(w)

    def test_mix_node_34_rgba_and_float(self):
        def b(t):
            m = t.new("ShaderNodeMix", "Mix", data_type="RGBA", blend_type="MIX", clamp_factor=True,
                      clamp_result=False, factor_mode="UNIFORM")
            f = t.new("ShaderNodeMix", "MixF", data_type="FLOAT", clamp_factor=True, clamp_result=False,
                      factor_mode="UNIFORM")
            f.inp("Factor_Float").default_value = 0.5
            f.inp("A_Float").default_value = 0.0
            f.inp("B_Float").default_value = 0.5  # -> 0.25
            t.link(f.out("Result_Float"), m.inp("Factor_Float"))
            m.inp("A_Color").default_value = [1.0, 1.0, 1.0, 1.0]
            m.inp("B_Color").default_value = [0.0, 0.0, 0.0, 1.0]
            return m.out("Result_Color")
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.75, 0.75, 0.75)))
        self.assertIsNone(w)

    def test_math_chain(self):
        def b(t):
            m1 = t.new("ShaderNodeMath", "Mul", operation="MULTIPLY", use_clamp=False)
            m1.inputs[0].default_value = 0.5
            m1.inputs[1].default_value = 0.5
            m2 = t.new("ShaderNodeMath", "Pow", operation="POWER", use_clamp=False)
            t.link(m1.out(), m2.inputs[0])
            m2.inputs[1].default_value = 0.5  # sqrt(0.25) = 0.5
            m3 = t.new("ShaderNodeMath", "Div0", operation="DIVIDE", use_clamp=True)
            t.link(m2.out(), m3.inputs[0])
            m3.inputs[1].default_value = 0.0  # safe divide -> 0
            m4 = t.new("ShaderNodeMath", "Add", operation="ADD", use_clamp=True)
            t.link(m3.out(), m4.inputs[0])
            t.link(m2.out(), m4.inputs[1])
            return m4.out()
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.5, 0.5, 0.5)))
        self.assertIsNone(w)

    def test_every_math_operation_evaluates(self):
        from shaders_map.nodes.converter import MATH
        for op in MATH:
            with self.subTest(op):
                def b(t):
                    m = t.new("ShaderNodeMath", "M", operation=op, use_clamp=False)
                    return m.out()
                p, w = self._color_into_diffuse(b)
                self.assertEqual(len(p["color"]), 3)
                self.assertIsNone(w)

    def test_color_ramp(self):
        def b(t):
            r = t.new("ShaderNodeValToRGB", "Ramp",
                      color_ramp=Ramp([(0.0, (0, 0, 0, 1)), (1.0, (1.0, 0.5, 0.0, 1))]))
            r.inp("Fac").default_value = 0.25
            return r.out("Color")
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.25, 0.125, 0.0)))
        self.assertIsNone(w)

    def test_color_ramp_constant(self):
        def b(t):
            r = t.new("ShaderNodeValToRGB", "Ramp",
                      color_ramp=Ramp([(0.0, (0.1, 0.1, 0.1, 1)), (0.5, (0.9, 0.9, 0.9, 1))], "CONSTANT"))
            r.inp("Fac").default_value = 0.4
            return r.out("Color")
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.1, 0.1, 0.1)))

    def test_color_ramp_baked_as_cycles(self):
        # With Blender's ColorRamp.evaluate the ramp is baked to 256 entries as Cycles bakes
        # it: B-spline (or any mode) without a warning, and a constant input folds to the
        # table's linear lookup.
        fn = lambda x: (x * x, 1.0 - x, 0.5, 1.0)
        def b(t):
            r = t.new("ShaderNodeValToRGB", "Ramp", color_ramp=EvaluatingRamp([(0.0, (0, 0, 0, 1)), (1.0, (1, 1, 1, 1))], fn))
            r.inp("Fac").default_value = 0.3
            return r.out("Color")
        p, w = self._color_into_diffuse(b)
        f = 0.3 * 255
        i = int(f)
        lo, hi = fn(i / 255), fn((i + 1) / 255)
        expect = tuple((1 - (f - i)) * a + (f - i) * c for a, c in zip(lo[:3], hi[:3]))
        self.assertTrue(close(p["color"], expect), (p["color"], expect))
        self.assertIsNone(w)

    def test_curves_are_baked_tables(self):
        square = lambda x: x * x
        rgb = CurveMapping([Curve([(0, 0), (1, 1)], square), Curve([(0, 0), (1, 1)], lambda x: x),
                            Curve([(0, 0), (1, 1)], lambda x: 1 - x), Curve([(0, 0), (2, 1)], lambda x: x / 2)])
        vec = CurveMapping([Curve([(-1, -1), (1, 1)], square)] * 3, extend="HORIZONTAL")
        flt = CurveMapping([Curve([(0, 0), (1, 1)], square)])
        cases = (("ShaderNodeRGBCurve", rgb, "Color", "rgb_curves", "color"),
                 ("ShaderNodeVectorCurve", vec, "Vector", "rgb_curves", "color"),
                 ("ShaderNodeFloatCurve", flt, "Value", "float_curve", "value"))
        for idname, mapping, out, node, value_key in cases:
            with self.subTest(idname):
                def b(t):
                    c = t.new(idname, "Curves", mapping=mapping)
                    t.link(t.new("ShaderNodeTexNoise", "N").out("Color" if out != "Value" else "Fac"), c.inputs[1])
                    return c.out(out)
                p, w = self._color_into_diffuse(b)
                c = p["color"] if p["color"]["node"] != "rgb_to_bw" else p["color"]["color"]
                self.assertEqual(c["node"], node)
                self.assertEqual(len(c["table"]), 256)
                self.assertEqual(c[value_key]["node"], "noise")
                self.assertIsNone(w)
        # The RGB table is the colour curve of the combined (C) curve over the widest range, 0..2.
        p, _ = self._color_into_diffuse(lambda t: t.new("ShaderNodeRGBCurve", "C", mapping=rgb).out("Color"))
        # (a constant input folds: white through C (x / 2) then R (x^2), G (x), B (1 - x))
        self.assertTrue(close(p["color"], (0.25, 0.5, 0.5)), p["color"])
        def b(t):
            c = t.new("ShaderNodeVectorCurve", "V", mapping=vec)
            t.link(t.new("ShaderNodeTexNoise", "N").out("Color"), c.inp("Vector"))
            return c.out("Vector")
        p, _ = self._color_into_diffuse(b)
        self.assertEqual((p["color"]["min_x"], p["color"]["max_x"], p["color"]["extrapolate"]), (-1.0, 1.0, False))

    def test_map_range_every_interpolation_folds_as_cycles(self):
        # (value, from, to, steps, type, clamp) -> Cycles' result (svm_node_map_range, and the
        # Clamp it adds to linear and stepped).
        cases = ((0.3, (0, 1), (0, 10), 4, "LINEAR", True, 3.0),
                 (1.5, (0, 1), (0, 10), 4, "LINEAR", True, 10.0),
                 (1.5, (0, 1), (0, 10), 4, "LINEAR", False, 15.0),
                 (0.3, (0, 1), (0, 1), 4, "STEPPED", True, 0.25),
                 (0.3, (0, 1), (0, 1), 4, "SMOOTHSTEP", True, 0.216),
                 (0.3, (1, 0), (0, 1), 4, "SMOOTHSTEP", True, 0.784),
                 (0.3, (0, 1), (0, 1), 4, "SMOOTHERSTEP", True, 0.16308),
                 (0.3, (0.5, 0.5), (0, 1), 4, "LINEAR", True, 0.0))
        for v, (a, b), (c, d), steps, kind, clamp, expect in cases:
            with self.subTest(kind=kind, v=v, a=a, b=b, clamp=clamp):
                def build(t):
                    n = t.new("ShaderNodeMapRange", "R", data_type="FLOAT", interpolation_type=kind, clamp=clamp)
                    for name, x in (("Value", v), ("From Min", a), ("From Max", b), ("To Min", c), ("To Max", d),
                                    ("Steps", steps)):
                        n.inp(name).default_value = x
                    return n.out("Result")
                p, w = self._color_into_diffuse(build)
                self.assertAlmostEqual(p["color"][0], expect, places=5)
                self.assertIsNone(w)

    def test_map_range_and_vector_math_become_engine_nodes(self):
        def build(t):
            noise = t.new("ShaderNodeTexNoise", "N")
            r = t.new("ShaderNodeMapRange", "R", data_type="FLOAT_VECTOR", interpolation_type="STEPPED", clamp=True)
            t.link(noise.out("Color"), r.inp("Vector"))
            r.inp("Steps_FLOAT3").default_value = (2.0, 3.0, 4.0)
            m = t.new("ShaderNodeVectorMath", "L", operation="LENGTH")
            t.link(r.out("Vector"), m.inputs[0])
            return m.out("Value")
        p, w = self._color_into_diffuse(build)
        c = p["color"] if p["color"]["node"] != "rgb_to_bw" else p["color"]["color"]
        self.assertEqual((c["node"], c["operation"], c["output"]), ("vector_math", "LENGTH", "value"))
        r = c["vector1"]
        self.assertEqual((r["node"], r["data_type"], r["interpolation_type"]), ("map_range", "FLOAT_VECTOR", "STEPPED"))
        self.assertEqual(r["steps"], [2.0, 3.0, 4.0])
        self.assertEqual(r["value"]["node"], "noise")
        self.assertIsNone(w)

    def test_vector_math_folds_every_operation(self):
        a, b, c = (0.6, -0.8, 2.5), (0.0, 2.0, 0.5), (1.0, 1.0, -1.0)
        expect = {"CROSS_PRODUCT": (-5.4, -0.3, 1.2), "PROJECT": (0.0, -0.1647, -0.0412),
                  "REFLECT": (0.6, -0.4706, 2.5824), "FACEFORWARD": (-0.6, 0.8, -2.5), "DOT_PRODUCT": (-0.35,) * 3,
                  "DISTANCE": (3.4928,) * 3, "LENGTH": (2.6926,) * 3, "SNAP": (0.0, -2.0, 2.5),
                  "WRAP": (0.6, 1.2, -0.5), "MULTIPLY_ADD": (1.0, -0.6, 0.25), "MODULO": (0.0, -0.8, 0.0)}
        for op, value in expect.items():
            with self.subTest(op):
                def build(t):
                    n = t.new("ShaderNodeVectorMath", "V", operation=op)
                    for s, x in zip(n.inputs[:3], (a, b, c)):
                        s.default_value = x
                    return n.out("Value" if op in ("DOT_PRODUCT", "DISTANCE", "LENGTH") else "Vector")
                p, w = self._color_into_diffuse(build)
                # (a colour input holds no negative part: Cycles clamps those, and so does the export)
                self.assertTrue(all(abs(max(y, 0.0) - x) < 1e-4 for x, y in zip(p["color"], value)), (op, p["color"]))

    def test_separate_and_combine_in_hsv_and_hsl(self):
        # Converted as Cycles' rgb_to_hsv / rgb_to_hsl (and back): no warning, exact folds.
        cases = (("HSV", 0, 1.0 / 6.0 * (0.6 / 0.8)), ("HSV", 1, 0.8), ("HSV", 2, 1.0),
                 ("HSL", 1, 0.8 / (2.0 - 1.2)), ("HSL", 2, 0.6))
        for mode, index, expect in cases:
            with self.subTest(mode=mode, index=index):
                def b(t):
                    rgb = t.new("ShaderNodeRGB", "RGB")
                    rgb.out().default_value = [1.0, 0.8, 0.2, 1.0]
                    sep = t.new("ShaderNodeSeparateColor", "Sep", mode=mode)
                    t.link(rgb.out(), sep.inp("Color"))
                    return sep.outputs[index]
                p, w = self._color_into_diffuse(b)
                self.assertAlmostEqual(p["color"][0], expect, places=5)
                self.assertIsNone(w)
        for mode in ("HSV", "HSL"):
            with self.subTest(round_trip=mode):
                def b(t):
                    rgb = t.new("ShaderNodeRGB", "RGB")
                    rgb.out().default_value = [0.3, 0.9, 0.5, 1.0]
                    sep = t.new("ShaderNodeSeparateColor", "Sep", mode=mode)
                    com = t.new("ShaderNodeCombineColor", "Com", mode=mode)
                    t.link(rgb.out(), sep.inp("Color"))
                    for k in range(3):
                        t.link(sep.outputs[k], com.inputs[k])
                    return com.out()
                p, w = self._color_into_diffuse(b)
                self.assertTrue(close(p["color"], (0.3, 0.9, 0.5)), p["color"])
        def b(t):  # a varying colour: the engine's color_space node
            sep = t.new("ShaderNodeSeparateColor", "Sep", mode="HSL")
            t.link(t.new("ShaderNodeTexNoise", "N").out("Color"), sep.inp("Color"))
            return sep.outputs[0]
        p, w = self._color_into_diffuse(b)
        c = p["color"]["color"] if p["color"]["node"] == "rgb_to_bw" else p["color"]
        self.assertEqual(c["node"], "separate_rgb")
        self.assertEqual((c["color"]["node"], c["color"]["convert"]), ("color_space", "RGB_TO_HSL"))

    def test_geometry_and_coordinate_normals(self):
        # Geometry's Position / Normal / True Normal are world-space engine coordinates; Texture
        # Coordinate's Normal the object-space normal; the view-dependent outputs a constant, named.
        for out, engine_out in (("Position", "position"), ("Normal", "normal"), ("True Normal", "true_normal")):
            with self.subTest(out):
                p, w = self._color_into_diffuse(lambda t: t.new("ShaderNodeNewGeometry", "G").out(out))
                self.assertEqual((p["color"]["node"], p["color"]["output"]), ("texture_coordinate", engine_out))
                self.assertIsNone(w)
        p, w = self._color_into_diffuse(lambda t: t.new("ShaderNodeTexCoord", "T").out("Normal"))
        self.assertEqual(p["color"]["output"], "object_normal")
        p, w = self._color_into_diffuse(lambda t: t.new("ShaderNodeNewGeometry", "G").out("Incoming"))
        self.assertIn("Incoming", w)

    def test_invert(self):
        def b(t):
            n = t.new("ShaderNodeInvert", "Inv")
            n.inp("Color").default_value = [0.2, 0.4, 1.0, 1.0]
            return n.out()
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.8, 0.6, 0.0)))

    def test_color_to_float_is_luminance(self):
        def b(t):
            rgb = t.new("ShaderNodeRGB", "RGB")
            rgb.out().default_value = [1.0, 0.0, 0.0, 1.0]
            m = t.new("ShaderNodeMath", "Add", operation="ADD", use_clamp=False)
            t.link(rgb.out(), m.inputs[0])
            m.inputs[1].default_value = 0.0
            return m.out()
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.2126,) * 3))

    def test_image_texture_average_and_mapping_chain(self):
        img = Image("wood.png", average=((0.25, 0.5, 0.75), 1.0))

        def b(t):
            tc = t.new("ShaderNodeTexCoord", "TexCoord")
            mp = t.new("ShaderNodeMapping", "Mapping", vector_type="POINT")
            uv = t.new("ShaderNodeUVMap", "UVMap", uv_map="UVMap")
            tex = t.new("ShaderNodeTexImage", "Wood", image=img)
            t.link(tc.out("UV"), mp.inp("Vector"))
            t.link(mp.out(), tex.inp("Vector"))
            tex2 = t.new("ShaderNodeTexImage", "Wood2", image=img)
            t.link(uv.out(), tex2.inp("Vector"))
            mix = t.new("ShaderNodeMixRGB", "MixRGB", blend_type="MIX", use_clamp=False)
            t.link(tex.out("Color"), mix.inp("Color1"))
            t.link(tex2.out("Color"), mix.inp("Color2"))
            return mix.out()
        p, w = self._color_into_diffuse(b)
        self.assertTrue(close(p["color"], (0.25, 0.5, 0.75)))
        self.assertIn("Image Texture 'Wood'", w)
        self.assertIn("Image Texture 'Wood2'", w)
        self.assertNotIn("Mapping", w)
        self.assertNotIn("TexCoord", w)

    def test_missing_image_is_magenta_and_named(self):
        img = Image("gone.png", filepath="/nope/gone.png", missing=True)
        p, w = self._color_into_diffuse(lambda t: t.new("ShaderNodeTexImage", "Tex", image=img).out("Color"))
        self.assertTrue(close(p["color"], (1.0, 0.0, 1.0)))
        self.assertIn("/nope/gone.png", w)
        self.assertIn("not found", w)

    def test_image_without_callback_is_grey(self):
        img = Image("a.png")
        p, w = material_with(lambda t: _tex_diffuse(t, img), image_average_fn=None)
        self.assertTrue(close(p["color"], (0.5, 0.5, 0.5)))
        self.assertIn("Image Texture 'Tex'", w)

    def test_procedural_textures_are_texture_nodes(self):
        for idname, node in (("ShaderNodeTexChecker", "checker"), ("ShaderNodeTexNoise", "noise"),
                             ("ShaderNodeTexGradient", "gradient")):
            with self.subTest(idname):
                p, w = self._color_into_diffuse(lambda t: t.new(idname, "Tex").out("Color"))
                self.assertEqual(p["color"]["node"], node)
                self.assertIsNone(w)  # the noise is Blender's (3D) pattern

    def test_noise_distortion_and_dimensions(self):
        def noise(dims, distortion):
            def b(t):
                n = t.new("ShaderNodeTexNoise", "N", noise_dimensions=dims)
                n.inp("Distortion").default_value = distortion
                return n.out("Fac")
            return self._color_into_diffuse(b)
        p, w = noise("3D", 0.7)
        self.assertAlmostEqual(p["color"]["distortion"], 0.7, places=6)
        self.assertIsNone(w)
        p, w = noise("3D", 0.0)
        self.assertNotIn("distortion", p["color"])
        for dims in ("1D", "2D", "4D"):
            p, w = noise(dims, 0.0)
            self.assertIsNone(w)
            self.assertEqual(p["color"]["dimensions"], dims)
            self.assertEqual("w" in p["color"], dims != "2D")

    def test_blenders_procedural_textures_are_engine_nodes(self):
        # Each becomes the engine's node of Blender's pattern (no warning), with its inputs,
        # properties and the socket used.
        cases = (
            ("ShaderNodeTexVoronoi", "Color", {"voronoi_dimensions": "4D", "feature": "SMOOTH_F1", "distance": "MINKOWSKI"},
             "voronoi", {"dimensions": "4D", "feature": "SMOOTH_F1", "distance": "MINKOWSKI", "output": "color",
                         "scale": 5.0, "smoothness": 1.0, "exponent": 0.5, "randomness": 1.0, "w": 0.0}),
            ("ShaderNodeTexMusgrave", "Fac", {"musgrave_dimensions": "2D", "musgrave_type": "RIDGED_MULTIFRACTAL"},
             "musgrave", {"dimensions": "2D", "musgrave_type": "RIDGED_MULTIFRACTAL", "detail": 2.0, "dimension": 2.0,
                          "lacunarity": 2.0, "offset": 0.0, "gain": 1.0}),
            ("ShaderNodeTexWave", "Fac", {"wave_type": "RINGS", "bands_direction": "Y", "rings_direction": "SPHERICAL",
                                          "wave_profile": "TRI"},
             "wave", {"wave_type": "RINGS", "direction": "SPHERICAL", "profile": "TRI", "output": "fac",
                      "detail_scale": 1.0, "phase": 0.0}),
            ("ShaderNodeTexMagic", "Color", {"turbulence_depth": 5}, "magic", {"depth": 5, "output": "color",
                                                                           "distortion": 1.0}),
            ("ShaderNodeTexBrick", "Color", {"offset": 0.25, "offset_frequency": 3, "squash": 0.5, "squash_frequency": 2},
             "brick", {"offset": 0.25, "offset_frequency": 3, "squash": 0.5, "squash_frequency": 2, "output": "color",
                       "mortar_smooth": 0.1, "row_height": 0.25}),
            ("ShaderNodeTexWhiteNoise", "Color", {"noise_dimensions": "1D"}, "white_noise",
             {"dimensions": "1D", "output": "color", "vector": [0.0, 0.0, 0.0]}),
        )
        for idname, out, props, node, expect in cases:
            with self.subTest(idname):
                p, w = self._color_into_diffuse(lambda t: t.new(idname, "Tex", **props).out(out))
                c = p["color"] if p["color"]["node"] != "rgb_to_bw" else p["color"]["color"]
                self.assertEqual(c["node"], node)
                for k, v in expect.items():
                    self.assertEqual(c[k], v, k) if not isinstance(v, float) else self.assertAlmostEqual(c[k], v, 6)
                self.assertIsNone(w)

    def test_texture_inputs_may_be_textures(self):
        # A linked Distortion or Detail is a node input, not a constant (a textured Noise
        # Distortion was ignored before).
        def b(t):
            n = t.new("ShaderNodeTexNoise", "N")
            v = t.new("ShaderNodeTexVoronoi", "V")
            t.link(v.out("Distance"), n.inp("Distortion"))
            t.link(v.out("Distance"), n.inp("Detail"))
            return n.out("Fac")
        p, w = self._color_into_diffuse(b)
        self.assertEqual(p["color"]["distortion"]["node"], "voronoi")
        self.assertEqual(p["color"]["detail"]["node"], "voronoi")
        self.assertIsNone(w)

    def test_normal_map_and_bump_named(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            nm = t.new("ShaderNodeNormalMap", "NMap", space="TANGENT", uv_map="")
            bump = t.new("ShaderNodeBump", "Bumpy", invert=False)
            t.link(nm.out(), bump.inp("Normal"))
            t.link(bump.out(), d.inp("Normal"))
            return d.out()
        p, w = material_with(b)
        self.assertEqual(p["type"], "diffuse")
        self.assertEqual(p["normal"]["node"], "bump")
        self.assertEqual(p["normal"]["normal"]["node"], "normal_map")
        self.assertIsNone(w)


def _tex_diffuse(t, img):
    d = t.new("ShaderNodeBsdfDiffuse", "D")
    tex = t.new("ShaderNodeTexImage", "Tex", image=img)
    t.link(tex.out("Color"), d.inp("Color"))
    return d.out()


class TestGraph(unittest.TestCase):
    def test_reroute_chain(self):
        def b(t):
            d = _diffuse(t, (0.1, 0.7, 0.2))
            prev = d.out()
            for i in range(5):
                r = t.new("NodeReroute", "Reroute.%d" % i)
                t.link(prev, r.inp("Input"))
                prev = r.out()
            return prev
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.1, 0.7, 0.2)))
        self.assertIsNone(w)

    def test_muted_color_node_passes_through(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            m = t.new("ShaderNodeMixRGB", "MixRGB", blend_type="MULTIPLY", use_clamp=False)
            m.inp("Fac").default_value = 1.0
            m.inp("Color1").default_value = [0.3, 0.3, 0.3, 1.0]
            m.inp("Color2").default_value = [0.0, 0.0, 0.0, 1.0]
            m.mute_with_passthrough()  # internal link: Fac (VALUE) is not RGBA -> Color1
            t.link(m.out(), d.inp("Color"))
            return d.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.3, 0.3, 0.3)), p)

    def test_muted_shader_without_passthrough_is_nothing(self):
        def b(t):
            d = _diffuse(t, (0.5, 0.5, 0.5))
            d.mute = True
            return d.out()
        p, w = material_with(b)
        self.assertEqual(p["color"], [0.0, 0.0, 0.0])

    def test_muted_mix_shader_passes_first_shader(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            t.link(_diffuse(t, (1, 0, 0), "A").out(), m.inp("Shader"))
            t.link(_diffuse(t, (0, 0, 1), "B").out(), m.inp("Shader_001"))
            m.mute_with_passthrough()
            return m.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (1, 0, 0)))

    def test_muted_link_is_ignored(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            rgb = t.new("ShaderNodeRGB", "RGB")
            rgb.out().default_value = [1.0, 0.0, 0.0, 1.0]
            t.link(rgb.out(), d.inp("Color")).is_muted = True
            return d.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.8, 0.8, 0.8)))

    def test_node_group(self):
        inner, gin, gout = group_tree("Tint", [("Input_0", "Color", "RGBA", (1, 1, 1, 1)),
                                               ("Input_1", "Amount", "VALUE", 0.5)],
                                      [("Output_0", "Shader", "SHADER", None)])
        mix = inner.new("ShaderNodeMixRGB", "Darken", blend_type="MULTIPLY", use_clamp=False)
        inner.link(gin.out("Input_0"), mix.inp("Color1"))
        inner.link(gin.out("Input_1"), mix.inp("Fac"))
        mix.inp("Color2").default_value = [0.0, 0.0, 0.0, 1.0]
        d = inner.new("ShaderNodeBsdfDiffuse", "D")
        inner.link(mix.out(), d.inp("Color"))
        inner.link(d.out(), gout.inp("Output_0"))

        def b(t):
            g = t.group_node(inner, "MyGroup")
            rgb = t.new("ShaderNodeRGB", "RGB")
            rgb.out().default_value = [0.8, 0.4, 0.2, 1.0]
            t.link(rgb.out(), g.inp("Input_0"))
            g.inp("Input_1").default_value = 0.25  # -> colour * 0.75
            return g.out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.6, 0.3, 0.15)), p)
        self.assertIsNone(w)

    def test_nested_groups_and_warning_path(self):
        inner, gin, gout = group_tree("Inner", [], [("Output_0", "Shader", "SHADER", None)])
        particles = inner.new("ShaderNodeParticleInfo", "Particles")
        d = inner.new("ShaderNodeBsdfDiffuse", "D")
        inner.link(particles.out("Random"), d.inp("Color"))
        inner.link(d.out(), gout.inp("Output_0"))
        outer, ogin, ogout = group_tree("Outer", [], [("Output_0", "Shader", "SHADER", None)])
        gi = outer.group_node(inner, "InnerGroup")
        outer.link(gi.out(), ogout.inp("Output_0"))

        def b(t):
            return t.group_node(outer, "OuterGroup").out()
        p, w = material_with(b)
        self.assertTrue(close(p["color"], (0.5, 0.5, 0.5)))
        self.assertIn("OuterGroup/InnerGroup/Particles", w)
        self.assertIn("unsupported node ShaderNodeParticleInfo", w)

    def test_unsupported_shader_node_falls_back_to_its_colour(self):
        p, w = material_with(lambda t: t.new("ShaderNodeFancyUnknownBsdf", "Fancy").out())
        self.assertEqual(p["type"], "diffuse")
        self.assertTrue(close(p["color"], (0.3, 0.6, 0.9)))
        self.assertIn("'Fancy'", w)
        self.assertIn("ShaderNodeFancyUnknownBsdf", w)

    def test_velvet_is_approximated_by_sheen(self):
        p, w = material_with(lambda t: t.new("ShaderNodeBsdfVelvet", "Soft").out())
        self.assertEqual(p["type"], "sheen")
        self.assertIn("Velvet BSDF 'Soft'", w)

    def test_one_warning_names_every_node(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            t.link(t.new("ShaderNodeBsdfVelvet", "VelvetA").out(), m.inp("Shader"))
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(t.new("ShaderNodeParticleInfo", "ParticlesB").out("Random"), d.inp("Color"))
            t.link(d.out(), m.inp("Shader_001"))
            return m.out()
        p, w = material_with(b, name="Combo")
        self.assertIsInstance(w, str)
        self.assertEqual(w.count("Material 'Combo'"), 1)
        self.assertIn("VelvetA", w)
        self.assertIn("ParticlesB", w)
        self.assertNotIn("\n", w)

    def test_cycle_does_not_hang(self):
        def b(t):
            a = t.new("ShaderNodeMath", "A", operation="ADD", use_clamp=False)
            c = t.new("ShaderNodeMath", "C", operation="ADD", use_clamp=False)
            t.link(a.out(), c.inputs[0])
            t.link(c.out(), a.inputs[0])
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(c.out(), d.inp("Color"))
            m = t.new("ShaderNodeMixShader", "Mix")
            t.link(m.out(), m.inp("Shader"))  # a shader cycle too
            t.link(d.out(), m.inp("Shader_001"))
            return m.out()
        start = time.time()
        p, w = material_with(b)
        self.assertLess(time.time() - start, 2.0)
        self.assertIn("cycle", w)

    def test_recursive_group_does_not_hang(self):
        inner, gin, gout = group_tree("Loop", [], [("Output_0", "Shader", "SHADER", None)])
        g = inner.group_node(inner, "Self")  # a group containing itself (malformed)
        inner.link(g.out(), gout.inp("Output_0"))
        start = time.time()
        p, w = material_with(lambda t: t.group_node(inner, "Top").out())
        self.assertLess(time.time() - start, 2.0)
        self.assertIsNotNone(w)

    def test_very_deep_chain_does_not_crash(self):
        def b(t):
            prev = None
            for i in range(2000):
                m = t.new("ShaderNodeMath", "M%d" % i, operation="ADD", use_clamp=False)
                if prev is not None:
                    t.link(prev.out(), m.inputs[0])
                prev = m
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(prev.out(), d.inp("Color"))
            return d.out()
        p, w = material_with(b)
        self.assertIn("too deep", w)
        self.assertEqual(p, sm.ERROR_SURFACE)  # magenta, as Blender shows a material it cannot use

    def test_hundred_thousand_nested_mix_shaders_is_an_error(self):
        # The walk stops at limits.MAX_DEPTH nodes with an error naming the material and the
        # node, without reaching Python's recursion limit (which would crash a C-level walk).
        t = Tree("Deep")
        prev = t.new("ShaderNodeBsdfDiffuse", "D")
        for i in range(100000):
            m = t.new("ShaderNodeMixShader", "Mix%d" % i)
            t.link(prev.out(), m.inp("Shader"))
            prev = m
        t.link(prev.out(), t.output().inp("Surface"))
        p, w = sm.convert_material(Material("Deep", t))
        self.assertEqual(p, sm.ERROR_SURFACE)
        self.assertIn("Material 'Deep'", w)
        self.assertIn("too deep: more than 120 nodes on one path, at MixShader 'Mix99879'", w)

    def test_shared_nodes_written_out_exponentially_is_an_error(self):
        # 30 Math nodes each feeding the next twice: 2^30 nodes once written out as the
        # engine's tree description; refused by counting, not by writing.
        p, w = material_with(lambda t: _diamond(t, t.new("ShaderNodeTexNoise", "N"), 30, "ADD"), name="Fractal")
        self.assertEqual(p, sm.ERROR_SURFACE)
        self.assertIn("Material 'Fractal': node graph too large: more than 100000 nodes", w)
        shared = {"node": "noise"}
        self.assertEqual(sm.limits.written_size({"a": shared, "b": [shared, shared]}), 5)

    def test_diamond_graph_is_linear_time(self):
        def b(t):
            value = t.new("ShaderNodeValue", "V")
            value.out().default_value = 0.0
            return _diamond(t, value, 60, "MAXIMUM")  # 2^60 paths without memoisation
        start = time.time()
        material_with(b)
        self.assertLess(time.time() - start, 2.0)

    def test_output_selection(self):
        t = Tree("M")
        eevee = t.output()
        eevee.target = "EEVEE"
        inactive = t.output()
        inactive.is_active_output = False
        active = t.output()
        t.link(_diffuse(t, (1, 0, 0), "Red").out(), eevee.inp("Surface"))
        t.link(_diffuse(t, (0, 1, 0), "Green").out(), inactive.inp("Surface"))
        t.link(_diffuse(t, (0, 0, 1), "Blue").out(), active.inp("Surface"))
        p, w = sm.convert_material(Material("M", t))
        self.assertTrue(close(p["color"], (0, 0, 1)))

    def test_material_without_nodes(self):
        p, w = sm.convert_material(Material("Plain", None, use_nodes=False, diffuse_color=(0.1, 0.2, 0.3, 1)))
        self.assertEqual(p, {"type": "diffuse", "color": [0.1, 0.2, 0.3]})
        self.assertIsNone(w)

    def test_translate_gives_serialisable_description(self):
        import json
        t = Tree("M")
        out = t.output()
        t.link(t.new("ShaderNodeBsdfPrincipled", "P").out(), out.inp("Surface"))
        desc = sm.translate_material(t, "M")
        text = json.dumps(desc.to_dict())
        self.assertIn("principled", text)

    @staticmethod
    def _displaced(normal=None, method=None, space="OBJECT"):
        """A Principled BSDF (Normal from normal(t) if given) over a Displacement of a noise's
        height into the Material Output (Settings > Displacement: method)."""
        t = Tree("M")
        out = t.output()
        p = t.new("ShaderNodeBsdfPrincipled", "P")
        if normal is not None:
            t.link(normal(t), p.inp("Normal"))
        t.link(p.out(), out.inp("Surface"))
        noise = t.new("ShaderNodeTexNoise", "Noise", noise_dimensions="3D")
        disp = t.new("ShaderNodeDisplacement", "Disp", space=space)
        disp.inp("Scale").default_value = 0.2
        t.link(noise.out("Fac"), disp.inp("Height"))
        t.link(disp.out(), out.inp("Displacement"))
        return sm.convert_material(Material("M", t, displacement_method=method))

    def test_displacement_bumps_the_material_normal(self):
        # Cycles' Bump Only: height = offset . normal, a bump of distance 1 that becomes the
        # surface normal (SetNormal), the material's "surface_normal".
        p, w = self._displaced()
        self.assertIsNone(w)
        self.assertNotIn("normal", p)
        bump = p["surface_normal"]
        self.assertEqual((bump["node"], bump["strength"], bump["distance"]), ("bump", 1.0, 1.0))
        dot = bump["height"]
        self.assertEqual((dot["node"], dot["operation"], dot["output"]), ("vector_math", "DOT_PRODUCT", "value"))
        self.assertEqual(dot["vector2"], {"node": "texture_coordinate", "output": "normal"})
        disp = dot["vector1"]
        self.assertEqual((disp["node"], disp["space"], disp["midlevel"], disp["scale"]),
                         ("displacement", "OBJECT", 0.5, 0.2))
        self.assertEqual(disp["height"]["node"], "noise")
        self.assertEqual(self._displaced(space="WORLD")[0]["surface_normal"]["height"]["vector1"]["space"], "WORLD")

    def test_displacement_under_a_bump_and_a_normal_map(self):
        # A shader's own Normal (a Bump, a Normal Map) stays its own; the engine evaluates it
        # at the displaced surface normal (a Bump without a Normal bumps it further, as Cycles).
        def bump(t):
            b = t.new("ShaderNodeBump", "Bumpy", invert=False)
            t.link(t.new("ShaderNodeTexChecker", "Check").out("Fac"), b.inp("Height"))
            return b.out()

        def normal_map(t):
            return t.new("ShaderNodeNormalMap", "NMap", space="OBJECT", uv_map="").out()
        for build, node in ((bump, "bump"), (normal_map, "normal_map")):
            p, w = self._displaced(build)
            self.assertEqual(p["normal"]["node"], node)
            self.assertNotIn("normal", p["normal"])
            self.assertEqual(p["surface_normal"]["height"]["vector1"]["node"], "displacement")

    def test_camera_data(self):
        for output, engine in (("View Vector", "view_vector"), ("View Z Depth", "view_z_depth"),
                               ("View Distance", "view_distance")):
            def b(t):
                cam = t.new("ShaderNodeCameraData", "Cam")
                d = t.new("ShaderNodeBsdfDiffuse", "D")
                t.link(cam.out(output), d.inp("Color"))
                return d.out()
            p, w = material_with(b)
            self.assertIsNone(w)
            text = json.dumps(p["color"])
            self.assertIn('{"node": "camera_data", "output": "%s"}' % engine, text)

    def test_aov_outputs(self):
        """AOV Output nodes (the AOV's name in the node's `name`, as Blender 3.4 keeps it) go to
        the material's "aovs", both inputs, a texture or a constant; muted ones are left out."""
        def b(t):
            noise = t.new("ShaderNodeTexNoise", "Noise")
            aov = t.new("ShaderNodeOutputAOV", "mask")
            t.link(noise.out("Color"), aov.inp("Color"))
            aov.inp("Value").default_value = 0.5
            muted = t.new("ShaderNodeOutputAOV", "ignored")
            muted.mute = True
            return t.new("ShaderNodeBsdfDiffuse", "D").out()
        p, w = material_with(b)
        self.assertIsNone(w)
        self.assertEqual(sorted(p["aovs"]), ["mask"])
        self.assertEqual(p["aovs"]["mask"]["value"], 0.5)
        self.assertIn('"node": "noise"', json.dumps(p["aovs"]["mask"]["color"]))
        p, _ = material_with(lambda t: t.new("ShaderNodeBsdfDiffuse", "D").out())
        self.assertNotIn("aovs", p)

    def test_aov_outputs_inside_node_groups(self):
        """An AOV Output inside a node group writes as Cycles' flattened groups do, reading what
        flows into that use of the group; a muted group's are left out."""
        inner, gin, gout = group_tree("Mask", [("Input_0", "Color", "RGBA", (1, 1, 1, 1))],
                                      [("Output_0", "Shader", "SHADER", None)])
        aov = inner.new("ShaderNodeOutputAOV", "inner")
        inner.link(gin.out("Input_0"), aov.inp("Color"))
        d = inner.new("ShaderNodeBsdfDiffuse", "D")
        inner.link(d.out(), gout.inp("Output_0"))
        muted_inner, _, muted_out = group_tree("Muted", [], [("Output_0", "Shader", "SHADER", None)])
        muted_inner.new("ShaderNodeOutputAOV", "muted")

        def b(t):
            g = t.group_node(inner, "MaskGroup")
            rgb = t.new("ShaderNodeRGB", "RGB")
            rgb.out().default_value = [0.2, 0.4, 0.6, 1.0]
            t.link(rgb.out(), g.inp("Input_0"))
            t.group_node(muted_inner, "MutedGroup").mute = True
            return g.out()
        p, w = material_with(b)
        self.assertIsNone(w)
        self.assertEqual(sorted(p["aovs"]), ["inner"])
        self.assertTrue(close(p["aovs"]["inner"]["color"], (0.2, 0.4, 0.6)), p["aovs"])

    def test_view_layer_attributes_are_the_render_constants(self):
        """Attribute nodes of type View Layer: the lookup's value (Color the RGB, Fac its average,
        Alpha its alpha; a name found nowhere 0, as Cycles); without a lookup, approximated."""
        values = {"tint": (0.9, 0.3, 0.0, 0.5)}

        def b(output, name="tint"):
            def build(t):
                a = t.new("ShaderNodeAttribute", "VL", attribute_type="VIEW_LAYER", attribute_name=name)
                d = t.new("ShaderNodeBsdfDiffuse", "D")
                t.link(a.out(output), d.inp("Color"))
                return d.out()
            return build
        for output, name, expected in (("Color", "tint", (0.9, 0.3, 0.0)), ("Fac", "tint", (0.4, 0.4, 0.4)),
                                       ("Alpha", "tint", (0.5, 0.5, 0.5)), ("Color", "missing", (0.0, 0.0, 0.0))):
            t = Tree("M")
            t.link(b(output, name)(t), t.output().inp("Surface"))
            p, w = sm.convert_material(Material("M", t), image_average=image_average,
                                       view_layer_attribute=lambda n: values.get(n))
            self.assertIsNone(w, output)
            self.assertTrue(close(p["color"], expected), (output, name, p["color"]))
        p, w = material_with(b("Color"))
        self.assertIn("'VL'", w)
        # With a ray type read beside it, the looks per kind of ray stay (the flag is no constant).
        t = Tree("M")
        m = t.new("ShaderNodeMixShader", "Mix")
        t.link(t.new("ShaderNodeLightPath", "LP").out("Is Camera Ray"), m.inp("Fac"))
        t.link(b("Color")(t), m.inp("Shader"))
        t.link(t.new("ShaderNodeBsdfDiffuse", "Other").out(), m.inp("Shader_001"))
        t.link(m.out(), t.output().inp("Surface"))
        variants, w = sm.convert_material_variants(Material("M", t), image_average=image_average,
                                                   view_layer_attribute=lambda n: values.get(n))
        self.assertEqual(len(variants), 2)

    def test_object_and_instancer_attributes(self):
        """Attribute nodes of type Object / Instancer: the engine reads the instance's value (the
        exporter sends it); View Layer stays an approximation."""
        for kind, output in (("OBJECT", "Color"), ("INSTANCER", "Fac"), ("VIEW_LAYER", "Color")):
            def b(t):
                a = t.new("ShaderNodeAttribute", "A", attribute_name="tint", attribute_type=kind)
                d = t.new("ShaderNodeBsdfDiffuse", "D")
                t.link(a.out(output), d.inp("Color"))
                return d.out()
            p, w = material_with(b)
            text = json.dumps(p["color"])
            if kind == "VIEW_LAYER":
                self.assertIn("approximated", w)
                continue
            self.assertIsNone(w)
            self.assertIn('"name": "tint"', text)
            self.assertIn('"attribute_type": "%s"' % kind, text)

    def test_vector_displacement(self):
        t = Tree("M")
        out = t.output()
        t.link(t.new("ShaderNodeBsdfPrincipled", "P").out(), out.inp("Surface"))
        noise = t.new("ShaderNodeTexNoise", "Noise", noise_dimensions="3D")
        vd = t.new("ShaderNodeVectorDisplacement", "VDisp", space="TANGENT")
        t.link(noise.out("Color"), vd.inp("Vector"))
        t.link(vd.out(), out.inp("Displacement"))
        p, w = sm.convert_material(Material("M", t, displacement_method="DISPLACEMENT"))
        self.assertIsNone(w)
        d = p["displacement"]
        self.assertEqual((d["node"], d["space"], d["midlevel"], d["scale"], d["vector"]["node"]),
                         ("vector_displacement", "TANGENT", 0.0, 1.0, "noise"))
        p, w = sm.convert_material(Material("M", t))  # Bump Only: the offset's normal part
        self.assertEqual(p["surface_normal"]["height"]["vector1"]["node"], "vector_displacement")

    def test_true_displacement_moves_the_vertices(self):
        # Displacement Only: the offset as the material's "displacement" (the engine moves the
        # vertices), no bump; Displacement and Bump: both, the bump in object space (Cycles').
        p, w = self._displaced(method="DISPLACEMENT")
        self.assertIsNone(w)
        self.assertNotIn("surface_normal", p)
        self.assertEqual((p["displacement"]["node"], p["displacement_method"]), ("displacement", "true"))
        p, w = self._displaced(method="BOTH")
        self.assertIsNone(w)
        self.assertEqual((p["displacement"]["node"], p["displacement_method"]), ("displacement", "both"))
        self.assertEqual((p["surface_normal"]["node"], p["surface_normal"]["space"]), ("bump", "OBJECT"))
        self.assertNotIn("displacement", self._displaced(method="BUMP")[0])

    def test_constant_displacement_bumps_nothing(self):
        def b(t):
            out = next(n for n in t.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
            t.link(t.new("ShaderNodeValue", "H").out(), out.inp("Displacement"))
            return _diffuse(t, (0.5, 0.5, 0.5)).out()
        p, w = material_with(b)
        self.assertNotIn("surface_normal", p)
        self.assertNotIn("displacement", p)
        self.assertIsNone(w)
        # Moved whole under true displacement (a float into the socket: that value on each axis).
        t = Tree("M")
        out = t.output()
        h = t.new("ShaderNodeValue", "H")
        h.outputs[0].default_value = 0.25
        t.link(h.out(), out.inp("Displacement"))
        t.link(_diffuse(t, (0.5, 0.5, 0.5)).out(), out.inp("Surface"))
        p, w = sm.convert_material(Material("M", t, displacement_method="DISPLACEMENT"))
        self.assertEqual((p["displacement"], p["displacement_method"]), ([0.25, 0.25, 0.25], "true"))


class TestLights(unittest.TestCase):
    """A light's node tree: its Emission's colour and strength, which Cycles multiplies into the
    lamp's, as the engine light's "emission"."""

    @staticmethod
    def _light(build, use_nodes=True, kind="POINT", image_file=None):
        t = Tree("L")
        out = t.new("ShaderNodeOutputLight", "Light Output")
        em = t.new("ShaderNodeEmission", "Emission")
        t.link(em.out(), out.inp("Surface"))
        build(t, em)
        light = type("Light", (), {"name": "Lamp", "use_nodes": use_nodes, "node_tree": t, "type": kind})()
        return sm.convert_light(light, image_file=image_file)

    def test_default_tree_and_no_nodes(self):
        self.assertEqual(self._light(lambda t, em: None), ({"color": [1.0, 1.0, 1.0], "strength": 1.0}, None))
        self.assertEqual(self._light(lambda t, em: None, use_nodes=False), (None, None))

    def test_blackbody_and_quadratic_falloff(self):
        def b(t, em):
            bb = t.new("ShaderNodeBlackbody", "BB")
            bb.inp("Temperature").default_value = 3000.0
            t.link(bb.out(), em.inp("Color"))
            fall = t.new("ShaderNodeLightFalloff", "Falloff")
            fall.inp("Strength").default_value = 2.5
            t.link(fall.out("Quadratic"), em.inp("Strength"))
        e, w = self._light(b)
        self.assertIsNone(w)
        self.assertEqual(e, {"color": {"node": "blackbody", "temperature": 3000.0}, "strength": 2.5})

    def test_what_varies_over_the_lamp_is_named(self):
        """A texture of the point light leaves from stays a graph (the engine evaluates it there),
        but on a sun, whose shader point is its direction; what a lamp's shader point does not
        have as Cycles' (a Fresnel's incoming ray) is a named constant."""
        def b(t, em):
            fall = t.new("ShaderNodeLightFalloff", "Falloff")
            t.link(fall.out("Linear"), em.inp("Strength"))
            t.link(t.new("ShaderNodeTexChecker", "Check").out("Color"), em.inp("Color"))
        for kind in ("POINT", "SPOT", "AREA"):
            e, w = self._light(b, kind=kind)
            self.assertIsNone(w)
            self.assertEqual(e["color"]["node"], "checker")  # of Generated (unlinked): the point in the world
            self.assertNotIn("vector", e["color"])
        e, w = self._light(b, kind="SUN")
        self.assertIn("Check", w)
        self.assertNotIn("Falloff", w)
        self.assertIsInstance(e["color"], list)
        self.assertEqual(e["strength"], {"node": "light_falloff", "output": "LINEAR", "strength": 100.0, "smooth": 0.0})

        def fresnel(t, em):
            t.link(t.new("ShaderNodeFresnel", "Fresnel").out(), em.inp("Strength"))
        e, w = self._light(fresnel, kind="AREA")
        self.assertIn("Fresnel", w)
        self.assertIsInstance(e["strength"], float)

    def test_an_image_over_an_area_lamp(self):
        """Geometry > Parametric into an Image Texture: the image over the lamp (Cycles 3.4's
        (0.5 + x, 0.5 + y) of an area lamp), its file from the image callback."""
        def b(t, em):
            geo = t.new("ShaderNodeNewGeometry", "Geometry")
            img = t.new("ShaderNodeTexImage", "Gobo", image=type("Image", (), {"name": "gobo.png"})())
            t.link(geo.out("Parametric"), img.inp("Vector"))
            t.link(img.out("Color"), em.inp("Color"))
        e, w = self._light(b, kind="AREA", image_file=lambda image, *user: "/maps/" + image.name)
        self.assertIsNone(w)
        self.assertEqual(e["color"]["node"], "image")
        self.assertEqual(e["color"]["file"], "/maps/gobo.png")
        self.assertEqual(e["color"]["vector"], {"node": "texture_coordinate", "output": "parametric"})

    def test_light_falloff_stays_a_node_by_the_distance(self):
        """Linear, Constant, and Quadratic with Smooth: the engine evaluates them at the distance
        light travels; Quadratic without Smooth is Strength itself (no node, no warning)."""
        for output, smooth, node in (("Linear", 0.0, True), ("Constant", 0.0, True), ("Quadratic", 2.0, True),
                                     ("Quadratic", 0.0, False)):
            with self.subTest(output=output, smooth=smooth):
                def b(t, em):
                    fall = t.new("ShaderNodeLightFalloff", "Falloff")
                    fall.inp("Strength").default_value = 40.0
                    fall.inp("Smooth").default_value = smooth
                    m = t.new("ShaderNodeMath", "Twice", operation="MULTIPLY", use_clamp=False)
                    t.link(fall.out(output), m.inputs[0])
                    m.inputs[1].default_value = 2.0
                    t.link(m.out(), em.inp("Strength"))
                e, w = self._light(b)
                self.assertIsNone(w)
                if node:
                    self.assertEqual(e["strength"]["value1"], {"node": "light_falloff", "output": output.upper(),
                                                               "strength": 40.0, "smooth": smooth})
                else:
                    self.assertEqual(e["strength"], 80.0)


    def test_ies_texture_by_direction(self):
        """An IES Texture (here scaled by a Math node and rotated by a Mapping of the lamp's
        normal) stays a graph the engine evaluates per direction; its profile goes inline."""
        import tempfile

        class Text:
            def as_string(self):
                return "IESNA:LM-63-2002\nTILT=NONE\n..."

        def b(t, em):
            ies = t.new("ShaderNodeTexIES", "IES")
            ies.mode, ies.ies = "INTERNAL", Text()
            ies.inp("Strength").default_value = 2.0
            coords = t.new("ShaderNodeTexCoord", "Coords")
            mapping = t.new("ShaderNodeMapping", "Turn")
            t.link(coords.out("Normal"), mapping.inp("Vector"))
            t.link(mapping.out("Vector"), ies.inp("Vector"))
            mul = t.new("ShaderNodeMath", "Times")
            mul.operation = "MULTIPLY"
            mul.inputs[1].default_value = 3.0
            t.link(ies.out("Fac"), mul.inputs[0])
            t.link(mul.out(), em.inp("Strength"))
        e, w = self._light(b)
        self.assertIsNone(w)
        text = json.dumps(e["strength"])
        self.assertIn('"node": "ies"', text)
        self.assertIn('"profile": "IESNA:LM-63-2002\\nTILT=NONE\\n..."', text)
        self.assertIn('"output": "object_normal"', text)
        self.assertIn('"strength": 2.0', text)
        # An external file is read here; one that cannot be goes as its path (the engine names it).
        with tempfile.NamedTemporaryFile("w", suffix=".ies", delete=False) as f:
            f.write("IESNA91\nTILT=NONE\n1 1000 1 1 1 1 2 0 0 0\n1 1 10\n0\n0\n100\n")
        for path, key in ((f.name, "profile"), ("/nonexistent/lamp.ies", "file")):
            def ext(t, em):
                ies = t.new("ShaderNodeTexIES", "IES")
                ies.mode, ies.filepath = "EXTERNAL", path
                t.link(ies.out("Fac"), em.inp("Strength"))
            e, w = self._light(ext)
            self.assertIsNone(w)
            self.assertIn(key, e["strength"])
        os.unlink(f.name)


class TestWorld(unittest.TestCase):
    def _world(self, build):
        t = Tree("W")
        out = t.new("ShaderNodeOutputWorld", "World Output")
        t.link(build(t), out.inp("Surface"))
        return sm.convert_world(World("W", t), image_average=image_average)

    def test_background(self):
        def b(t):
            bg = t.new("ShaderNodeBackground", "Background")
            bg.inp("Color").default_value = [0.2, 0.4, 0.8, 1.0]
            bg.inp("Strength").default_value = 2.0
            return bg.out()
        p, w = self._world(b)
        self.assertTrue(close([c * p["strength"] for c in p["color"]], (0.4, 0.8, 1.6)))
        self.assertIsNone(w)

    def test_environment_texture_average(self):
        img = Image("sky.hdr", average=((2.0, 1.0, 0.5), 1.0))

        def b(t):
            bg = t.new("ShaderNodeBackground", "Background")
            env = t.new("ShaderNodeTexEnvironment", "Sky", image=img)
            t.link(env.out("Color"), bg.inp("Color"))
            return bg.out()
        p, w = self._world(b)
        self.assertTrue(close([c * p["strength"] for c in p["color"]], (2.0, 1.0, 0.5)))
        self.assertIn("Environment Texture 'Sky'", w)

    def test_nishita_sky_goes_to_the_engine(self):
        def b(t, sky_type="NISHITA"):
            bg = t.new("ShaderNodeBackground", "Background")
            bg.inp("Strength").default_value = 0.5
            sky = t.new("ShaderNodeTexSky", "Sky", sky_type=sky_type, sun_disc=True, sun_size=0.02,
                        sun_intensity=0.7, sun_elevation=0.3, sun_rotation=1.2, altitude=100.0, air_density=1.5,
                        dust_density=0.5, ozone_density=2.0)
            mapping = t.new("ShaderNodeMapping", "Mapping", vector_type="POINT")
            mapping.inp("Rotation").default_value = [0.0, 0.0, 0.25]
            t.link(mapping.out(), sky.inp("Vector"))
            t.link(sky.out("Color"), bg.inp("Color"))
            return bg.out()
        p, w = self._world(b)
        self.assertIsNone(w)
        self.assertEqual(p["strength"], 0.5)
        self.assertEqual(p["sky"], {"type": "nishita", "sun_disc": True, "sun_size": 0.02, "sun_intensity": 0.7,
                                    "sun_elevation": 0.3, "sun_rotation": 1.2, "altitude": 100.0, "air_density": 1.5,
                                    "dust_density": 0.5, "ozone_density": 2.0})  # Cycles 3.4 ignores the Mapping
        # The other sky types: a constant, named.
        p, w = self._world(lambda t: b(t, "HOSEK_WILKIE"))
        self.assertNotIn("sky", p)
        self.assertIn("Sky Texture 'Sky'", w)

    def test_world_aov_outputs(self):
        """The World's AOV Outputs go to its "aovs" (written where camera rays leave for the
        world); with Light Path > Is Camera Ray in the World, the camera look's, and not in
        "camera" (the engine reads them at the top)."""
        def b(t, camera_ray=False):
            bg = t.new("ShaderNodeBackground", "Background")
            aov = t.new("ShaderNodeOutputAOV", "sky")
            aov.inp("Color").default_value = [0.1, 0.2, 0.3, 1.0]
            if camera_ray:
                t.link(t.new("ShaderNodeLightPath", "LP").out("Is Camera Ray"), aov.inp("Value"))
                t.link(t.new("ShaderNodeLightPath", "LP2").out("Is Camera Ray"), bg.inp("Strength"))
            else:
                aov.inp("Value").default_value = 0.75
            return bg.out()
        p, w = self._world(b)
        self.assertTrue(close(p["aovs"]["sky"]["color"], (0.1, 0.2, 0.3)), p)
        self.assertEqual(p["aovs"]["sky"]["value"], 0.75)
        p, w = self._world(lambda t: b(t, camera_ray=True))
        self.assertEqual(p["aovs"]["sky"]["value"], 1.0)
        self.assertIn("camera", p)
        self.assertNotIn("aovs", p["camera"])

        def aov_only(t):  # the AOV alone reads the ray type: no camera look, the AOV's camera value
            aov = t.new("ShaderNodeOutputAOV", "sky")
            t.link(t.new("ShaderNodeLightPath", "LP").out("Is Camera Ray"), aov.inp("Value"))
            return t.new("ShaderNodeBackground", "Background").out()
        p, w = self._world(aov_only)
        self.assertEqual(p["aovs"]["sky"]["value"], 1.0)
        self.assertNotIn("camera", p)

    def test_world_without_nodes_and_none(self):
        p, w = sm.convert_world(World("W", None, use_nodes=False, color=(0.1, 0.2, 0.3)))
        self.assertEqual(p, {"color": [0.1, 0.2, 0.3], "strength": 1.0})
        p, w = sm.convert_world(None)
        self.assertEqual(p["color"], [0.0, 0.0, 0.0])


class TestRegistry(unittest.TestCase):
    def test_issue_node_list_is_covered(self):
        required = ["ShaderNodeBsdfPrincipled", "ShaderNodeBsdfDiffuse", "ShaderNodeBsdfGlossy",
                    "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction",
                    "ShaderNodeBsdfTransparent", "ShaderNodeBsdfTranslucent", "ShaderNodeEmission",
                    "ShaderNodeMixShader", "ShaderNodeAddShader", "ShaderNodeTexImage", "ShaderNodeTexEnvironment",
                    "ShaderNodeMapping", "ShaderNodeTexCoord", "ShaderNodeUVMap", "ShaderNodeNormalMap",
                    "ShaderNodeBump", "ShaderNodeMixRGB", "ShaderNodeMix", "ShaderNodeMath", "ShaderNodeValToRGB",
                    "ShaderNodeInvert", "ShaderNodeRGB", "ShaderNodeValue", "ShaderNodeTexChecker",
                    "ShaderNodeTexNoise", "ShaderNodeTexGradient", "ShaderNodeBackground"]
        missing = [n for n in required if n not in sm.supported_nodes()]
        self.assertEqual(missing, [])

    def test_no_bpy_import(self):
        self.assertNotIn("bpy", sys.modules)


if __name__ == "__main__":
    unittest.main()
