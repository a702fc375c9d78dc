"""Benchmark (label bench): export of a smoke / fire domain's grids to the engine, the
final render's path (SceneExporter into an engine scene, then commit): wall time and the
process's peak resident memory during the export, for domains 64 and 128 voxels across
(a 2-frame Replay simulation; the grids are dense, so their size is what counts).

    python3 run_blender.py --lib build/engine/librendezvous.so --script bench_fluid_export.py [-- 64 128]
"""

import os
import sys
import time

import bpy

ROOT = os.environ.get("RDV_REPO_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scenes", "blend"))
import build_scenes  # noqa: E402

from rendezvous import binding  # noqa: E402
from rendezvous.export import SceneExporter  # noqa: E402

TMP = os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir


def status_mb(key):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def reset_peak():
    with open("/proc/self/clear_refs", "w") as f:  # resets VmHWM (Linux)
        f.write("5")


def bench(resolution):
    scene = bpy.context.scene
    for ob in list(scene.objects):
        if ob.type != "CAMERA":
            bpy.data.objects.remove(ob)
    domain = build_scenes.fire_domain(os.path.join(TMP, "fluid_cache_%d" % resolution), 2, resolution)
    ds = [m for m in domain.modifiers if m.type == "FLUID"][0].domain_settings
    depsgraph = bpy.context.evaluated_depsgraph_get()
    res = tuple(int(x) for x in domain.evaluated_get(depsgraph).modifiers["Fluid"].domain_settings.domain_resolution)
    rss0 = status_mb("VmRSS")
    reset_peak()
    t0 = time.perf_counter()
    with binding.Scene() as rscene:
        exporter = SceneExporter(depsgraph, rscene)
        exporter.export()
        rscene.commit()
        dt = time.perf_counter() - t0
        peak = status_mb("VmHWM")
    print("BENCH fluid export %s (resolution_max %d): %.2f s, peak RSS %.0f MB (+%.0f MB over %.0f MB before)"
          % ("x".join(map(str, res)), resolution, dt, peak, peak - rss0, rss0), flush=True)
    del ds


args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
for r in [int(a) for a in args] or [64, 128]:
    bench(r)
