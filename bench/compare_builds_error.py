#!/usr/bin/env python3
"""Benchmark (prints numbers, asserts nothing): the error of two builds of the command-line
renderer on the same scene, as a sampling change alters it. Each build renders the scene
at the same sample count with seeds 1..N, alternating builds within each seed; each image's
mean squared error against a reference EXR (render one long with either build) and its
render time are averaged, and the ratios of the second build to the first printed with
the efficiency 1 / (MSE x time).

  bench/compare_builds_error.py scenes/softboxes.json ref.exr --integrator path --samples 32 \\
      --resolution 128x96 old=/tmp/old/build/engine/rendezvous new=build/engine/rendezvous
"""
import argparse
import re
import statistics
import subprocess
import sys
import tempfile

SUMMARY = re.compile(r"samples/pixel in ([0-9.]+) s")
AVERAGE = re.compile(r"Stats Avg: ([0-9.e+-]+) ([0-9.e+-]+) ([0-9.e+-]+)")


def mse(image, reference):
    """Mean over pixels and R, G, B of the squared difference (oiiotool)."""
    out = subprocess.run(["oiiotool", image, "--ch", "R,G,B", reference, "--ch", "R,G,B", "--sub", "--powc", "2",
                          "--printstats"], capture_output=True, text=True, check=True).stdout
    return statistics.mean(float(x) for x in AVERAGE.search(out).groups())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("reference", help="an EXR of the scene at the same resolution, rendered long")
    ap.add_argument("builds", nargs=2, help="label=path/to/rendezvous; ratios are of the second to the first")
    ap.add_argument("--integrator", default="path")
    ap.add_argument("--samples", type=int, default=32)
    ap.add_argument("--resolution", default="128x96")
    ap.add_argument("--seeds", type=int, default=6)
    a = ap.parse_args()
    builds = [b.split("=", 1) for b in a.builds]
    errors = {label: [] for label, _ in builds}
    times = {label: [] for label, _ in builds}
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, a.seeds + 1):
            for label, binary in builds:
                out = "%s/%s.exr" % (tmp, label)
                done = subprocess.run([binary, a.scene, "--integrator", a.integrator, "--samples", str(a.samples),
                                       "--resolution", a.resolution, "--seed", str(seed), "-o", out, "--quiet"],
                                      capture_output=True, text=True)
                m = SUMMARY.search(done.stderr)
                if done.returncode != 0 or not m:
                    sys.exit("%s failed (%d):\n%s" % (binary, done.returncode, done.stderr))
                times[label].append(float(m.group(1)))
                errors[label].append(mse(out, a.reference))
    for label, _ in builds:
        e = errors[label]
        print("%-8s %s %d spp: MSE %.5g +- %.2g, render time median %.3f s" % (
            label, a.integrator, a.samples, statistics.mean(e), statistics.stdev(e) / len(e) ** 0.5,
            statistics.median(times[label])))
    (first, _), (second, _) = builds
    e_ratio = statistics.mean(errors[second]) / statistics.mean(errors[first])
    t_ratio = statistics.median(times[second]) / statistics.median(times[first])
    print("%s / %s: MSE %.3f, time %.3f, efficiency %.2f" % (second, first, e_ratio, t_ratio, 1 / (e_ratio * t_ratio)))


if __name__ == "__main__":
    main()
