"""Export helpers of the add-on with fake Blender data (no bpy): lights in Blender's
units, camera, render settings and halt conditions, the JSON dump sink, the binding's
library search.  Needs numpy (Debian's python3-numpy)."""

import importlib.util
import json
import math
import os
import sys
import tempfile
import types
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

try:
    import numpy as np
except ImportError:  # pragma: no cover
    np = None


def load_addon():
    """Imports addon/ as the package `rendezvous` (source-tree layout, no bpy needed)."""
    if "rendezvous" in sys.modules:
        return sys.modules["rendezvous"]
    spec = importlib.util.spec_from_file_location("rendezvous", os.path.join(ROOT, "addon", "__init__.py"),
                                                  submodule_search_locations=[os.path.join(ROOT, "addon")])
    mod = importlib.util.module_from_spec(spec)
    sys.modules["rendezvous"] = mod
    spec.loader.exec_module(mod)
    return mod


def ns(**kw):
    return types.SimpleNamespace(**kw)


def translation(x, y, z, scale=(1.0, 1.0, 1.0)):
    return [scale[0], 0, 0, x, 0, scale[1], 0, y, 0, 0, scale[2], z, 0, 0, 0, 1]


@unittest.skipIf(np is None, "numpy not available")
class TestLights(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        load_addon()
        from rendezvous.export import lights
        cls.lights = lights

    def params(self, light, m16=None):
        warnings = []
        p = self.lights.light_params(light, m16 or translation(1, 2, 3), "L", warnings.append)
        return p, warnings

    def test_point(self):
        p, w = self.params(ns(type="POINT", color=(1, 0.5, 0.25), energy=100.0, shadow_soft_size=0.2))
        self.assertEqual(p["type"], "point")
        self.assertEqual(p["power"], 100.0)
        self.assertAlmostEqual(p["radius"], 0.2)
        self.assertEqual(p["color"], [1.0, 0.5, 0.25])
        self.assertEqual(p["transform"][3], 1.0)
        self.assertEqual(w, [])

    def test_spot(self):
        p, w = self.params(ns(type="SPOT", color=(1, 1, 1), energy=50.0, shadow_soft_size=0.0,
                              spot_size=math.radians(45), spot_blend=0.2))
        self.assertEqual(p["type"], "spot")
        self.assertAlmostEqual(p["spot_size"], math.radians(45))
        self.assertAlmostEqual(p["spot_blend"], 0.2)

    def test_sun_strength(self):
        p, w = self.params(ns(type="SUN", color=(1, 1, 1), energy=3.0, angle=0.1))
        self.assertEqual(p, {"type": "sun", "color": [1.0, 1.0, 1.0], "transform": p["transform"],
                             "strength": 3.0, "angle": 0.1})

    def test_area_scale_goes_into_size(self):
        light = ns(type="AREA", color=(1, 1, 1), energy=10.0, shape="SQUARE", size=0.5, size_y=9.0)
        p, w = self.params(light, translation(0, 0, 2, scale=(2.0, 3.0, 1.0)))
        self.assertEqual(p["shape"], "rectangle")  # a square scaled non-uniformly
        self.assertAlmostEqual(p["size"], 1.0)
        self.assertAlmostEqual(p["size_y"], 1.5)
        self.assertAlmostEqual(p["transform"][0], 1.0)  # the transform has no scale left
        self.assertAlmostEqual(p["transform"][5], 1.0)

    def test_area_disk_rectangle(self):
        p, w = self.params(ns(type="AREA", color=(1, 1, 1), energy=10.0, shape="ELLIPSE", size=1.0, size_y=0.5))
        self.assertEqual((p["shape"], p["size"], p["size_y"]), ("ellipse", 1.0, 0.5))

    def test_area_spread(self):
        """Spread goes to the engine in radians, and only when narrower than Blender's 180 degrees."""
        light = ns(type="AREA", color=(1, 1, 1), energy=10.0, shape="SQUARE", size=1.0, size_y=1.0, spread=0.5)
        p, w = self.params(light)
        self.assertAlmostEqual(p["spread"], 0.5)
        self.assertEqual(w, [])
        light.spread = 3.1415927
        self.assertNotIn("spread", self.params(light)[0])


@unittest.skipIf(np is None, "numpy not available")
class TestRayVisibility(unittest.TestCase):
    """Object, light and world ray visibility: only what differs from the engine's defaults."""

    def setUp(self):
        load_addon()
        import rendezvous.export.visibility as visibility
        self.v = visibility

    def test_objects(self):
        seen = ns(visible_camera=True, visible_diffuse=True, visible_glossy=True, visible_transmission=True,
                  visible_volume_scatter=True, visible_shadow=True)
        self.assertEqual(self.v.object_visibility(seen), {})
        hidden = ns(**{**vars(seen), "visible_camera": False, "visible_shadow": False})
        self.assertEqual(self.v.object_visibility(hidden), {"camera": False, "shadow": False})

    def test_lights(self):
        lamp = ns(visible_camera=False, visible_diffuse=True, visible_glossy=False, visible_transmission=True,
                  visible_volume_scatter=True, visible_shadow=False)  # the object's shadow is not Cycles' setting
        self.assertEqual(self.v.light_visibility(lamp, ns(cycles=ns(cast_shadow=True))), {"glossy": False})
        lamp.visible_camera = True
        self.assertEqual(self.v.light_visibility(lamp, ns(cycles=ns(cast_shadow=False))),
                         {"glossy": False, "camera": True, "shadow": False})

    def test_copies_per_look(self):
        # An object whose materials look different to camera rays: the copy the camera sees, and
        # the rest, each hidden from the other's kinds and from what the object hides.
        ob = ns(visible_camera=True, visible_diffuse=True, visible_glossy=False, visible_transmission=True,
                visible_volume_scatter=True, visible_shadow=True)
        self.assertEqual(self.v.object_visibility(ob, ["camera"]),
                         {"diffuse": False, "glossy": False, "transmission": False, "shadow": False,
                          "volume_scatter": False})
        rest = self.v.object_visibility(ob, ["diffuse", "glossy", "transmission", "shadow", "volume_scatter"])
        self.assertEqual(rest, {"camera": False, "glossy": False})
        self.assertFalse(self.v.hidden_from_all(rest))
        self.assertTrue(self.v.hidden_from_all(self.v.object_visibility(ob, ["glossy"])))
        from rendezvous.export.materials import ray_kind_cells
        camera_split = [(["camera"], 7), (["diffuse", "glossy", "transmission", "shadow", "volume_scatter"], 8)]
        shadow_split = [(["camera", "diffuse", "glossy", "transmission", "volume_scatter"], 3), (["shadow"], 4)]
        self.assertEqual(ray_kind_cells([[(None, 1)], [(None, 2)]]), [(None, [1, 2])])
        self.assertEqual(ray_kind_cells([camera_split, [(None, 2)], shadow_split]),
                         [(["camera"], [7, 2, 3]), (["diffuse", "glossy", "transmission", "volume_scatter"], [8, 2, 3]),
                          (["shadow"], [8, 2, 4])])

    def test_world(self):
        self.assertEqual(self.v.world_visibility(None), {})
        w = ns(cycles_visibility=ns(camera=False, diffuse=True, glossy=True, transmission=True, scatter=False,
                                    shadow=False))
        self.assertEqual(self.v.world_visibility(w), {"camera": False, "volume_scatter": False})


@unittest.skipIf(np is None, "numpy not available")
class TestObjectInfo(unittest.TestCase):
    """What an Object Info node reads, exported with each instance as Cycles takes it."""

    def setUp(self):
        load_addon()
        import rendezvous.export as export
        self.export = export

    def test_random_ids(self):
        # An object's: lookup3 of its name's hash (Cycles: hash_uint2(hash_string(name), 0)); the
        # Random Cycles rendered for 'Tile0' in blender.brightness.object_info was 0.986.
        self.assertAlmostEqual(self.export.name_random_id("Tile0") / 0xFFFFFFFF, 0.9862349, places=6)
        self.assertAlmostEqual(self.export.name_random_id("Tile1") / 0xFFFFFFFF, 0.7699500, places=6)
        ob = ns(name="Tile0", pass_index=3, color=(1.0, 0.5, 0.25, 1.0), is_holdout=False, is_shadow_catcher=False,
                visible_camera=True, visible_diffuse=True, visible_glossy=True, visible_transmission=True,
                visible_volume_scatter=True, visible_shadow=True)
        s = self.export.SceneExporter.object_settings(ob)
        self.assertEqual(s["random_id"], self.export.name_random_id("Tile0"))
        self.assertEqual((s["pass_index"], s["color"]), (3, [1.0, 0.5, 0.25, 1.0]))
        # An instance's: the depsgraph's random_id, a signed int made unsigned.
        s = self.export.SceneExporter.object_settings(ob, ns(is_instance=True, random_id=-2))
        self.assertEqual(s["random_id"], 0xFFFFFFFE)
        ob.color = (1.0, 1.0, 1.0, 1.0)
        self.assertNotIn("color", self.export.SceneExporter.object_settings(ob))


class TestObjectAttributes(unittest.TestCase):
    """What Attribute nodes of type Object / Instancer read, looked up as Cycles does."""

    @classmethod
    def setUpClass(cls):
        load_addon()
        from rendezvous.export import object_attributes
        cls.oa = object_attributes

    class Block(dict):
        """A stand-in ID: custom properties by name, RNA paths from `rna`."""
        def __init__(self, props=None, rna=None, **kw):
            super().__init__(props or {})
            self.rna = rna or {}
            self.__dict__.update(kw)

        def path_resolve(self, name):
            if name not in self.rna:
                raise ValueError("could not be resolved")
            return self.rna[name]

    def test_lookup_order_and_values(self):
        B = self.Block
        mesh = B({"tint": (0.1, 0.2, 0.3), "level": 7})
        ob = B({"tint": (0.9, 0.8, 0.7, 0.5), "name": "not a number"}, rna={"color": (0.2, 0.4, 0.6, 1.0)}, data=mesh)
        value = self.oa.attribute_value
        self.assertEqual(value(ob, None, "OBJECT", "tint"), [0.9, 0.8, 0.7, 0.5])  # the object before its data
        self.assertEqual(value(ob, None, "OBJECT", "level"), [7.0, 7.0, 7.0, 1.0])  # then the data; n is (n, n, n, 1)
        self.assertEqual(value(ob, None, "OBJECT", "color"), [0.2, 0.4, 0.6, 1.0])  # an RNA path
        self.assertIsNone(value(ob, None, "OBJECT", "name"))  # text is not a value
        self.assertIsNone(value(ob, None, "OBJECT", "missing"))
        parent = B({"tint": (1.0, 0.0, 0.0)})
        inst = types.SimpleNamespace(is_instance=True, particle_system=None, parent=parent)
        self.assertEqual(value(ob, inst, "INSTANCER", "tint"), [1.0, 0.0, 0.0, 1.0])  # the instancer first
        self.assertEqual(value(ob, inst, "OBJECT", "tint"), [0.9, 0.8, 0.7, 0.5])
        self.assertEqual(value(ob, inst, "INSTANCER", "level"), [7.0, 7.0, 7.0, 1.0])  # then the object's own
        params = self.oa.instance_attributes(ob, inst, {("OBJECT", "tint"), ("INSTANCER", "tint"), ("OBJECT", "x")})
        self.assertEqual(params, {"object_attributes": {"tint": [0.9, 0.8, 0.7, 0.5]},
                                  "instancer_attributes": {"tint": [1.0, 0.0, 0.0, 1.0]}})


class TestShaderAovPasses(unittest.TestCase):
    """View Layer > Shader AOV: registered as Cycles registers them, the session's "aovs" in the
    same order (the engine's pass of AOV k is its colour or value range + k)."""

    def test_passes_and_settings(self):
        load_addon()
        # engine/passes.py alone: the engine package's __init__ needs bpy.
        if "rendezvous.engine" not in sys.modules:
            package = types.ModuleType("rendezvous.engine")
            package.__path__ = [os.path.join(ROOT, "addon", "engine")]
            sys.modules["rendezvous.engine"] = package
        spec = importlib.util.spec_from_file_location("rendezvous.engine.passes",
                                                      os.path.join(ROOT, "addon", "engine", "passes.py"))
        passes = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(passes)
        from rendezvous import binding
        aovs = [ns(name="mask", type="COLOR", is_valid=True), ns(name="dup", type="VALUE", is_valid=False),
                ns(name="depth", type="VALUE", is_valid=True)]
        layer = ns(aovs=aovs, pass_alpha_threshold=0.5)
        wanted = passes.enabled_passes(layer, ns())
        self.assertIn(("mask", binding.PASS_AOV_COLOR_FIRST, 4, "RGBA", "COLOR"), wanted)
        self.assertIn(("depth", binding.PASS_AOV_VALUE_FIRST + 1, 1, "X", "VALUE"), wanted)
        self.assertNotIn("dup", [w[0] for w in wanted])
        warnings = []
        settings = passes.light_pass_settings(layer, ns(), "path", warnings.append)
        self.assertEqual(settings["aovs"], [{"name": "mask", "type": "color"}, {"name": "depth", "type": "value"}])
        many = ns(aovs=[ns(name="a%d" % k, type="COLOR", is_valid=True) for k in range(20)])
        self.assertEqual(len(passes.light_pass_settings(many, ns(), "path", warnings.append)["aovs"]), 16)
        self.assertIn("a16", warnings[-1])


class TestCameraSettings(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        load_addon()

    def cam(self, **kw):
        dof = ns(use_dof=kw.pop("use_dof", False), aperture_fstop=2.0, focus_object=None, focus_distance=4.0,
                 aperture_blades=6, aperture_rotation=0.1, aperture_ratio=1.0)
        data = ns(type=kw.pop("type", "PERSP"), lens=35.0, sensor_width=36.0, sensor_height=24.0, sensor_fit="AUTO",
                  shift_x=0.1, shift_y=-0.2, clip_start=0.01, clip_end=500.0, ortho_scale=7.0, dof=dof)
        rows = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 5], [0, 0, 0, 1]]
        return ns(data=data, name="Camera", matrix_world=rows)

    def test_perspective_and_dof(self):
        from rendezvous.export.camera import camera_params
        ob = self.cam(use_dof=True)
        p = camera_params(ob, print)
        self.assertEqual(p["type"], "perspective")
        self.assertEqual((p["focal_length"], p["shift_x"], p["shift_y"]), (35.0, 0.1, -0.2))
        self.assertAlmostEqual(p["aperture_radius"], 35e-3 / 4.0)
        self.assertEqual(p["focus_distance"], 4.0)
        self.assertEqual(p["transform"][11], 5.0)

    def test_ortho(self):
        from rendezvous.export.camera import camera_params
        p = camera_params(self.cam(type="ORTHO"), print)
        self.assertEqual((p["type"], p["ortho_scale"]), ("orthographic", 7.0))
        self.assertNotIn("aperture_radius", p)

    def render(self, **kw):
        r = ns(resolution_x=200, resolution_y=100, resolution_percentage=50, use_border=False, border_min_x=0.0,
               border_max_x=1.0, border_min_y=0.0, border_max_y=1.0, pixel_aspect_x=1.0, pixel_aspect_y=1.0)
        for k, v in kw.items():
            setattr(r, k, v)
        return r

    def props(self, **kw):
        p = ns(integrator="PATH", samples=64, time_limit=0.0, max_bounces=8, seed=5, use_animated_seed=False,
               clamp=0.0, threads=0)
        for k, v in kw.items():
            setattr(p, k, v)
        return p

    def test_settings_resolution_seed_halt(self):
        from rendezvous.export.settings import session_settings
        scene = ns(render=self.render(), frame_current=7)
        s = session_settings(scene, self.props(use_animated_seed=True, integrator="BDPT"))
        self.assertEqual((s["width"], s["height"], s["samples"], s["seed"], s["integrator"]), (100, 50, 64, 12, "bdpt"))
        self.assertNotIn("time_limit", s)
        self.assertEqual(s["mis"], "power")
        s = session_settings(scene, self.props(integrator="BDPT", bdpt_mis="LAFORTUNE_WILLEMS"))
        self.assertEqual(s["mis"], "lafortune_willems")
        s = session_settings(scene, self.props(integrator="MMLT", mlt_large_step=0.5, mlt_bootstrap=2, mlt_chains=64,
                                               mlt_step_size=0.02, mlt_target="LUMINANCE"))
        self.assertEqual((s["integrator"], s["mlt_large_step"], s["mlt_bootstrap"], s["mlt_chains"],
                          s["mlt_step_size"], s["mlt_target"]), ("mmlt", 0.5, 2, 64, 0.02, "luminance"))
        s = session_settings(scene, self.props(integrator="PSSMLT", mlt_large_step=0.3, mlt_bootstrap=1, mlt_chains=256,
                                               mlt_step_size=0.01, mlt_target="RELATIVE"))
        self.assertEqual((s["integrator"], s["mlt_target"]), ("pssmlt", "relative"))
        s = session_settings(scene, self.props(integrator="MLT", mlt_large_step=0.2, mlt_bootstrap=1, mlt_chains=128,
                                               mlt_step_size=0.01, mlt_target="LUMINANCE"))
        self.assertEqual((s["integrator"], s["mlt_large_step"], s["mlt_chains"]), ("mlt", 0.2, 128))
        self.assertEqual(s["mlt_mutations"], {"bidirectional": 1.0, "lens": 1.0, "propagation": 1.0, "scattering": 1.0,
                                              "caustic": 1.0, "multi_chain": 1.0, "lens_subpath": 1.0})
        s = session_settings(scene, self.props(integrator="MLT", mlt_large_step=0.2, mlt_bootstrap=1, mlt_chains=128,
                                               mlt_step_size=0.01, mlt_target="LUMINANCE", mlt_mutation_propagation=3.0,
                                               mlt_keep_distances=0.8, mlt_equiangular=0.25, mlt_direct_samples=0))
        self.assertEqual(s["mlt_mutations"]["propagation"], 3.0)
        self.assertAlmostEqual(s["mlt_keep_distances"], 0.8)
        self.assertAlmostEqual(s["mlt_equiangular"], 0.25)
        self.assertEqual(s["mlt_direct_samples"], 0)
        # Target "Automatic": none sent, each integrator's own (relative; mlt luminance).
        s = session_settings(scene, self.props(integrator="MLT", mlt_large_step=0.2, mlt_bootstrap=1, mlt_chains=128,
                                               mlt_step_size=0.01, mlt_target="DEFAULT"))
        self.assertNotIn("mlt_target", s)
        s = session_settings(scene, self.props(samples=0, time_limit=0.0))
        self.assertNotIn("mis", s)  # path tracing has no strategies to weight
        self.assertNotIn("mlt_chains", s)
        self.assertGreater(s["samples"], 0)  # a render always halts
        s = session_settings(scene, self.props(samples=0, time_limit=2.5))
        self.assertEqual(s["time_limit"], 2.5)
        self.assertNotIn("samples", s)

    def test_auto_integrator_settings(self):
        from rendezvous.export.settings import session_settings, SettingsError
        scene = ns(render=self.render(), frame_current=1)
        mlt = dict(mlt_large_step=0.3, mlt_bootstrap=1, mlt_chains=256, mlt_step_size=0.01, mlt_target="RELATIVE")
        s = session_settings(scene, self.props(integrator="AUTO", samples=0, time_limit=30.0, **mlt))
        # Whichever it picks gets the user's settings for it.
        self.assertEqual((s["integrator"], s["time_limit"], s["mis"], s["mlt_chains"]), ("auto", 30.0, "power", 256))
        with self.assertRaises(SettingsError) as caught:
            session_settings(scene, self.props(integrator="AUTO", time_limit=0.0, **mlt))
        self.assertIn("Time Limit", str(caught.exception))

    def test_path_space_mlt_takes_limits_but_no_clamps(self):
        from rendezvous.export.settings import light_paths_for
        cycles_defaults = {"max_bounces": 13, "diffuse_bounces": 4, "glossy_bounces": 4, "clamp_indirect": 10.0,
                           "filter_glossy": 1.0}
        warnings = []
        self.assertEqual(light_paths_for("mlt", cycles_defaults, warnings.append),
                         {"max_bounces": 13, "diffuse_bounces": 4, "glossy_bounces": 4, "filter_glossy": 1.0})
        self.assertEqual(len(warnings), 1)
        self.assertIn("clamps (clamp_indirect)", warnings[0])
        self.assertEqual(light_paths_for("mlt", {"max_bounces": 13, "caustics_refractive": False,
                                                 "filter_glossy": 1.0}, warnings.append),
                         {"max_bounces": 13, "caustics_refractive": False, "filter_glossy": 1.0})
        self.assertEqual(len(warnings), 1)
        for integrator in ("path", "bdpt", "pssmlt", "mmlt"):  # Filter Glossy included
            self.assertEqual(light_paths_for(integrator, cycles_defaults, warnings.append), cycles_defaults)
        self.assertEqual(light_paths_for("mlt", {"max_bounces": 13}, warnings.append), {"max_bounces": 13})
        self.assertEqual(len(warnings), 1)

    def test_auto_choice_text(self):
        from rendezvous.export.settings import auto_choice_text
        self.assertEqual(auto_choice_text({}), "")
        self.assertEqual(auto_choice_text({"auto": {"integrator": None, "pilots": []}}), "Automatic: pilots running")
        text = auto_choice_text({"auto": {"integrator": "bdpt", "pilot_seconds": 0.61, "pilots": [
            {"integrator": "path", "efficiency": 24.0, "rel_mse": 0.555, "spp": 15},
            {"integrator": "bdpt", "efficiency": 66.6, "rel_mse": 0.2, "spp": 7}]}})
        self.assertIn("Automatic chose Bidirectional after 0.6 s of pilots", text)
        self.assertIn("Path Tracing 24/s (relMSE 0.56, 15 spp)", text)
        text = auto_choice_text({"auto": {"integrator": "path", "pilot_seconds": 0.2, "pilots": [
            {"integrator": "path", "efficiency": 24.0, "rel_mse": 0.555, "spp": 15}],
            "left_out": ["mlt: Light Paths clamps cap one sample's estimate"]}})
        self.assertIn("; Metropolis (Path Space) left out: Light Paths clamps cap one sample's estimate", text)

    def test_noise_target_settings(self):
        from rendezvous.export.settings import session_settings, SettingsError
        scene = ns(render=self.render(), frame_current=1)
        self.assertNotIn("noise_target", session_settings(scene, self.props()))  # props without the field
        s = session_settings(scene, self.props(samples=0, noise_target=0.002, use_pass_noise=True))
        self.assertEqual((s["noise_target"], s["noise_pass"]), (0.002, True))
        self.assertNotIn("samples", s)  # the target alone halts
        for bad in (-0.001, float("nan"), float("inf")):
            with self.assertRaises(SettingsError) as caught:
                session_settings(scene, self.props(noise_target=bad))
            self.assertIn("noise_target", str(caught.exception))

    def test_adaptive_sampling_settings(self):
        from rendezvous.export.settings import session_settings
        scene = ns(render=self.render(), frame_current=1)
        self.assertNotIn("adaptive_sampling", session_settings(scene, self.props()))  # props without the field
        s = session_settings(scene, self.props(use_adaptive_sampling=True, adaptive_threshold=0.02,
                                               adaptive_min_samples=32))
        self.assertEqual((s["adaptive_sampling"], s["adaptive_threshold"], s["adaptive_min_samples"]), (True, 0.02, 32))
        # Metropolis spreads its mutations by brightness itself: the setting does not apply.
        s = session_settings(scene, self.props(integrator="PSSMLT", use_adaptive_sampling=True, adaptive_threshold=0.02,
                                               adaptive_min_samples=32, mlt_large_step=0.3, mlt_bootstrap=1, mlt_target="RELATIVE",
                                               mlt_chains=256, mlt_step_size=0.01))
        self.assertNotIn("adaptive_sampling", s)

    def test_farm_part_settings(self):
        from rendezvous.export.settings import session_settings, part_output_path, scene_hash
        scene = ns(render=self.render(), frame_current=3)
        self.assertNotIn("sample_offset", session_settings(scene, self.props()))  # props without the field
        s = session_settings(scene, self.props(sample_offset=256))
        self.assertEqual((s["sample_offset"], s["samples"]), (256, 64))
        self.assertNotIn("sample_offset", session_settings(scene, self.props(sample_offset=0)))
        self.assertEqual(part_output_path("/farm/part_####.exr", 7), "/farm/part_0007.exr")
        self.assertEqual(part_output_path("/farm/f#_p#.exr", 12), "/farm/f12_p12.exr")
        self.assertEqual(part_output_path("/farm/part.exr", 7), "/farm/part.exr")
        with tempfile.TemporaryDirectory() as d:
            blend = os.path.join(d, "a.blend")
            with open(blend, "wb") as f:
                f.write(b"BLENDER-v304 one")
            h1 = scene_hash(blend, "Scene", 1)
            self.assertEqual(h1, scene_hash(blend, "Scene", 1))
            self.assertNotEqual(h1, scene_hash(blend, "Scene", 2))  # another frame is another image
            with open(blend, "wb") as f:
                f.write(b"BLENDER-v304 two")
            self.assertNotEqual(h1, scene_hash(blend, "Scene", 1))
        self.assertEqual(scene_hash("", "Scene", 1), "blend:unsaved:Scene:frame1")

    def test_farm_submit_scripts(self):
        from rendezvous.farm import submit
        self.assertEqual(submit.parse_frames("1-3,7"), [1, 2, 3, 7])
        with self.assertRaises(ValueError):
            submit.parse_frames("5-2")
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "scene.json")
            with open(scene, "w") as f:
                f.write("{}")
            args = submit.parse_args([scene, "--split", "3", "--samples", "16", "--out", os.path.join(d, "farm"),
                                      "--renderer", "/opt/rdv/rendezvous", "--dry-run"])
            self.assertEqual(submit.submit(args), ("DRYRUN", "DRYRUN"))
            task = open(os.path.join(d, "farm", "slurm", "task.sh")).read()
            self.assertIn("2) cmd=(/opt/rdv/rendezvous %s --samples 16 --sample-offset 32" % scene, task)
            self.assertIn("for attempt in 1 2", task)
            merge = open(os.path.join(d, "farm", "slurm", "merge.sh")).read()
            self.assertIn("/opt/rdv/rendezvous merge %s/farm/parts/part_0001_*.exr --samples 48" % d, merge)
            with self.assertRaises(ValueError):
                submit.submit(submit.parse_args([os.path.join(d, "absent.json"), "--samples", "4", "--out", d,
                                                 "--dry-run"]))

    def test_filter_width(self):
        from rendezvous.export.settings import session_settings
        s = session_settings(ns(render=self.render(), frame_current=1), self.props())
        self.assertNotIn("filter_width", s)  # no filter_size: the engine's default, Blender's 1.5 px
        s = session_settings(ns(render=self.render(filter_size=2.5), frame_current=1), self.props())
        self.assertEqual(s["filter_width"], 2.5)  # Blender's Film > Pixel Filter width

    def test_border_rows_from_top(self):
        from rendezvous.export.settings import session_settings, border_rect
        r = self.render(use_border=True, border_min_x=0.25, border_max_x=0.75, border_min_y=0.0, border_max_y=0.5)
        self.assertEqual(border_rect(r, 100, 50), (25, 25, 50, 25))  # bottom half = rows 25..49 from the top
        s = session_settings(ns(render=r, frame_current=1), self.props())
        self.assertEqual(s["border"], [25, 25, 75, 50])


