"""The ctypes binding against the built library (RDV_TEST_LIBRARY, set by ctest):
a scene, a session, progress, cancel, film read-back, and errors as EngineError."""

import os
import time
import unittest

from test_export_helpers import load_addon, np, translation

LIB = os.environ.get("RDV_TEST_LIBRARY")


@unittest.skipIf(not LIB or not os.path.exists(LIB) or np is None, "RDV_TEST_LIBRARY not set or numpy missing")
class TestBindingLive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        load_addon()
        from rendezvous import binding
        cls.b = binding
        cls.lib = binding.load(LIB)

    def scene(self):
        sc = self.b.Scene(self.lib)
        mat = sc.add_material("white", {"type": "diffuse", "color": [0.8, 0.8, 0.8]})
        pos = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], np.float32)
        idx = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
        mesh = sc.add_mesh("floor", pos, idx, default_material=mat)
        sc.add_instance(mesh, translation(0, 0, 0))
        sc.add_light("sun", {"type": "sun", "strength": 1.0, "transform": translation(0, 0, 5)})
        sc.set_world({"color": [0.0, 0.0, 0.0], "strength": 1.0})
        sc.set_camera({"type": "perspective", "transform": translation(0, 0, 3)})
        return sc

    def test_render_and_read(self):
        with self.scene() as sc:
            sc.commit()
            with self.b.Session(sc, {"width": 16, "height": 8, "samples": 8, "threads": 1}) as s:
                s.start()
                s.wait()
                p = s.progress()
                self.assertTrue(p.finished)
                self.assertEqual(p.samples_done, 8)
                out = np.zeros((16 * 8, 4), np.float32)
                s.read_film(self.b.PASS_COMBINED, 0, 0, 16, 8, out.reshape(-1))
                # a white diffuse floor under a sun of irradiance 1: radiance 0.8/pi
                self.assertAlmostEqual(float(out[:, 0].mean()), 0.8 / np.pi, places=2)
                depth = np.zeros(16 * 8, np.float32)
                s.read_film(self.b.PASS_DEPTH, 0, 0, 16, 8, depth)
                self.assertAlmostEqual(float(depth.min()), 3.0, places=3)

    def test_cancel(self):
        with self.scene() as sc:
            with self.b.Session(sc, {"width": 64, "height": 64, "samples": 1000000}) as s:
                s.start()
                time.sleep(0.2)
                t = time.monotonic()
                s.cancel()
                s.wait()
                self.assertLess(time.monotonic() - t, 0.5)
                self.assertTrue(s.progress().cancelled)

    def test_mesh_attribute_colour_renders(self):
        """A floor whose 'Col' colour attribute is red, read by a vertex_color texture node."""
        with self.b.Scene(self.lib) as sc:
            mat = sc.add_material("vc", {"type": "diffuse",
                                         "color": {"node": "vertex_color", "layer": "Col"}})
            pos = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], np.float32)
            idx = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
            col = np.tile(np.array([1.0, 0.0, 0.0, 1.0], np.float32), 4)
            uv2 = np.zeros(8, np.float32)
            mesh = sc.add_mesh("floor", pos, idx, default_material=mat,
                               attributes=[("Col", "color", col, 4), ("UV2", "uv", uv2, 2)])
            sc.add_instance(mesh, translation(0, 0, 0))
            sc.add_light("sun", {"type": "sun", "strength": 1.0, "transform": translation(0, 0, 5)})
            sc.set_world({"color": [0.0, 0.0, 0.0], "strength": 1.0})
            sc.set_camera({"type": "perspective", "transform": translation(0, 0, 3)})
            sc.commit()
            with self.b.Session(sc, {"width": 8, "height": 8, "samples": 4, "threads": 1}) as s:
                s.start()
                s.wait()
                out = np.zeros((8 * 8, 4), np.float32)
                s.read_film(self.b.PASS_COMBINED, 0, 0, 8, 8, out.reshape(-1))
                self.assertAlmostEqual(float(out[:, 0].mean()), 1.0 / np.pi, places=2)
                self.assertAlmostEqual(float(out[:, 1].mean()), 0.0, places=3)

    def test_errors_raise_engine_error(self):
        with self.b.Scene(self.lib) as sc:
            with self.assertRaises(self.b.EngineError) as cm:
                sc.add_material("bad", {"type": "diffuse", "colour": [1, 1, 1]})
            self.assertIn("colour", str(cm.exception))
            with self.assertRaises(self.b.EngineError):
                sc.add_mesh("bad", np.zeros((3, 3), np.float32), np.array([[0, 1, 7]], np.uint32))


if __name__ == "__main__":
    unittest.main()
