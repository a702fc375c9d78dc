"""Viewport benchmark (label bench), in a real Blender window on Xvfb (run_viewport.py):

    run_viewport.py --screen 1280x800 --script bench_viewport.py [-- 100000 1000000]
    run_viewport.py --screen 1280x800 --script bench_viewport.py -- volumes --vdb-writer build/tests/write_test_vdb [32 128]

Volumes: build_scenes.cloud_and_fog with a Volume object whose ball is N voxels across its
radius (write_test_vdb ball N), prints the time from Rendered on to the first frame drawn
(and Cycles'), the add-on's export time, and for Principled Volume density edits on the
Volume object and on the mesh volume: the time to the first new frame drawn and the
in-place re-export time (the add-on reads the grid and the engine loads the .vdb again).

For the materials_instances scene plus one sphere of N triangles, prints:
  * time from switching to Rendered to the first Rendezvous frame drawn, and Cycles' (same run,
    CPU device: when the centre of the region first shows rendered pixels);
  * time from a camera move / object move / material colour change to the first new frame drawn
    (medians of 5);
  * CPU use of the Blender process while idle after the viewport converged.
"""

import os
import resource
import statistics
import sys
import time
import traceback

import bpy
import numpy as np

from rendezvous.engine import viewport

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
VOLUMES = "volumes" in ARGS
VDB_WRITER = ARGS[ARGS.index("--vdb-writer") + 1] if "--vdb-writer" in ARGS else None
SIZES = [int(a) for a in ARGS if a.isdigit()] or ([32, 128] if VOLUMES else [100000, 1000000])


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return win, area, region, area.spaces.active


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


# A POST_PIXEL draw handler samples the centre of the region on every redraw (any engine).
probe = {"value": None, "time": 0.0}