@unittest.skipIf(np is None, "numpy not available")
class TestDumpSink(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        load_addon()

    def fill(self, sink):
        red = sink.add_material("red", {"type": "diffuse", "color": [1, 0, 0]})
        blue = sink.add_material("blue", {"type": "diffuse", "color": [0, 0, 1]})
        pos = np.array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], np.float32)
        idx = np.array([0, 1, 2, 0, 2, 3], np.uint32)
        m = sink.add_mesh("quad", pos, idx, material_ids=np.array([blue, red], np.uint32))
        sink.add_instance(m, translation(0, 0, 0))
        sink.add_instance(m, translation(2, 0, 0))
        sink.add_light("sun", {"type": "sun", "strength": 2.0})
        sink.set_world({"color": [0.1, 0.1, 0.1], "strength": 1.0})
        sink.set_camera({"type": "perspective"})
        return sink.document({"width": 8, "height": 8, "samples": 1})

    def test_inline(self):
        from rendezvous.export.dump import JsonSink
        doc = json.loads(json.dumps(self.fill(JsonSink())))
        mesh = doc["meshes"][0]
        self.assertEqual(mesh["materials"], ["red", "blue"])
        self.assertEqual(mesh["material_indices"], [1, 0])
        self.assertEqual(len(mesh["positions"]), 12)
        self.assertEqual([i["mesh"] for i in doc["instances"]], ["quad", "quad"])
        self.assertEqual(doc["lights"][0]["name"], "sun")
        self.assertEqual(set(doc), {"settings", "camera", "world", "materials", "meshes", "instances", "lights"})

    def test_grid_buffers_inline(self):
        """Scene files have no grid buffers: a material naming one gets its values inline."""
        from rendezvous.export.dump import JsonSink
        sink = JsonSink()
        sink.add_grid("D/grid", np.array([0.5, 1.0], np.float32), (2, 1, 1))
        sink.add_material("smoke", {"type": "volume", "volume": {"density": 2.0, "grid": {
            "buffer": "D/grid", "bounds": [[0, 0, 0], [1, 1, 1]]}}})
        doc = json.loads(json.dumps(sink.document({})))
        self.assertEqual(doc["materials"][0]["volume"], {"density": 2.0, "grid": {
            "resolution": [2, 1, 1], "values": [0.5, 1.0], "bounds": [[0, 0, 0], [1, 1, 1]]}})

    def test_image_sequence_frames(self):
        """The frame an Image User shows (Blender's start / duration / cyclic / offset rules)
        and the sequence file of that frame."""
        load_addon()
        from rendezvous.export import images
        user = lambda **kw: ns(**dict(dict(frame_duration=4, frame_start=3, frame_offset=0, use_cyclic=False), **kw))
        self.assertEqual([images.user_frame(user(), f) for f in (1, 2, 3, 4, 6, 7, 9)], [0, 0, 1, 2, 4, 4, 4])
        self.assertEqual([images.user_frame(user(use_cyclic=True), f) for f in (2, 3, 6, 7, 8, 11)],
                         [4, 1, 4, 1, 2, 1])
        self.assertEqual(images.user_frame(user(use_cyclic=True, frame_offset=1), 8), 3)
        self.assertEqual(images.user_frame(user(frame_duration=0), 5), 0)
        self.assertEqual(images.sequence_path("/a/b7/frame_001.png", 12), "/a/b7/frame_012.png")
        self.assertEqual(images.sequence_path("/a/render0001x.exr", 3), "/a/render0003x.exr")
        self.assertEqual(images.sequence_path("/a/noframe.png", 3), "/a/noframe.png")
        self.assertEqual(images.sequence_path("/a/f_9.png", 123), "/a/f_123.png")

    def test_binary(self):
        from rendezvous.export.dump import JsonSink
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.bin")
            with open(path, "wb") as f:
                doc = self.fill(JsonSink(f, "s.bin"))
            b = doc["meshes"][0]["binary"]
            with open(path, "rb") as f:
                data = f.read()
            pos = np.frombuffer(data, "<f4", 12, b["positions"])
            idx = np.frombuffer(data, "<u4", 6, b["indices"])
            self.assertEqual(pos[3], 1.0)
            self.assertEqual(list(idx), [0, 1, 2, 0, 2, 3])
            self.assertEqual((b["num_vertices"], b["num_triangles"]), (4, 2))


