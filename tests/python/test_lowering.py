"""Lowering to the engine's full material format (docs/scene-format.md), with stand-in nodes,
and every lowered material checked by the real engine (RDV_TEST_LIBRARY, or
build/engine/librendezvous.so, through the add-on's binding) at 16x16."""

import json
import os
import sys
import tempfile
import types
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, ROOT)

import shaders_map as sm  # noqa: E402
from fakenodes import Tree, Material, World, Image, Ramp, image_average  # noqa: E402

TMP = tempfile.mkdtemp(prefix="rdv_lowering_")


def _ppm(path, w=4, h=4):
    with open(path, "wb") as f:
        f.write(b"P6 %d %d 255\n" % (w, h))
        f.write(bytes(v for y in range(h) for x in range(w) for v in (x * 60 % 256, y * 60 % 256, 128)))
    return path


IMG_PATH = _ppm(os.path.join(TMP, "tex.ppm"))


def image_file(image):
    return None if getattr(image, "missing", False) else getattr(image, "engine_file", IMG_PATH)


def convert(build, name="M", volume=None):
    t = Tree(name)
    out = t.output()
    sock = build(t) if build is not None else None
    if sock is not None:
        t.link(sock, out.inp("Surface"))
    if volume is not None:
        t.link(volume(t), out.inp("Volume"))
    return sm.convert_material(Material(name, t), image_average=image_average, image_file=image_file)


def _find_library():
    lib = os.environ.get("RDV_TEST_LIBRARY") or os.path.join(ROOT, "build", "engine", "librendezvous.so")
    return lib if os.path.isfile(lib) else None


LIBRARY = _find_library()
ENGINE_CASES = {}  # name -> (params, warning): every material built below, rendered once by the engine


def keep(name, result):
    ENGINE_CASES[name] = result
    return result


def principled(t, name="P", **inputs):
    n = t.new("ShaderNodeBsdfPrincipled", name)
    for k, v in inputs.items():
        n.inp(k.replace("_", " ")).default_value = list(v) + [1.0] if isinstance(v, tuple) else v
    return n