def _probe():
    import gpu
    _, _, region, _ = view3d()
    fb = gpu.state.active_framebuffer_get()
    buf = fb.read_color(region.width // 2 - 4, region.height // 2 - 4, 8, 8, 4, 0, "FLOAT")
    buf.dimensions = 8 * 8 * 4
    probe["value"] = float(np.array(buf.to_list()).reshape(-1, 4)[:, :3].mean())
    probe["time"] = time.perf_counter()


def heavy_sphere(tris):
    old = bpy.data.objects.get("Heavy")
    if old is not None:
        bpy.data.objects.remove(old, do_unlink=True)
    rings = max(8, int((tris / 4) ** 0.5))
    segments = max(8, tris // (2 * rings))
    mesh = bpy.data.meshes.new("Heavy")
    import bmesh
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=0.9)
    bm.to_mesh(mesh)
    bm.free()
    ob = bpy.data.objects.new("Heavy", mesh)
    ob.location = (0.0, 0.2, 0.9)
    bpy.context.scene.collection.objects.link(ob)
    mesh.materials.append(bpy.data.materials["Principled"])
    return sum(len(p.vertices) - 2 for p in mesh.polygons)


def wait_converged(timeout=30.0):
    t0 = time.time()
    while time.time() - t0 < timeout:
        if viewport._renderers and all(r.converged for r in viewport._renderers):
            return
        yield 0.05


def latency(action, n=5, also=None):
    """Median time from `action()` to the first new frame drawn (and the median of also()
    read after each frame, if given)."""
    out, figures = [], []
    for i in range(n):
        yield from wait_converged(10)
        t0 = time.perf_counter()
        action(i)
        _, area, _, _ = view3d()
        area.tag_redraw()
        while viewport.stats["first_new_frame_drawn"] < t0 and time.perf_counter() - t0 < 10:
            yield 0.001
        out.append(viewport.stats["first_new_frame_drawn"] - t0)
        if also is not None:
            figures.append(also())
    if also is not None:
        return statistics.median(out), statistics.median(figures)
    return statistics.median(out)


def switch_time(engine):
    """Seconds from Rendered on to the centre of the region changing from the empty background."""
    scene = bpy.context.scene
    _, area, _, space = view3d()
    space.shading.type = "SOLID"
    yield 0.5
    scene.render.engine = engine
    t0 = time.perf_counter()
    viewport.stats["first_new_frame_drawn"] = 0.0
    space.shading.type = "RENDERED"
    area.tag_redraw()
    while time.perf_counter() - t0 < 60:
        if engine == "RENDEZVOUS" and viewport.stats["first_new_frame_drawn"] > t0:
            return viewport.stats["first_new_frame_drawn"] - t0
        if engine != "RENDEZVOUS" and probe["time"] > t0 and probe["value"] is not None \
                and abs(probe["value"] - probe["background"]) > 0.03:
            return probe["time"] - t0
        yield 0.002
    return float("nan")


def bench_settings(scene):
    """Rendezvous in the viewport, 16 samples (Cycles: CPU, 16 samples)."""
    scene.render.engine = "RENDEZVOUS"
    scene.rendezvous.viewport_samples = 16
    scene.cycles.max_bounces = 3  # Light Paths are shared with Cycles: 3 bounces = 4 scattering vertices
    scene.cycles.device = "CPU"
    scene.cycles.preview_samples = 16


def bench():
    scene = bpy.context.scene
    bench_settings(scene)
    win, area, region, space = view3d()
    space.overlay.show_overlays = False
    space.show_gizmo = False
    import bpy_extras  # noqa: F401
    space.region_3d.view_perspective = "CAMERA"
    handler = bpy.types.SpaceView3D.draw_handler_add(_probe, (), "WINDOW", "POST_PIXEL")
    print("BENCH region %dx%d, %d cores" % (region.width, region.height, os.cpu_count()))
    for tris in SIZES:
        n = heavy_sphere(tris)
        yield from background_probe(space, area)
        t_rdv = yield from switch_time("RENDEZVOUS")
        yield from wait_converged()
        exports = dict(viewport.stats)
        cam = yield from latency(lambda i: setattr(space.region_3d, "view_camera_zoom",
                                                   space.region_3d.view_camera_zoom + (1 if i % 2 else -1)))
        heavy = bpy.data.objects["Heavy"]
        obj = yield from latency(lambda i: setattr(heavy.location, "x", heavy.location.x + (0.05 if i % 2 else -0.05)))
        node = bpy.data.materials["Principled"].node_tree.nodes["Principled BSDF"]
        mat = yield from latency(lambda i: node.inputs["Base Color"].default_value.__setitem__(0, 0.3 + 0.1 * i))
        reexports = viewport.stats["full_exports"] - exports["full_exports"]
        mesh_exports = viewport.stats["mesh_exports"] - exports["mesh_exports"]
        yield from wait_converged()
        yield 0.5
        c0, w0 = cpu_seconds(), time.perf_counter()
        yield 3.0
        idle = 100.0 * (cpu_seconds() - c0) / (time.perf_counter() - w0)
        t_cycles = yield from switch_time("CYCLES")
        yield 2.0
        space.shading.type = "SOLID"
        scene.render.engine = "RENDEZVOUS"
        yield 0.5
        print("BENCH %8d triangles: Rendered on -> first frame %.3f s (Cycles %.3f s); camera move %.1f ms, "
              "object move %.1f ms, material colour %.1f ms (first new frame drawn, medians of 5); "
              "re-exports during edits: %d scene, %d mesh; idle CPU after convergence %.1f %%"
              % (n, t_rdv, t_cycles, cam * 1e3, obj * 1e3, mat * 1e3, reexports, mesh_exports, idle), flush=True)
    bpy.types.SpaceView3D.draw_handler_remove(handler, "WINDOW")


def background_probe(space, area):
    """The centre pixel of an empty Rendered viewport (paused Rendezvous draws nothing)."""
    scene = bpy.context.scene
    scene.rendezvous.viewport_pause = True
    space.shading.type = "RENDERED"
    area.tag_redraw()
    yield 1.0
    probe["background"] = probe["value"]
    space.shading.type = "SOLID"
    scene.rendezvous.viewport_pause = False
    yield 0.3


def bench_volumes():
    import subprocess
    sys.path.insert(0, os.path.join(os.environ["RDV_REPO_ROOT"], "scenes", "blend"))
    import build_scenes
    tmp = os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir
    win, area, region, space = view3d()
    space.overlay.show_overlays = False
    space.show_gizmo = False
    handler = bpy.types.SpaceView3D.draw_handler_add(_probe, (), "WINDOW", "POST_PIXEL")
    print("BENCH region %dx%d, %d cores" % (region.width, region.height, os.cpu_count()))
    for n in SIZES:
        path = os.path.join(tmp, "ball_%d.vdb" % n)
        subprocess.run([VDB_WRITER, path, "ball", str(n)], check=True)
        space.shading.type = "SOLID"
        yield 0.3
        cloud, pv, fog_pv = build_scenes.cloud_and_fog(path)
        scene = bpy.context.scene
        bench_settings(scene)
        space.region_3d.view_perspective = "CAMERA"
        yield from background_probe(space, area)
        t_rdv = yield from switch_time("RENDEZVOUS")
        export = viewport.stats["export_seconds"]
        yield from wait_converged()
        before = dict(viewport.stats)

        def density(node, base):
            return lambda i: setattr(node.inputs["Density"], "default_value", base * (1.2 if i % 2 else 0.8))
        vol_t, vol_reexport = yield from latency(density(pv, 8.0), also=lambda: viewport.stats["volume_update_seconds"])
        mesh_t = yield from latency(density(fog_pv, 1.5))
        reexports = viewport.stats["full_exports"] - before["full_exports"]
        volume_updates = viewport.stats["volume_updates"] - before["volume_updates"]
        material_updates = viewport.stats["material_updates"] - before["material_updates"]
        t_cycles = yield from switch_time("CYCLES")
        yield 2.0
        space.shading.type = "SOLID"
        scene.render.engine = "RENDEZVOUS"
        yield 0.5
        voxels = (2 * n + 1) ** 3
        print("BENCH Volume object %d voxels across (%.1f M voxels in its box, .vdb %.1f MB) + mesh volume: "
              "Rendered on -> first frame %.3f s (export %.3f s; Cycles %.3f s); Volume material density edit: "
              "first new frame %.1f ms, in-place re-export %.1f ms; mesh volume density edit: first new frame %.1f ms "
              "(medians of 5); during edits %d scene re-exports, %d volume and %d material updates"
              % (2 * n + 1, voxels / 1e6, os.path.getsize(path) / 1e6, t_rdv, export, t_cycles, vol_t * 1e3,
                 vol_reexport * 1e3, mesh_t * 1e3, reexports, volume_updates, material_updates), flush=True)
    bpy.types.SpaceView3D.draw_handler_remove(handler, "WINDOW")


def run():
    gen = bench_volumes() if VOLUMES else bench()

    def step():
        try:
            return next(gen)
        except StopIteration:
            os._exit(0)
        except Exception:
            traceback.print_exc()
            os._exit(1)

    bpy.app.timers.register(step, first_interval=1.0)


run()