@unittest.skipIf(np is None, "needs numpy")
class TestMeshDerivedAttributes(unittest.TestCase):
    """Geometry > Pointiness and Random Per Island as Cycles derives them (export/mesh.py); the
    Blender test blender.brightness.mesh_derived_attributes compares the images with Cycles'."""

    def setUp(self):
        load_addon()
        from rendezvous.export import mesh
        self.mesh = mesh

    def test_pointiness_of_a_flat_grid_a_cube_and_welded_corners(self):
        # A 3 x 3 vertex grid, normals up: its centre's edges are balanced (0.5 exactly), a
        # border vertex's edges lean inward, still perpendicular to the normal: 0.5 too.
        co = np.array([[x, y, 0.0] for y in range(3) for x in range(3)], np.float32)
        edges = np.array([[i, i + 1] for i in range(9) if i % 3 < 2] + [[i, i + 3] for i in range(6)], np.uint32)
        up = np.tile([0.0, 0.0, 1.0], (9, 1)).astype(np.float32)
        self.assertTrue(np.allclose(self.mesh.pointiness(co, up, edges), 0.5))
        # A cube's corner: the mean of its three edges points away from its outward normal, at
        # acos(-1 / sqrt(3)) / pi (0.696), and every corner alike after the blur.
        corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], np.float32)
        normals = (corners - 0.5) / np.linalg.norm(corners - 0.5, axis=1, keepdims=True)
        cube_edges = np.array([[a, b] for a in range(8) for b in range(a + 1, 8)
                               if np.abs(corners[a] - corners[b]).sum() == 1], np.uint32)
        p = self.mesh.pointiness(corners, normals, cube_edges)
        self.assertTrue(np.allclose(p, math.acos(-1.0 / math.sqrt(3.0)) / math.pi, atol=1e-6), p)
        # The same cube with each face's corners its own vertices (split normals): welded by
        # position, the corners get the cube's value, not a face's.
        faces = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]]
        split = np.array([corners[v] for f in faces for v in f], np.float32)
        split_normals = np.array([normals[v] for f in faces for v in f], np.float32)
        split_edges = np.array([[4 * k + i, 4 * k + (i + 1) % 4] for k in range(6) for i in range(4)], np.uint32)
        self.assertTrue(np.allclose(self.mesh.pointiness(split, split_normals, split_edges), p[0], atol=1e-6))

    def test_random_per_island_roots_as_cycles_joins_them(self):
        # Two islands: 0-1-2 and 3-4. Union by rank keeps the first root on a tie: 0 (edge 0-1,
        # then 2 joins 0's set of rank 1) and 3 (edge 3-4).
        values = self.mesh.random_per_island(5, np.array([[0, 1], [2, 1], [3, 4]], np.uint32))
        root = self.mesh._hash_uint_to_float(np.array([0, 3], np.uint32))
        self.assertEqual(list(values), [root[0]] * 3 + [root[1]] * 2)
        self.assertNotEqual(root[0], root[1])
        self.assertTrue(0.0 <= root.min() and root.max() <= 1.0)
        # Edge 1-0 first: 1 is the root (the first argument's root wins the tie).
        self.assertEqual(self.mesh.random_per_island(2, np.array([[1, 0]], np.uint32))[0],
                         self.mesh._hash_uint_to_float(np.array([1], np.uint32))[0])


