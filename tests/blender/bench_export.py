"""Benchmarks (label bench, not part of CI): export of a 1M-triangle mesh and of 10,000
instances (with Cycles' own sync+render time of the same scene at 1 sample for comparison),
cost of pushing a 1920x1080 float frame into the RenderResult, peak memory per triangle.

    python3 run_blender.py --lib build/engine/librendezvous.so --script bench_export.py
"""

import resource
import time

import bpy

from rendezvous import binding
from rendezvous.engine import final
from rendezvous.export import SceneExporter


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def clear():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for m in list(bpy.data.meshes):
        bpy.data.meshes.remove(m)
    scene = bpy.context.scene
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    scene.collection.objects.link(cam)
    cam.location = (0, -30, 20)
    cam.rotation_euler = (0.9, 0, 0)
    scene.camera = cam
    return scene


class NullSink:
    def __init__(self):
        self.n = 0

    def add_material(self, name, params):
        return 0

    def add_mesh(self, name, positions, indices, **kw):
        self.n += 1
        return self.n

    def add_instance(self, mesh, m):
        return 0

    def add_light(self, name, p):
        return 0

    def set_world(self, p):
        pass

    def set_camera(self, p):
        pass


def time_export(label, runs=3):
    dg = bpy.context.evaluated_depsgraph_get()
    best_null = min(_timed(lambda: SceneExporter(dg, NullSink()).export()) for _ in range(runs))
    lib = binding.load()
    times, commit_times, peak = [], [], 0.0
    for _ in range(runs):
        rss0 = rss_mb()
        with binding.Scene(lib) as sc:
            t0 = time.perf_counter()
            stats = SceneExporter(dg, sc).export()
            t1 = time.perf_counter()
            sc.commit()
            t2 = time.perf_counter()
            peak = max(peak, rss_mb() - rss0)
            summary = sc.summary()
        times.append(t1 - t0)
        commit_times.append(t2 - t1)
    print("BENCH %s: export (arrays only) %.3f s | export into engine %.3f s | + commit/BVH %.3f s | "
          "%d triangles, %d instances | RSS growth %.1f MB" % (label, best_null, min(times), min(commit_times),
                                                               stats.triangles, stats.instances, peak))
    return stats, summary, peak


def _timed(fn):
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def cycles_time(scene):
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 16
    t = time.perf_counter()
    bpy.ops.render.render()
    return time.perf_counter() - t


def main():
    # 1M triangles
    scene = clear()
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=20)
    bpy.ops.object.shade_smooth()
    stats, summary, peak = time_export("1M-triangle mesh")
    print("BENCH memory: %.0f bytes/triangle (process RSS growth during export+commit); engine summary: %s"
          % (peak * 1024 * 1024 / max(stats.triangles, 1), summary))
    print("BENCH Cycles render of the same scene (1 spp, 16x16: sync + BVH + render): %.3f s" % cycles_time(scene))

    # 10,000 instances (hair particles rendering a cube)
    scene = clear()
    bpy.ops.mesh.primitive_cube_add(size=0.1, location=(0, 0, -100))
    cube = bpy.context.active_object
    bpy.ops.mesh.primitive_plane_add(size=20)
    plane = bpy.context.active_object
    mod = plane.modifiers.new("scatter", "PARTICLE_SYSTEM")
    ps = mod.particle_system.settings
    ps.type = "HAIR"
    ps.count = 10000
    ps.render_type = "OBJECT"
    ps.instance_object = cube
    ps.use_advanced_hair = True
    plane.show_instancer_for_render = False
    cube.hide_render = False
    stats, summary, peak = time_export("10,000 instances")
    print("BENCH Cycles render of the same scene (1 spp, 16x16: sync + BVH + render): %.3f s" % cycles_time(scene))

    # pushing a 1920x1080 frame into the RenderResult
    scene = clear()
    bpy.ops.mesh.primitive_plane_add(size=20)
    scene.render.engine = "RENDEZVOUS"
    scene.render.resolution_x, scene.render.resolution_y = 1920, 1080
    scene.render.resolution_percentage = 100
    scene.rendezvous.samples = 100000
    scene.rendezvous.time_limit = 2.2  # a few pushes at the 0.5 s interval
    bpy.ops.render.render()
    pushes = final.last_render.get("push_seconds", [])
    print("BENCH film push 1920x1080 (Combined, read_film + foreach_set): %s ms"
          % ", ".join("%.1f" % (1000 * p) for p in pushes))
    print("BENCH peak RSS of the whole run: %.0f MB" % (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024))


main()
