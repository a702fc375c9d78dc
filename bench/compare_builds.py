#!/usr/bin/env python3
"""Benchmark (prints numbers, asserts nothing): the same scene rendered by two or more
builds of the command-line renderer, alternating the binaries within each round so
that a shared machine's drift hits all of them alike. Prints each run's wall time (the
whole process: load, BVH, render, write) and render time with Msamples/s (from the
renderer's own summary line), then per round the ratio of every build to the first.

Run it under the build lock on a shared machine:
  flock /tmp/rdv-build.lock bench/compare_builds.py scenes/cornell_box.json \
      --samples 64 --rounds 3 --integrator path main=build/engine/rendezvous \
      nomedia=/tmp/rdv-nomedia/build/engine/rendezvous
"""
import argparse
import re
import statistics
import subprocess
import sys
import tempfile
import time

SUMMARY = re.compile(r"(\d+) samples/pixel in ([0-9.]+) s")


def run(binary, args, out):
    start = time.perf_counter()
    done = subprocess.run([binary, *args, "-o", out], capture_output=True, text=True)
    wall = time.perf_counter() - start
    m = SUMMARY.search(done.stderr)
    if done.returncode != 0 or not m:
        sys.exit(f"{binary} failed ({done.returncode}):\n{done.stderr}")
    return wall, int(m.group(1)), float(m.group(2))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("builds", nargs="+", help="label=path/to/rendezvous; ratios are against the first")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--integrator", default="path")
    ap.add_argument("--resolution", default="512x512")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    builds = [b.split("=", 1) for b in a.builds]
    w, h = (int(x) for x in a.resolution.split("x"))
    args = [a.scene, "--samples", str(a.samples), "--integrator", a.integrator, "--resolution", a.resolution,
            "--threads", str(a.threads), "--quiet"]
    print(f"{a.scene} {a.integrator} {a.resolution} {a.samples} spp, {a.threads} threads, {a.rounds} rounds")
    ratios = {label: ([], []) for label, _ in builds[1:]}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.rounds):
            # Alternate the order each round (A B C, C B A, ...): drift cancels in pairs.
            order = builds if r % 2 == 0 else builds[::-1]
            results = {}
            for label, binary in order:
                wall, spp, render = run(binary, args, f"{tmp}/{label}.exr")
                results[label] = (wall, render)
                print(f"  round {r + 1} {label:>10}: wall {wall:6.2f} s  render {render:6.2f} s  "
                      f"{w * h * spp / render * 1e-6:6.3f} Msamples/s")
            base_wall, base_render = results[builds[0][0]]
            for label, _ in builds[1:]:
                wall, render = results[label]
                ratios[label][0].append(wall / base_wall)
                ratios[label][1].append(render / base_render)
                print(f"  round {r + 1} {label} / {builds[0][0]}: wall {wall / base_wall:.3f}  render {render / base_render:.3f}")
    for label, (walls, renders) in ratios.items():
        print(f"{label} / {builds[0][0]}: wall time ratio median {statistics.median(walls):.3f} "
              f"(min {min(walls):.3f}, max {max(walls):.3f}); render time ratio median {statistics.median(renders):.3f} "
              f"(min {min(renders):.3f}, max {max(renders):.3f})")


if __name__ == "__main__":
    main()