@unittest.skipIf(np is None, "needs numpy")
class TestDeformationBlur(unittest.TestCase):
    """export/motion.py's deformation steps: sent only when a vertex moves, refused (with a
    warning naming the object) when the vertex count changes over the shutter."""

    def setUp(self):
        load_addon()
        from rendezvous.export import motion
        from rendezvous.export.mesh import MeshArrays
        self.motion, self.MeshArrays = motion, MeshArrays

    def arrays(self, x, count=3):
        positions = np.array([[x + i, 0.0, 0.0] for i in range(count)], np.float32).reshape(-1)
        return self.MeshArrays(positions, None, None, np.array([0, 1, 2], np.uint32), np.zeros(1, np.uint32))

    def sampled(self, at_steps):
        sampler = self.motion.MotionSampler((-0.5, 0.5))
        sampler.track_deform(("Cloth", "", ()), 3, 7, "Cloth", self.arrays(0.0), False, [])
        sampler._deformations({("Cloth", "", ()): dict(zip((0.0, 1.0), at_steps))})
        return sampler

    def test_moving_vertices_are_sent(self):
        s = self.sampled([self.arrays(-1.0), self.arrays(1.0)])
        self.assertEqual(len(s.deformed), 1)
        mesh, positions, normals = s.deformed[0]
        self.assertEqual((mesh, len(positions), normals), (7, 3, None))
        self.assertEqual([float(p[0]) for p in positions], [-1.0, 0.0, 1.0])  # the frame's in the middle
        self.assertEqual(s.warnings, [])

    def test_still_vertices_are_not_sent(self):
        self.assertEqual(self.sampled([self.arrays(0.0), self.arrays(0.0)]).deformed, [])

    def test_changing_vertex_count_warns_naming_the_object(self):
        s = self.sampled([self.arrays(-1.0), self.arrays(1.0, count=4)])
        self.assertEqual(s.deformed, [])
        self.assertEqual(len(s.warnings), 1)
        self.assertIn("Object 'Cloth'", s.warnings[0])
        self.assertIn("without deformation blur", s.warnings[0])

    def test_may_deform(self):
        mesh = ns(shape_keys=ns(), animation_data=None)
        ob = ns(type="MESH", cycles=ns(use_deform_motion=True), modifiers=[], data=mesh)
        self.assertTrue(self.motion.may_deform(ob))
        ob.cycles.use_deform_motion = False  # Object > Motion Blur > Deformation off
        self.assertFalse(self.motion.may_deform(ob))
        plain = ns(type="MESH", cycles=ns(use_deform_motion=True), modifiers=[], data=ns(shape_keys=None,
                                                                                          animation_data=None))
        self.assertFalse(self.motion.may_deform(plain))

    def test_dump_writes_steps(self):
        from rendezvous.export.dump import JsonSink
        sink = JsonSink()
        sink.add_material("m", {"type": "diffuse"})
        mesh = sink.add_mesh("Cloth", [0, 0, 0, 1, 0, 0, 0, 1, 0], [0, 1, 2], default_material=0)
        sink.set_mesh_motion(mesh, [np.zeros(9, np.float32), np.ones(9, np.float32)])
        self.assertEqual(sink.meshes[mesh]["motion_positions"], [[0] * 9, [1] * 9])