class TestClosures(unittest.TestCase):
    def test_principled_is_principled(self):
        p, w = keep("principled", convert(lambda t: principled(
            t, Base_Color=(0.9, 0.6, 0.2), Metallic=0.5, Roughness=0.2, Clearcoat=0.3, Sheen=0.2,
            Transmission=0.1, Alpha=0.9).out()))
        self.assertEqual(p["type"], "principled")
        self.assertEqual(p["base_color"], [0.9, 0.6, 0.2])
        self.assertAlmostEqual(p["metallic"], 0.5)
        self.assertAlmostEqual(p["clearcoat"], 0.3)
        self.assertAlmostEqual(p["alpha"], 0.9)
        self.assertNotIn("emission", p)
        self.assertIsNone(w)

    def test_principled_subsurface_warns_and_emission_kept(self):
        p, w = keep("principled_sss", convert(lambda t: principled(
            t, Subsurface=0.5, Emission=(1.0, 0.5, 0.0), Emission_Strength=3.0).out()))
        self.assertEqual(p["emission"], [1.0, 0.5, 0.0])
        self.assertAlmostEqual(p["emission_strength"], 3.0)
        self.assertIn("subsurface", w)

    def test_glass_refraction_translucent_transparent(self):
        for idname, kind in (("ShaderNodeBsdfGlass", "glass"), ("ShaderNodeBsdfRefraction", "refraction"),
                             ("ShaderNodeBsdfTranslucent", "translucent"),
                             ("ShaderNodeBsdfTransparent", "transparent")):
            with self.subTest(idname):
                dist = {"distribution": "GGX"} if kind in ("glass", "refraction") else {}
                p, w = keep(kind, convert(lambda t: t.new(idname, "X", **dist).out()))
                self.assertEqual(p["type"], kind)
                self.assertIsNone(w)

    def test_glass_beckmann_is_ggx_with_warning(self):
        p, w = keep("glass_beckmann", convert(lambda t: t.new("ShaderNodeBsdfGlass", "G",
                                                               distribution="BECKMANN").out()))
        self.assertEqual(p["distribution"], "GGX")
        self.assertIsNone(w)  # smooth glass: the distribution does not matter

        def rough(t):
            g = t.new("ShaderNodeBsdfGlass", "G", distribution="BECKMANN")
            g.inp("Roughness").default_value = 0.3
            return g.out()
        p, w = keep("glass_beckmann_rough", convert(rough))
        self.assertEqual(p["distribution"], "GGX")
        self.assertIn("Glass BSDF 'G'", w)

    def test_anisotropic_glossy(self):
        def b(t):
            a = t.new("ShaderNodeBsdfAnisotropic", "Aniso", distribution="GGX")
            a.inp("Anisotropy").default_value = 0.5
            a.inp("Rotation").default_value = 0.25
            return a.out()
        p, w = keep("anisotropic", convert(b))
        self.assertEqual((p["type"], p["anisotropy"], p["rotation"]), ("glossy", 0.5, 0.25))
        self.assertIsNone(w)

    def test_velvet_is_sheen_with_warning(self):
        p, w = keep("velvet", convert(lambda t: t.new("ShaderNodeBsdfVelvet", "Soft").out()))
        self.assertEqual(p["type"], "sheen")
        self.assertIn("Velvet BSDF 'Soft'", w)

    def test_mix_of_different_closures_is_a_mix(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            m.inp("Fac").default_value = 0.3
            t.link(t.new("ShaderNodeBsdfDiffuse", "D").out(), m.inp("Shader"))
            t.link(t.new("ShaderNodeBsdfGlossy", "G", distribution="GGX").out(), m.inp("Shader_001"))
            a = t.new("ShaderNodeAddShader", "Add")
            t.link(m.out(), a.inp("Shader"))
            t.link(t.new("ShaderNodeBsdfGlass", "Gl", distribution="GGX").out(), a.inp("Shader_001"))
            return a.out()
        p, w = keep("mix_add", convert(b))
        self.assertEqual(p["type"], "add")
        self.assertEqual(p["shader1"]["type"], "mix")
        self.assertAlmostEqual(p["shader1"]["fac"], 0.3)
        self.assertEqual(p["shader1"]["shader1"]["type"], "diffuse")
        self.assertEqual(p["shader1"]["shader2"]["type"], "glossy")
        self.assertEqual(p["shader2"]["type"], "glass")
        self.assertIsNone(w)

    def test_textured_mix_factor(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            chk = t.new("ShaderNodeTexChecker", "Chk")
            t.link(chk.out("Fac"), m.inp("Fac"))
            t.link(t.new("ShaderNodeBsdfDiffuse", "D").out(), m.inp("Shader"))
            t.link(t.new("ShaderNodeBsdfTransparent", "T").out(), m.inp("Shader_001"))
            return m.out()
        p, w = keep("textured_mix", convert(b))
        self.assertEqual(p["fac"]["node"], "checker")
        self.assertEqual(p["fac"]["output"], "fac")
        self.assertIsNone(w)

    def test_textured_emission_is_kept_for_the_engine(self):
        def b(t):
            m = t.new("ShaderNodeMixShader", "Mix")
            t.link(t.new("ShaderNodeTexChecker", "Chk").out("Fac"), m.inp("Fac"))
            t.link(t.new("ShaderNodeBsdfDiffuse", "D").out(), m.inp("Shader"))
            e = t.new("ShaderNodeEmission", "E")
            t.link(t.new("ShaderNodeTexChecker", "Chk2").out("Color"), e.inp("Color"))
            t.link(e.out(), m.inp("Shader_001"))
            return m.out()
        p, w = keep("emission_mix", convert(b))
        self.assertIsNone(w)
        self.assertEqual(p["type"], "mix")
        self.assertEqual(p["fac"]["node"], "checker")
        self.assertEqual(p["shader2"]["type"], "emission")
        self.assertEqual(p["shader2"]["color"]["node"], "checker")

    def test_volume_only_and_surface_with_volume(self):
        def vol(t):
            v = t.new("ShaderNodeVolumePrincipled", "Fog")
            v.inp("Density").default_value = 0.5
            return v.out()
        p, w = keep("volume_only", convert(None, volume=vol))
        self.assertEqual(p["type"], "volume")
        self.assertAlmostEqual(p["volume"]["density"], 0.5)
        self.assertIsNone(w)

        def tinted(t):  # Cycles 3.4's Principled Volume absorbs by 1 - sqrt(Absorption Color)
            v = t.new("ShaderNodeVolumePrincipled", "Tinted")
            v.inp("Absorption Color").default_value = (0.25, 0.64, 1.0, 1.0)
            return v.out()
        p, w = keep("volume_tinted", convert(None, volume=tinted))
        for got, want in zip(p["volume"]["absorption_color"], [0.5, 0.8, 1.0]):
            self.assertAlmostEqual(got, want, places=6)
        p, w = keep("glass_smoke", convert(lambda t: t.new("ShaderNodeBsdfGlass", "G", distribution="GGX").out(),
                                           volume=lambda t: t.new("ShaderNodeVolumeAbsorption", "Abs").out()))
        self.assertEqual(p["type"], "glass")
        self.assertEqual(p["volume"]["color"], [0.0, 0.0, 0.0])
        self.assertEqual(p["volume"]["absorption_color"], [0.8, 0.8, 0.8])

    def test_added_volumes_are_physical(self):
        def vol(t):
            a = t.new("ShaderNodeAddShader", "AddV")
            t.link(t.new("ShaderNodeVolumeScatter", "S").out(), a.inp("Shader"))
            t.link(t.new("ShaderNodeVolumeAbsorption", "A").out(), a.inp("Shader_001"))
            return a.out()
        p, w = keep("volume_add", convert(None, volume=vol))
        v = p["volume"]
        self.assertTrue(all(abs(x - 0.8) < 1e-6 for x in v["sigma_s"]))  # scatter: color 0.8 x density 1
        self.assertTrue(all(abs(x - 0.2) < 1e-6 for x in v["sigma_a"]))  # absorption: (1 - 0.8) x 1


class TestVolumeGrids(unittest.TestCase):
    """Principled Volume blackbody and attributes: grids of Volume objects (references by
    name that the exporter completes), uniform values in mesh volumes."""

    def fire(self, t, **inputs):
        v = t.new("ShaderNodeVolumePrincipled", "Fire")
        for k, val in inputs.items():
            v.inp(k.replace("_", " ")).default_value = list(val) + [1.0] if isinstance(val, tuple) else val
        return v

    def convert_volume_object(self, volume):
        t = Tree("Fire")
        t.link(volume(t), t.output().inp("Volume"))
        return sm.convert_material(Material("Fire", t), image_average=image_average, image_file=image_file,
                                   volume_grids=True)

    def test_blackbody_from_temperature_grid(self):
        p, w = self.convert_volume_object(lambda t: self.fire(
            t, Blackbody_Intensity=0.8, Blackbody_Tint=(1.0, 0.5, 0.25), Temperature=1500.0).out())
        self.assertIsNone(w)
        v = p["volume"]
        self.assertEqual(v["grid"], {"name": "density"})
        self.assertEqual(v["temperature_grid"], {"name": "temperature"})
        self.assertAlmostEqual(v["blackbody_intensity"], 0.8)
        self.assertEqual(v["blackbody_tint"], [1.0, 0.5, 0.25])
        self.assertAlmostEqual(v["temperature"], 1500.0)

    def test_attribute_names_and_no_blackbody(self):
        def vol(t):
            f = self.fire(t)
            f.inp("Density Attribute").default_value = "smoke"
            f.inp("Temperature Attribute").default_value = "heat"
            return f.out()
        p, w = self.convert_volume_object(vol)
        self.assertIsNone(w)
        v = p["volume"]
        self.assertEqual(v["grid"], {"name": "smoke"})
        for k in ("temperature_grid", "blackbody_intensity", "temperature", "emission_grid"):
            self.assertNotIn(k, v)  # blackbody intensity 0: nothing about temperature

    def test_attribute_times_constant_into_emission_strength(self):
        def vol(t):
            f = self.fire(t, Emission_Color=(1.0, 0.4, 0.1))
            a = t.new("ShaderNodeAttribute", "Flame", attribute_name="flame", attribute_type="GEOMETRY")
            m = t.new("ShaderNodeMath", "Times", operation="MULTIPLY")
            m.inp("Value_001").default_value = 5.0
            t.link(a.out("Fac"), m.inp("Value"))
            t.link(m.out(), f.inp("Emission Strength"))
            return f.out()
        p, w = self.convert_volume_object(vol)
        self.assertIsNone(w)
        v = p["volume"]
        self.assertEqual(v["emission_grid"], {"name": "flame"})
        self.assertAlmostEqual(v["emission_strength"], 5.0)
        self.assertEqual(v["emission_color"], [1.0, 0.4, 0.1])

    def test_attribute_colour_output_into_density(self):
        def vol(t):
            f = self.fire(t)
            f.inp("Density Attribute").default_value = ""
            a = t.new("ShaderNodeAttribute", "D", attribute_name="smoke", attribute_type="GEOMETRY")
            t.link(a.out("Color"), f.inp("Density"))  # a float grid's colour is (v, v, v): luminance v
            return f.out()
        p, w = self.convert_volume_object(vol)
        self.assertIsNone(w)
        self.assertEqual(p["volume"]["grid"], {"name": "smoke"})
        self.assertAlmostEqual(p["volume"]["density"], 1.0)

    def test_unsupported_grid_uses_are_named(self):
        def vol(t):
            f = self.fire(t)
            f.inp("Color Attribute").default_value = "color"
            a = t.new("ShaderNodeAttribute", "D", attribute_name="density", attribute_type="GEOMETRY")
            t.link(a.out("Fac"), f.inp("Density"))  # Cycles: density x density
            return f.out()
        p, w = self.convert_volume_object(vol)
        self.assertIn("Color Attribute 'color' ignored", w)
        self.assertIn("only 'density' used", w)
        self.assertEqual(p["volume"]["grid"], {"name": "density"})

    def test_mixed_volumes_keep_their_grids(self):
        def vol(t):
            mix = t.new("ShaderNodeMixShader", "Mix")
            mix.inp("Fac").default_value = 0.25
            t.link(self.fire(t, Blackbody_Intensity=1.0).out(), mix.inp("Shader"))
            t.link(self.fire(t, Density=2.0).out(), mix.inp("Shader_001"))
            return mix.out()
        p, w = self.convert_volume_object(vol)
        self.assertIsNone(w)
        v = p["volume"]
        self.assertIn("sigma_s", v)
        self.assertEqual(v["grid"], {"name": "density"})
        self.assertEqual(v["temperature_grid"], {"name": "temperature"})
        self.assertEqual(v["blackbody_tint"], [0.75, 0.75, 0.75])  # the mix weight of the blackbody part

    def test_mesh_volume_blackbody_is_uniform(self):
        p, w = keep("volume_blackbody_mesh", convert(None, volume=lambda t: self.fire(
            t, Density=0.5, Blackbody_Intensity=1.0, Temperature=1200.0).out()))
        self.assertIsNone(w)
        v = p["volume"]
        self.assertAlmostEqual(v["blackbody_intensity"], 1.0)
        self.assertAlmostEqual(v["temperature"], 1200.0)
        for k in ("grid", "temperature_grid", "emission_grid"):
            self.assertNotIn(k, v)  # a mesh has no grids: Cycles ignores the attribute names


class TestTextures(unittest.TestCase):
    def test_image_through_mapping_and_uv(self):
        img = Image("wood.png")

        def b(t):
            d = t.new("ShaderNodeBsdfPrincipled", "P")
            uv = t.new("ShaderNodeUVMap", "UVMap", uv_map="Second")
            mp = t.new("ShaderNodeMapping", "Mapping", vector_type="POINT")
            mp.inp("Scale").default_value = [4.0, 4.0, 1.0]
            tex = t.new("ShaderNodeTexImage", "Wood", image=img, interpolation="Closest", extension="EXTEND")
            t.link(uv.out(), mp.inp("Vector"))
            t.link(mp.out(), tex.inp("Vector"))
            t.link(tex.out("Color"), d.inp("Base Color"))
            t.link(tex.out("Alpha"), d.inp("Alpha"))
            return d.out()
        p, w = keep("image", convert(b))
        bc = p["base_color"]
        self.assertEqual((bc["node"], bc["file"], bc["interpolation"], bc["extension"]),
                         ("image", IMG_PATH, "Closest", "EXTEND"))
        self.assertEqual(bc["vector"]["node"], "mapping")
        self.assertEqual(bc["vector"]["scale"], [4.0, 4.0, 1.0])
        self.assertEqual(bc["vector"]["vector"], {"node": "uv", "layer": "Second"})
        self.assertEqual(p["alpha"]["output"], "alpha")
        self.assertIsNone(w)

    def test_image_sources_other_than_a_file(self):
        """An image the exporter sends as a buffer, UDIM tiles and a movie frame pass through
        as the image node's source (a buffer carries its own colour space)."""
        for source in ({"buffer": "Paint"}, {"file": "/t/tiles.<UDIM>.png", "tiles": [1001, 1002]},
                       {"file": "/t/clip.mp4", "frame": 4}):
            img = Image("Paint")
            img.colorspace_settings = types.SimpleNamespace(name="sRGB")
            img.engine_file = source

            def b(t):
                d = t.new("ShaderNodeBsdfDiffuse", "D")
                t.link(t.new("ShaderNodeTexImage", "Tex", image=img, interpolation="Cubic").out("Color"), d.inp("Color"))
                return d.out()
            p, w = convert(b)
            self.assertIsNone(w)
            expected = dict(source, node="image", name="Paint", interpolation="Cubic", extension="REPEAT")
            if "buffer" not in source:
                expected["colorspace"] = "sRGB"
            self.assertEqual(p["color"], expected)

    def test_missing_image_stays_magenta_constant(self):
        img = Image("gone.png", filepath="/nope/gone.png", missing=True)

        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(t.new("ShaderNodeTexImage", "Tex", image=img).out("Color"), d.inp("Color"))
            return d.out()
        p, w = keep("missing_image", convert(b))
        self.assertEqual(p["color"], [1.0, 0.0, 1.0])
        self.assertIn("not found", w)

    def test_procedural_and_color_nodes(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            noise = t.new("ShaderNodeTexNoise", "Noise")
            ramp = t.new("ShaderNodeValToRGB", "Ramp", color_ramp=Ramp([(0.2, (1, 0, 0, 1)), (0.8, (0, 0, 1, 1))]))
            t.link(noise.out("Fac"), ramp.inp("Fac"))
            mix = t.new("ShaderNodeMixRGB", "MixRGB", blend_type="MULTIPLY", use_clamp=True)
            t.link(ramp.out("Color"), mix.inp("Color1"))
            grad = t.new("ShaderNodeTexGradient", "Grad", gradient_type="RADIAL")
            tc = t.new("ShaderNodeTexCoord", "TC")
            t.link(tc.out("Object"), grad.inp("Vector"))
            t.link(grad.out("Color"), mix.inp("Color2"))
            inv = t.new("ShaderNodeInvert", "Inv")
            t.link(mix.out(), inv.inp("Color"))
            math = t.new("ShaderNodeMath", "Math", operation="POWER", use_clamp=False)
            t.link(grad.out("Fac"), math.inputs[0])
            t.link(math.out(), d.inp("Roughness"))
            t.link(inv.out(), d.inp("Color"))
            return d.out()
        p, w = keep("procedural", convert(b))
        c = p["color"]
        self.assertEqual(c["node"], "invert")
        self.assertEqual(c["color"]["node"], "mix")
        self.assertEqual(c["color"]["blend_type"], "MULTIPLY")
        self.assertEqual(c["color"]["color1"]["node"], "color_ramp")
        self.assertEqual(c["color"]["color1"]["fac"]["node"], "noise")
        self.assertEqual(c["color"]["color2"]["vector"], {"node": "texture_coordinate", "output": "object"})
        self.assertEqual(p["roughness"]["node"], "math")
        self.assertIsNone(w)  # Blender's 3D noise exactly (engine/src/textures/noise.h), the ramp too

    def test_constant_chains_still_fold(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            hs = t.new("ShaderNodeHueSaturation", "HS")
            hs.inp("Color").default_value = [0.8, 0.2, 0.2, 1.0]
            hs.inp("Saturation").default_value = 0.0
            t.link(hs.out(), d.inp("Color"))
            return d.out()
        p, w = keep("hue_sat_const", convert(b))
        self.assertTrue(all(abs(x - 0.8) < 1e-6 for x in p["color"]))  # desaturated: value kept
        self.assertIsNone(w)

    def test_normal_map_bump_chain_and_vertex_color(self):
        img = Image("n.png")

        def b(t):
            d = t.new("ShaderNodeBsdfPrincipled", "P")
            tex = t.new("ShaderNodeTexImage", "N", image=img)
            nm = t.new("ShaderNodeNormalMap", "NMap", space="TANGENT", uv_map="")
            t.link(tex.out("Color"), nm.inp("Color"))
            bump = t.new("ShaderNodeBump", "Bumpy", invert=True)
            vc = t.new("ShaderNodeVertexColor", "VC", layer_name="")
            t.link(vc.out("Color"), bump.inp("Height"))
            t.link(nm.out(), bump.inp("Normal"))
            t.link(bump.out(), d.inp("Normal"))
            attr = t.new("ShaderNodeVertexColor", "VC2", layer_name="Col")
            t.link(attr.out("Color"), d.inp("Base Color"))
            return d.out()
        p, w = keep("normal_bump", convert(b))
        n = p["normal"]
        self.assertEqual((n["node"], n["invert"]), ("bump", True))
        self.assertEqual(n["normal"]["node"], "normal_map")
        self.assertEqual(n["height"]["node"], "rgb_to_bw")
        self.assertEqual(n["height"]["color"]["layer"], sm.DEFAULT_COLOR_ATTRIBUTE)
        self.assertEqual(p["base_color"], {"node": "vertex_color", "layer": "Col"})
        self.assertIsNone(w)


class TestValueRules(unittest.TestCase):
    """The lowering cache and the colour clamp: a value lowered once as a vector and once as a
    colour keeps both forms; no path lets a negative constant reach a colour input (the engine
    rejects those); a non-finite socket value becomes 0 with a warning naming the node."""

    def _lowerer(self):
        from shaders_map.issues import Issues
        from shaders_map.lowering import _Lowerer
        return _Lowerer(Issues(), image_average, image_file, "surface")

    def _approximated(self, output):
        """An image without a file minus 2 (SUBTRACT): constant and negative, but approximated
        (not folded), so lowered through the cache."""
        from shaders_map.ir import Expr, Const
        img = Image("gone.png", filepath="/nope/gone.png", missing=True)
        tex = Expr("tex_image", "Tex", {}, {"image": img, "output": output})
        if output == "Alpha":
            return Expr("math", "Sub", {"a": tex, "b": Const(2.0)}, {"operation": "SUBTRACT"})
        return Expr("mix_color", "Sub", {"fac": Const(1.0), "a": tex, "b": Const((2.0, 2.0, 2.0))},
                    {"blend_type": "SUBTRACT", "clamp_result": False, "clamp_factor": True})

    def test_cache_keeps_the_colour_flag(self):
        sub = self._approximated("Color")
        low = self._lowerer()
        as_vector = low.value(sub)
        self.assertLess(min(as_vector), 0.0)  # a vector keeps its sign
        self.assertEqual(low.value(sub, True), [0.0, 0.0, 0.0])  # the same IR as a colour: clamped
        self.assertEqual(low.value(sub), as_vector)

    def test_float_constant_into_a_colour_is_clamped(self):
        sub = self._approximated("Alpha")
        self.assertEqual(self._lowerer().value(sub, True), 0.0)  # a float into a colour input
        low = self._lowerer()
        self.assertLess(low.value(sub), 0.0)
        self.assertEqual(low.value(sub, True), 0.0)

    def test_non_finite_socket_values_become_zero_with_a_warning(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            checker = t.new("ShaderNodeTexChecker", "Check")
            checker.inp("Scale").default_value = float("inf")
            checker.inp("Color1").default_value = [float("nan"), 0.5, 0.5, 1.0]
            t.link(checker.out("Color"), d.inp("Color"))
            d.inp("Roughness").default_value = float("-inf")
            return d.out()
        p, w = keep("non_finite", convert(b))
        self.assertEqual(p["color"]["scale"], 0.0)
        self.assertEqual(p["color"]["color1"], [0.0, 0.5, 0.5])
        self.assertEqual(p.get("roughness", 0.0), 0.0)
        self.assertIn("Check", w)
        self.assertIn("Scale", w)
        self.assertIn("not finite", w)
        json.dumps(p, allow_nan=False)  # what the binding sends


class TestWorld(unittest.TestCase):
    def _world(self, build, volume=None):
        t = Tree("W")
        out = t.new("ShaderNodeOutputWorld", "World Output")
        t.link(build(t), out.inp("Surface"))
        if volume is not None:
            t.link(volume(t), out.inp("Volume"))
        return sm.convert_world(World("W", t), image_average=image_average, image_file=image_file)

    def test_environment_file_with_rotation(self):
        img = Image("sky.exr")

        def b(t):
            bg = t.new("ShaderNodeBackground", "Background")
            bg.inp("Strength").default_value = 2.0
            env = t.new("ShaderNodeTexEnvironment", "Sky", image=img)
            mp = t.new("ShaderNodeMapping", "Mapping", vector_type="POINT")
            mp.inp("Rotation").default_value = [0.0, 0.0, 1.5]
            t.link(t.new("ShaderNodeTexCoord", "TC").out("Generated"), mp.inp("Vector"))
            t.link(mp.out(), env.inp("Vector"))
            t.link(env.out("Color"), bg.inp("Color"))
            return bg.out()
        p, w = self._world(b)
        self.assertEqual(p["environment"], {"file": IMG_PATH, "rotation": [0.0, 0.0, 1.5]})
        self.assertEqual(p["strength"], 2.0)
        self.assertIsNone(w)
        keep("world_env", ({"type": "diffuse"}, None))[0]["__world"] = p

    def test_preetham_sky(self):
        def b(t):
            bg = t.new("ShaderNodeBackground", "Background")
            sky = t.new("ShaderNodeTexSky", "Sky", sky_type="PREETHAM", sun_direction=(0.0, 0.6, 0.8), turbidity=3.0)
            t.link(sky.out("Color"), bg.inp("Color"))
            return bg.out()
        p, w = self._world(b)
        self.assertIsNone(w)
        self.assertEqual(p["sky"], {"type": "preetham", "sun_direction": [0.0, 0.6, 0.8], "turbidity": 3.0})
        keep("world_preetham", ({"type": "diffuse"}, None))[0]["__world"] = p

    def test_world_volume(self):
        def b(t):
            return t.new("ShaderNodeBackground", "Background").out()
        p, w = self._world(b, volume=lambda t: t.new("ShaderNodeVolumeScatter", "Fog").out())
        self.assertEqual(p["volume"]["absorption_color"], [1.0, 1.0, 1.0])
        self.assertIsNone(w)


class TestLightFalloff(unittest.TestCase):
    """Light Falloff reads the length of the ray (Cycles' ray length): where a surface emits, the
    engine knows it (the node stays); on the world and in volumes Cycles 3.4 sets it to 0 (exact
    constants); elsewhere in a material it is Strength, named."""

    @staticmethod
    def _falloff(t, output, strength=30.0, smooth=0.0):
        f = t.new("ShaderNodeLightFalloff", "Falloff")
        f.inp("Strength").default_value = strength
        f.inp("Smooth").default_value = smooth
        return f.out(output)

    def test_emission_strength_and_principled_emission(self):
        def b(t):
            em = t.new("ShaderNodeEmission", "Em")
            t.link(self._falloff(t, "Linear"), em.inp("Strength"))
            return em.out()
        p, w = keep("falloff_emission", convert(b))
        self.assertIsNone(w)
        self.assertEqual(p["strength"], {"node": "light_falloff", "output": "LINEAR", "strength": 30.0, "smooth": 0.0})

        def pr(t):
            n = principled(t, Emission=(1.0, 0.5, 0.25))
            t.link(self._falloff(t, "Quadratic", 5.0, smooth=1.5), n.inp("Emission Strength"))
            return n.out()
        p, w = keep("falloff_principled", convert(pr))
        self.assertIsNone(w)
        self.assertEqual(p["emission_strength"]["node"], "light_falloff")
        self.assertEqual(p["emission_strength"]["smooth"], 1.5)

    def test_light_paths_ray_length_is_the_distance_light_travels(self):
        def b(t):
            em = t.new("ShaderNodeEmission", "Em")
            t.link(t.new("ShaderNodeLightPath", "LP").out("Ray Length"), em.inp("Strength"))
            return em.out()
        p, w = keep("ray_length_emission", convert(b))
        self.assertIsNone(w)
        self.assertEqual(p["strength"], {"node": "light_falloff", "output": "LINEAR", "strength": 1.0, "smooth": 0.0})

        def d(t):
            diffuse = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(t.new("ShaderNodeLightPath", "LP").out("Ray Length"), diffuse.inp("Roughness"))
            return diffuse.out()
        p, w = convert(d)
        self.assertEqual(p.get("roughness", 1.0), 1.0)
        self.assertIn("Ray Length outside an emitter", w)

    def test_outside_emission_it_is_strength_named(self):
        def b(t):
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            m = t.new("ShaderNodeMath", "Scale", operation="MULTIPLY", use_clamp=False)
            t.link(self._falloff(t, "Constant", 0.5), m.inputs[0])
            m.inputs[1].default_value = 1.0
            t.link(m.out(), d.inp("Roughness"))
            return d.out()
        p, w = keep("falloff_roughness", convert(b))
        self.assertEqual(p["roughness"], 0.5)
        self.assertIn("Constant falloff", w)

    def test_world_and_volumes_see_a_ray_length_of_zero(self):
        for output, smooth, expect in (("Linear", 0.0, 0.0), ("Constant", 0.0, 0.0), ("Quadratic", 1.0, 0.0),
                                       ("Quadratic", 0.0, 3.0)):
            with self.subTest(output=output, smooth=smooth):
                def b(t):
                    bg = t.new("ShaderNodeBackground", "Background")
                    bg.inp("Color").default_value = [1.0, 1.0, 1.0, 1.0]
                    t.link(self._falloff(t, output, 3.0, smooth), bg.inp("Strength"))
                    return bg.out()
                p, w = TestWorld._world(None, b)
                self.assertIsNone(w)
                self.assertAlmostEqual(max(p["color"]) * p["strength"], expect)

                def vol(t):
                    v = t.new("ShaderNodeVolumePrincipled", "Glow")
                    v.inp("Density").default_value = 0.5
                    t.link(self._falloff(t, output, 3.0, smooth), v.inp("Emission Strength"))
                    return v.out()
                p, w = convert(None, volume=vol)
                self.assertIsNone(w)
                self.assertAlmostEqual(p["volume"].get("emission_strength", 0.0), expect)


class TestMeshNodes(unittest.TestCase):
    """Nodes the engine computes from the hit's triangle: Wireframe, Geometry > Parametric."""

    def test_wireframe_and_parametric(self):
        def b(t):
            wf = t.new("ShaderNodeWireframe", "Wire")
            wf.inp("Size").default_value = 0.05
            em = t.new("ShaderNodeEmission", "Glow")
            t.link(wf.out("Fac"), em.inp("Strength"))
            t.link(t.new("ShaderNodeNewGeometry", "Geo").out("Parametric"), em.inp("Color"))
            return em.out()
        p, w = keep("wireframe_parametric", convert(b))
        self.assertIsNone(w)
        self.assertEqual(p["strength"], {"node": "wireframe", "size": 0.05, "pixel_size": False})
        self.assertEqual(p["color"], {"node": "texture_coordinate", "output": "parametric"})
        p, w = convert(lambda t: _emit(t, t.new("ShaderNodeNewGeometry", "Geo").out("Tangent")))
        self.assertEqual(p["color"], {"node": "texture_coordinate", "output": "tangent"})
        self.assertIsNone(w)
        p, w = convert(_wire_pixels)
        self.assertEqual(p["color"]["pixel_size"], True)
        self.assertIn("Pixel Size widths from the ray's footprint", w)


class TestAmbientOcclusion(unittest.TestCase):
    def test_ao_outputs_and_settings(self):
        def b(t):
            ao = t.new("ShaderNodeAmbientOcclusion", "Occlusion", samples=8, inside=True, only_local=True)
            ao.inp("Distance").default_value = 0.3
            ao.inp("Color").default_value = [0.9, 0.5, 0.1, 1.0]
            em = t.new("ShaderNodeEmission", "Glow")
            t.link(ao.out("Color"), em.inp("Color"))
            t.link(ao.out("AO"), em.inp("Strength"))
            return em.out()
        p, w = keep("ambient_occlusion", convert(b))
        self.assertIsNone(w)
        common = {"node": "ambient_occlusion", "color": [0.9, 0.5, 0.1], "distance": 0.3, "samples": 8, "inside": True,
                  "only_local": True}
        self.assertEqual(p["color"], dict(common, output="color"))
        self.assertEqual(p["strength"], dict(common, output="ao"))

    def test_linked_normal_is_named(self):
        def b(t):
            ao = t.new("ShaderNodeAmbientOcclusion", "Occlusion")
            t.link(t.new("ShaderNodeNewGeometry", "Geo").out("Normal"), ao.inp("Normal"))
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(ao.out("Color"), d.inp("Color"))
            return d.out()
        p, w = convert(b)
        self.assertEqual(p["color"]["node"], "ambient_occlusion")
        self.assertIn("its Normal input ignored", w)


def _emit(t, socket):
    em = t.new("ShaderNodeEmission", "Glow")
    t.link(socket, em.inp("Color"))
    return em.out()


def _wire_pixels(t):
    wf = t.new("ShaderNodeWireframe", "Wire", use_pixel_size=True)
    d = t.new("ShaderNodeBsdfDiffuse", "D")
    t.link(wf.out("Fac"), d.inp("Color"))
    return d.out()


def _mix_by(t, output, a, b, invert=False, name="Mix"):
    """Mix Shader (Fac = Light Path's output [1 - it]) of shader sockets a and b."""
    fac = t.new("ShaderNodeLightPath", "Light Path").out(output)
    if invert:
        m = t.new("ShaderNodeMath", "One minus", operation="SUBTRACT")
        m.inp("Value").default_value = 1.0
        t.link(fac, m.inp("Value_001"))
        fac = m.out()
    mix = t.new("ShaderNodeMixShader", name)
    t.link(fac, mix.inp("Fac"))
    t.link(a, mix.inp("Shader"))
    t.link(b, mix.inp("Shader_001"))
    return mix.out()


def _diffuse(t, color, name="Diffuse"):
    n = t.new("ShaderNodeBsdfDiffuse", name)
    n.inp("Color").default_value = list(color) + [1.0]
    return n.out()


def variants(build, name="M", volume=None):
    t = Tree(name)
    out = t.output()
    t.link(build(t), out.inp("Surface"))
    if volume is not None:
        t.link(volume(t), out.inp("Volume"))
    return sm.convert_material_variants(Material(name, t), image_average=image_average, image_file=image_file)


class TestRayKinds(unittest.TestCase):
    """Light Path's ray types (shaders_map/ray_kinds.py): one material per group of the engine's
    ray kinds that see it alike."""
    REST = ["diffuse", "glossy", "transmission", "shadow", "volume_scatter"]

    def test_camera_ray_splits_camera_from_the_rest(self):
        for invert in (False, True):
            with self.subTest(invert=invert):
                v, w = variants(lambda t: _mix_by(t, "Is Camera Ray", _diffuse(t, (0.8, 0.1, 0.1)),
                                                  t.new("ShaderNodeEmission", "Glow").out(), invert))
                self.assertIsNone(w)
                self.assertEqual([kinds for kinds, _ in v], [["camera"], self.REST])
                seen_by_camera, seen_by_rest = v[0][1], v[1][1]
                if invert:
                    seen_by_camera, seen_by_rest = seen_by_rest, seen_by_camera
                # The mix is gone: each kind sees one shader (a plain diffuse runs no mix code).
                self.assertEqual(seen_by_camera["type"], "emission")
                self.assertEqual(seen_by_rest, {"type": "diffuse", "color": [0.8, 0.1, 0.1]})
        keep("ray_kind_rest", (v[0][1], None))

    def test_shadow_ray_makes_glass_cast_no_shadow(self):
        v, w = variants(lambda t: _mix_by(t, "Is Shadow Ray", t.new("ShaderNodeBsdfGlass", "Glass").out(),
                                          t.new("ShaderNodeBsdfTransparent", "Clear").out()))
        self.assertIsNone(w)
        self.assertEqual([kinds for kinds, _ in v], [["camera", "diffuse", "glossy", "transmission", "volume_scatter"],
                                                     ["shadow"]])
        self.assertEqual(v[0][1]["type"], "glass")
        self.assertEqual(v[1][1]["type"], "transparent")

    def test_one_material_when_the_kinds_see_it_alike(self):
        # Is Camera Ray times 0: every kind sees the diffuse; a depth output is a constant, warned.
        def b(t):
            m = t.new("ShaderNodeMath", "Zero", operation="MULTIPLY")
            t.link(t.new("ShaderNodeLightPath", "LP").out("Is Camera Ray"), m.inp("Value"))
            m.inp("Value_001").default_value = 0.0
            mix = t.new("ShaderNodeMixShader", "Mix")
            t.link(m.out(), mix.inp("Fac"))
            t.link(_diffuse(t, (0.2, 0.3, 0.4)), mix.inp("Shader"))
            t.link(t.new("ShaderNodeEmission", "E").out(), mix.inp("Shader_001"))
            return mix.out()
        v, w = variants(b)
        self.assertEqual(v, [(None, {"type": "diffuse", "color": [0.2, 0.3, 0.4]})])
        self.assertIsNone(w)
        p, w = convert(lambda t: _mix_by(t, "Ray Depth", _diffuse(t, (0.2, 0.3, 0.4)),
                                         t.new("ShaderNodeEmission", "E").out()))
        self.assertIn("Ray Depth is not supported", w)

    def test_kinds_the_engine_cannot_tell_apart_are_named(self):
        # Is Glossy Ray: a refraction is glossy, a translucency diffuse; both are transmission rays.
        v, w = variants(lambda t: _mix_by(t, "Is Glossy Ray", _diffuse(t, (0.5, 0.5, 0.5)),
                                          t.new("ShaderNodeEmission", "E").out()))
        self.assertIn("transmission rays are refractions, translucency or singular reflections alike", w)
        self.assertEqual([kinds for kinds, _ in v], [["camera", "diffuse", "shadow", "volume_scatter"],
                                                     ["glossy", "transmission"]])
        # Is Volume Scatter Ray (Blender 4): scattering rays meet the diffuse rays' copy.
        # A volume inside: no copies (each would be a boundary), the diffuse rays' look, warned.
        v, w = variants(lambda t: _mix_by(t, "Is Camera Ray", _diffuse(t, (0.5, 0.5, 0.5)),
                                          t.new("ShaderNodeEmission", "E").out()),
                        volume=lambda t: t.new("ShaderNodeVolumeAbsorption", "Ink").out())
        self.assertEqual(len(v), 1)
        self.assertEqual(v[0][1]["type"], "diffuse")
        self.assertIn("with a volume: shaded as diffuse rays see it", w)

    def test_bevel_is_one_look_for_every_ray(self):
        # Bevel into a Principled BSDF's Normal, a Bump chained on it, a normal map into its
        # own Normal: one material (no copies per ray kind: Cycles skips the Bevel after blurry
        # bounces, the engine keeps it, README), the bevel a normal node.
        for bump in (False, True):
            with self.subTest(bump=bump):
                def b(t):
                    bevel = t.new("ShaderNodeBevel", "Bevel", samples=8)
                    bevel.inp("Radius").default_value = 0.02
                    bsdf = t.new("ShaderNodeBsdfPrincipled", "P")
                    n = bevel.out()
                    if bump:
                        bp = t.new("ShaderNodeBump", "Bump")
                        t.link(t.new("ShaderNodeTexNoise", "Noise").out("Fac"), bp.inp("Height"))
                        t.link(n, bp.inp("Normal"))
                        n = bp.out()
                    t.link(n, bsdf.inp("Normal"))
                    return bsdf.out()
                v, w = variants(b)
                self.assertIsNone(w)
                self.assertEqual(len(v), 1)
                self.assertIsNone(v[0][0])
                normal = v[0][1]["normal"]
                self.assertEqual(normal["normal"] if bump else normal, {"node": "bevel", "radius": 0.02, "samples": 8})
                keep("bevel_bump" if bump else "bevel", (v[0][1], None))

        def mapped(t):
            bevel = t.new("ShaderNodeBevel", "Bevel", samples=200)
            nm = t.new("ShaderNodeNormalMap", "Map")
            t.link(nm.out(), bevel.inp("Normal"))
            d = t.new("ShaderNodeBsdfDiffuse", "D")
            t.link(bevel.out(), d.inp("Normal"))
            return d.out()
        p, w = convert(mapped)
        self.assertEqual(p["normal"]["node"], "bevel")
        self.assertEqual(p["normal"]["samples"], 128)
        self.assertIn("Samples kept to 0..128", w)
        self.assertEqual(p["normal"]["normal"]["node"], "normal_map")
        keep("bevel_mapped", (p, w))

    def test_convert_material_gives_the_diffuse_rays_look(self):
        p, w = convert(lambda t: _mix_by(t, "Is Camera Ray", _diffuse(t, (0.8, 0.1, 0.1)),
                                         t.new("ShaderNodeEmission", "Glow").out()))
        self.assertEqual(p["type"], "diffuse")
        self.assertIn("one object copy per look", w)

    def test_world_camera_ray(self):
        img = Image("sky.exr")

        def b(t):
            lit = t.new("ShaderNodeBackground", "Lighting")
            env = t.new("ShaderNodeTexEnvironment", "HDRI", image=img)
            t.link(env.out("Color"), lit.inp("Color"))
            backdrop = t.new("ShaderNodeBackground", "Backdrop")
            backdrop.inp("Color").default_value = [0.1, 0.2, 0.9, 1.0]
            backdrop.inp("Strength").default_value = 2.0
            return _mix_by(t, "Is Camera Ray", lit.out(), backdrop.out())
        p, w = TestWorld._world(None, b)
        self.assertIsNone(w)
        self.assertEqual(p["environment"], {"file": IMG_PATH})
        cam = p["camera"]
        self.assertEqual(sorted(cam), ["color", "strength"])
        for got, want in zip(cam["color"], (0.2, 0.4, 1.8)):
            self.assertAlmostEqual(got * cam["strength"], want)
        keep("world_camera", ({"type": "diffuse"}, None))[0]["__world"] = p
        # Is Diffuse Ray: 0, as next-event estimation sees the world, warned; Is Shadow Ray: 0.
        p, w = TestWorld._world(None, lambda t: _mix_by(t, "Is Diffuse Ray", b(t), t.new("ShaderNodeBackground",
                                                                                         "Black").out()))
        self.assertIn("Is Diffuse Ray in the World is 0 here", w)
        self.assertIn("camera", p)
        p, w = TestWorld._world(None, lambda t: _mix_by(t, "Is Shadow Ray", t.new("ShaderNodeBackground", "G").out(),
                                                        t.new("ShaderNodeBackground", "Black").out()))
        self.assertIsNone(w)
        self.assertNotIn("camera", p)


@unittest.skipIf(LIBRARY is None, "the engine library is not built (RDV_TEST_LIBRARY)")
class TestZEngineAcceptsLowering(unittest.TestCase):
    """Runs last (class name order): every material kept above, on a box each, through the
    add-on's binding as Blender's renders use it (one process: a command-line renderer per
    material cost 0.5 s of loading each, 19 of this file's 22 s)."""

    def test_engine_renders_every_lowered_material(self):
        import numpy as np
        from test_export_helpers import load_addon
        load_addon()
        from rendezvous import binding
        lib = binding.load(LIBRARY)
        corners = np.array([[x, y, z] for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)], np.float32)
        faces = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
                          [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]], np.uint32)
        identity = np.eye(4, dtype=np.float32)
        self.assertGreater(len(ENGINE_CASES), 10)
        for name, (params, _w) in sorted(ENGINE_CASES.items()):
            with self.subTest(name):
                world = params.pop("__world", None) if isinstance(params, dict) else None
                mat = dict(params) if world is None else {"type": "diffuse"}
                if world is None:
                    world = {"color": [0.2, 0.2, 0.2]}
                    if name.startswith("volume"):
                        world["volume"] = {"density": 0.01}
                with binding.Scene(lib) as sc:
                    # A material the engine cannot read raises here, naming it (EngineError).
                    m = sc.add_material("m", mat)
                    sc.add_instance(sc.add_mesh("box", corners, faces, default_material=m), identity)
                    sc.add_light("l", {"type": "point", "position": [0, -2, 3], "power": 200})
                    sc.set_world(world)
                    sc.set_camera({"type": "perspective", "transform": {"look_at": {"from": [0, -3, 1], "to": [0, 0, 0]}}})
                    sc.commit()
                    # A texture the engine cannot read renders magenta with a warning.
                    self.assertFalse([w for w in sc.messages() if "magenta" in w], json.dumps(mat))
                    with binding.Session(sc, {"width": 16, "height": 16, "samples": 2, "threads": 1}) as s:
                        s.start()
                        s.wait()
                        self.assertTrue(s.progress().finished, name)
                        out = np.zeros(16 * 16 * 4, np.float32)
                        s.read_film(binding.PASS_COMBINED, 0, 0, 16, 16, out)
                        self.assertTrue(np.isfinite(out).all(), name)


def tearDownModule():
    import shutil
    shutil.rmtree(TMP, ignore_errors=True)


if __name__ == "__main__":
    unittest.main()
