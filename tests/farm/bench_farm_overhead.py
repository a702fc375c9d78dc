"""Per-task overhead of a farm task and the speed-up it allows (label bench; docs/farm.md).

    python3 tests/farm/bench_farm_overhead.py --renderer build/engine/rendezvous \
        --blender blender --lib build/engine/librendezvous.so

A task pays a fixed cost before its first sample: Blender's start, loading the .blend, the
scene export, the BVH build (and after its last sample: writing the part). Measured as
T(1 spp) - (T(1 + n spp) - T(1 spp)) / n for headless Blender renders of the Cornell box
(BDPT, 320 x 320, 1 thread) and for the command-line renderer; each run 3 times, the
minimum kept. Also the merge time per part at that size. Prints the projection for a
1-hour still split into 10, 100 and 1,000 tasks (each on its own core).
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "blender"))
sys.path.insert(0, os.path.join(ROOT, "tests", "farm"))

RES = 320


def timed(cmd, env=None, runs=3):
    best = None
    for _ in range(runs):
        t = time.time()
        subprocess.run(cmd, check=True, env=env, capture_output=True)
        dt = time.time() - t
        best = dt if best is None else min(best, dt)
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--renderer", required=True)
    ap.add_argument("--blender", required=True)
    ap.add_argument("--lib", required=True)
    ap.add_argument("--samples", type=int, default=32)
    args = ap.parse_args()
    import run_blender
    from test_slurm import BUILD_BLEND
    tmp = tempfile.mkdtemp(prefix="rdv-farm-bench-")
    env = run_blender.addon_test_env(os.path.join(tmp, "blender"), args.lib)
    blend = os.path.join(tmp, "cornell.blend")
    build = BUILD_BLEND.replace("48, 36", "%d, %d" % (RES, RES))
    subprocess.run([args.blender, "-b", "--factory-startup", "--addons", "rendezvous", "--python-expr",
                    build % {"scenes": os.path.join(ROOT, "scenes", "blend"), "path": blend}],
                   check=True, env=env, capture_output=True)

    def blender_task(samples, part):
        return [args.blender, "-b", blend, "--addons", "rendezvous", "--python-expr",
                "import bpy; r = bpy.context.scene.rendezvous; r.samples = %d; r.threads = 1; r.part_output = %r"
                % (samples, part), "-o", os.path.join(tmp, "out_####"), "-f", "1"]

    start = timed([args.blender, "-b", "--factory-startup", "--python-expr", "pass"], env)
    b1 = timed(blender_task(1, os.path.join(tmp, "b1.exr")), env)
    bn = timed(blender_task(1 + args.samples, os.path.join(tmp, "bn.exr")), env)
    per_sample = (bn - b1) / args.samples
    blender_overhead = b1 - per_sample

    scene = os.path.join(ROOT, "scenes", "cornell_box.json")
    def cli_task(samples, offset, out):
        return [args.renderer, scene, "--integrator", "bdpt", "--resolution", "%dx%d" % (RES, RES), "--threads", "1",
                "--samples", str(samples), "--sample-offset", str(offset), "--quiet", "-o", out]
    c1 = timed(cli_task(1, 0, os.path.join(tmp, "c1.exr")))
    cn = timed(cli_task(1 + args.samples, 0, os.path.join(tmp, "cn.exr")))
    cli_per_sample = (cn - c1) / args.samples
    cli_overhead = c1 - cli_per_sample
    parts = []
    for k in range(8):
        parts.append(os.path.join(tmp, "p%d.exr" % k))
        subprocess.run(cli_task(1, k, parts[-1]), check=True, capture_output=True)
    merge8 = timed([args.renderer, "merge"] + parts + ["-o", os.path.join(tmp, "merged.exr")])
    merge_per_part = merge8 / 8

    print("Blender start (factory settings, nothing loaded): %.2f s" % start)
    print("Blender task overhead (start, load, export, BVH, part file) %dx%d BDPT: %.2f s; %.3f s per sample"
          % (RES, RES, blender_overhead, per_sample))
    print("CLI task overhead (load, BVH, part file): %.3f s; %.3f s per sample" % (cli_overhead, cli_per_sample))
    print("merge: %.3f s per %dx%d part (8 parts %.2f s)" % (merge_per_part, RES, RES, merge8))
    hd = 1920 * 1080 / float(RES * RES)
    print("projection, a 3600 s BDPT still on one core, Blender tasks (overhead %.2f s), merge scaled to 1920x1080 "
          "(%.2f s per part):" % (blender_overhead, merge_per_part * hd))
    # One merge of all parts reads them one after another; merged EXRs are parts again, so a
    # tree of merges of 10 (each level's merges in parallel on the farm) takes log10(K) levels.
    print("| tasks | task wall (s) | one merge (s) | speed-up | tree of 10-part merges (s) | speed-up |")
    for k in (1, 10, 100, 1000):
        task = blender_overhead + 3600.0 / k
        flat = merge_per_part * hd * k if k > 1 else 0.0
        levels, n = 0, k
        while n > 1:
            n = (n + 9) // 10
            levels += 1
        tree = merge_per_part * hd * min(k, 10) * levels
        print("| %d | %.1f | %.1f | %.1fx | %.1f | %.1fx |" % (k, task, flat, 3600.0 / (task + flat), tree,
                                                                3600.0 / (task + tree)))


if __name__ == "__main__":
    main()