class TestBinding(unittest.TestCase):
    def test_missing_library_message(self):
        load_addon()
        from rendezvous import binding
        old = os.environ.get("RDV_LIBRARY")
        os.environ["RDV_LIBRARY"] = "/nonexistent/librendezvous.so"
        try:
            binding.reset()
            cands = binding.library_candidates()
            self.assertEqual(cands[0], "/nonexistent/librendezvous.so")
            if not any(os.path.isfile(c) for c in cands):
                msg = binding.status_message()
                self.assertIn("not found", msg)
                self.assertIn("cmake --install", msg)
        finally:
            if old is None:
                os.environ.pop("RDV_LIBRARY", None)
            else:
                os.environ["RDV_LIBRARY"] = old
            binding.reset()

    def test_broken_library_message(self):
        load_addon()
        from rendezvous import binding
        with tempfile.NamedTemporaryFile(suffix=".so") as f:
            f.write(b"not an ELF file")
            f.flush()
            with self.assertRaises(binding.LibraryError) as cm:
                binding.load(f.name)
            self.assertIn("could not be loaded", str(cm.exception))

    def test_progress_struct_layout(self):
        load_addon()
        from rendezvous import binding
        import ctypes
        # uint32 x2, double x3, uint64, double, uint64, int32 x2, double x2, int32 (+ 4 padding:
        # C layout, 8-byte aligned)
        self.assertEqual(ctypes.sizeof(binding.Progress), 4 + 4 + 8 * 3 + 8 + 8 + 8 + 4 + 4 + 8 * 2 + 4 + 4)


if __name__ == "__main__":
    unittest.main()


class VolumeHelpers(unittest.TestCase):
    """addon/export/volumes.py: frame sequences as Blender resolves them, the bounding box."""

    def setUp(self):
        load_addon()
        from rendezvous.export import volumes
        self.volumes = volumes

    def test_sequence_frames(self):
        v = self.volumes
        vol = ns(frame_duration=10, frame_start=5, frame_offset=0, sequence_mode="CLIP")
        self.assertEqual(v.sequence_frame(vol, 5), 1)
        self.assertEqual(v.sequence_frame(vol, 14), 10)
        self.assertIsNone(v.sequence_frame(vol, 15))
        self.assertIsNone(v.sequence_frame(vol, 4))
        vol.sequence_mode = "EXTEND"
        self.assertEqual(v.sequence_frame(vol, 30), 10)
        self.assertEqual(v.sequence_frame(vol, 1), 1)
        vol.sequence_mode = "REPEAT"
        self.assertEqual(v.sequence_frame(vol, 15), 1)
        self.assertEqual(v.sequence_frame(vol, 14), 10)
        vol.sequence_mode = "PING_PONG"
        self.assertEqual(v.sequence_frame(vol, 15), 9)  # 11th frame: back down from 10
        vol.frame_offset = 100
        vol.sequence_mode = "CLIP"
        self.assertEqual(v.sequence_frame(vol, 7), 103)

    def test_frame_in_file_name(self):
        v = self.volumes
        self.assertEqual(v.with_frame("/c/fluid_data_0001.vdb", 37), "/c/fluid_data_0037.vdb")
        self.assertEqual(v.with_frame("/c/v2/smoke_12.vdb", 3), "/c/v2/smoke_03.vdb")
        self.assertEqual(v.with_frame("/c/smoke.vdb", 3), "/c/smoke.vdb")

    def test_box_faces_point_out(self):
        positions, indices = self.volumes.box_arrays([-1, -2, 0], [1, 2, 3])
        self.assertEqual(indices.shape, (12, 3))
        centre = positions.mean(axis=0)
        for tri in indices:
            a, b, c = positions[tri]
            n = np.cross(b - a, c - a)
            self.assertGreater(float(np.dot(n, (a + b + c) / 3 - centre)), 0)

    def test_attach_grids(self):
        v = self.volumes
        m = {"density": 2.0, "grid": {"name": "density"}, "temperature_grid": {"name": "temperature"},
             "emission_grid": {"name": "flame"}, "emission_strength": 3.0, "blackbody_intensity": 1.0}
        xf = translation(1, 2, 3, scale=(2.0, 2.0, 2.0))
        voxel = [[0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]]
        grids = {"density": ("FLOAT", voxel), "flame": ("FLOAT", voxel), "velocity": ("VECTOR_FLOAT", voxel)}
        warnings = v.attach_grids(m, v.vdb_lookup("/c/fire.vdb", grids, xf), "Volume 'Fire'")
        # Cycles' voxel centres: half a voxel (0.05, x 2 by the object) along each axis.
        self.assertEqual(m["grid"], {"name": "density", "file": "/c/fire.vdb",
                                     "transform": translation(1.1, 2.1, 3.1, scale=(2.0, 2.0, 2.0))})
        self.assertEqual(m["emission_grid"]["file"], "/c/fire.vdb")
        self.assertNotIn("temperature_grid", m)  # Cycles: a missing attribute leaves the temperature as it is
        self.assertEqual(len(warnings), 1)
        self.assertIn("Volume 'Fire'", warnings[0])
        self.assertIn("no grid 'temperature'", warnings[0])
        self.assertIn("density, flame, velocity", warnings[0])
        m = {"emission_grid": {"name": "velocity"}, "emission_strength": 3.0}
        warnings = v.attach_grids(m, v.vdb_lookup("/c/fire.vdb", grids, xf), "Volume 'Fire'")
        self.assertEqual(m, {})  # an Attribute node without its grid reads 0: no emission
        self.assertIn("VECTOR_FLOAT", warnings[0])

    def test_fluid_grids(self):
        v = self.volumes
        res = (2, 3, 4)
        n = 24
        ds = ns(domain_resolution=res, use_noise=False, noise_scale=2,
                density_grid=[float(i) for i in range(n)], flame_grid=[0.0] * n,
                heat_grid=[-1.0] + [float("nan")] * (n - 1), temperature_grid=[])
        m = {"density": 5.0, "grid": {"name": "density"}, "temperature_grid": {"name": "temperature"},
             "emission_grid": {"name": "heat"}, "emission_strength": 1.0, "blackbody_intensity": 1.0}
        xf = translation(0, 0, 1)
        warnings = v.attach_grids(m, v.fluid_lookup(ds, [[-1, -1, -1], [1, 1, 1]], xf, "the simulation"),
                                  "Fluid domain 'Smoke'")
        grid = dict(m["grid"])
        values = grid.pop("values")  # a float32 array, sent as a binary buffer
        self.assertEqual(values.dtype.name, "float32")
        self.assertEqual(values.tolist(), [float(i) for i in range(n)])
        self.assertEqual(grid, {"resolution": [2, 3, 4], "bounds": [[-1, -1, -1], [1, 1, 1]], "transform": xf})
        self.assertEqual(m["emission_grid"]["values"].tolist(), [0.0] * n)  # negative and NaN: empty
        self.assertNotIn("temperature_grid", m)  # no flame data at this frame
        # The dense grids become buffer references and buffers, one per array.
        m["temperature_grid"] = m["grid"]
        split, buffers = v.split_dense_grids(m, "Smoke")
        self.assertEqual([(name, list(r)) for name, _, r in buffers],
                         [("Smoke/grid", [2, 3, 4]), ("Smoke/emission_grid", [2, 3, 4])])
        self.assertIs(buffers[0][1], values)
        self.assertEqual(split["grid"], {"buffer": "Smoke/grid", "bounds": [[-1, -1, -1], [1, 1, 1]], "transform": xf})
        self.assertEqual(split["temperature_grid"], split["grid"])
        self.assertEqual(split["emission_grid"]["buffer"], "Smoke/emission_grid")
        self.assertEqual(split["density"], 5.0)
        self.assertIn("values", m["grid"])  # the medium given is left as it was
        self.assertEqual(len(warnings), 1)
        self.assertIn("Fluid domain 'Smoke'", warnings[0])
        self.assertIn("'temperature'", warnings[0])
        ds.use_noise = True
        ds.density_grid = [0.5] * (n * 8)
        self.assertEqual(v.fluid_resolution(ds, n * 8), [4, 6, 8])
        self.assertIsNone(v.fluid_resolution(ds, 7))
