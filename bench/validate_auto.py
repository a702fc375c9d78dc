#!/usr/bin/env python3
"""Checks `--integrator auto` against a study (docs/trade.md): for every scene of the
study's CSV, the pilots of a render of TOTAL seconds pick an integrator; its error in the
study at the budget nearest TOTAL is compared with the best integrator's there. Prints one
line per scene and the share of scenes where the pick is within 1.5x of the best (the
issue's goal: 80%). Renders only the pilots (--samples 1 ends the render after them).

    python3 bench/validate_auto.py docs/images/trade/study.csv --total 20 [--rendezvous build/engine/rendezvous]
                                   [--candidates path,bdpt,pssmlt,mmlt,mlt]

--candidates: the pilots' integrators instead of the engine's default (the scene's settings
get "auto_candidates"; a copy of the scene next to it, removed after).
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--total", type=float, default=20)
    ap.add_argument("--rendezvous", default=os.path.join(ROOT, "build", "engine", "rendezvous"))
    ap.add_argument("--scenes", default=os.path.join(ROOT, "scenes"))
    ap.add_argument("--candidates", help="comma-separated integrators for the pilots")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    good = 0
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    for scene in scenes:
        mine = [r for r in rows if r["scene"] == scene]
        budget = min({float(r["budget_s"]) for r in mine}, key=lambda b: abs(b - a.total))
        errors = {r["integrator"]: float(r["rel_mse"]) for r in mine if float(r["budget_s"]) == budget}
        size = "%sx%s" % (mine[0]["width"], mine[0]["height"])
        path = os.path.join(a.scenes, scene + ".json")
        if a.candidates:  # a copy beside the scene, so its relative file names still resolve
            doc = json.load(open(path))
            doc.setdefault("settings", {})["auto_candidates"] = a.candidates.split(",")
            path = os.path.join(a.scenes, ".validate_auto_" + scene + ".json")
            with open(path, "w") as f:
                json.dump(doc, f)
        try:
            out = subprocess.run([a.rendezvous, path, "--integrator", "auto", "--time", str(a.total), "--samples", "1",
                                  "--resolution", size, "--quiet", "-o", "/tmp/rdv_validate_auto.png"],
                                 capture_output=True, text=True)
        finally:
            if a.candidates:
                os.remove(path)
        m = re.search(r"auto: chose (\w+); pilots took ([\d.]+) s", out.stderr)
        if not m:
            print("%-18s failed: %s" % (scene, out.stderr.strip()[-300:]))
            continue
        pick, pilot = m.group(1), float(m.group(2))
        best = min(errors, key=errors.get)
        ratio = errors[pick] / errors[best] if pick in errors else float("inf")
        good += ratio <= 1.5
        print("%-18s pick %-6s best at %g s %-6s error ratio %5.2f  pilots %.2f s of %g s" %
              (scene, pick, budget, best, ratio, pilot, a.total))
    print("pick within 1.5x of the best on %d of %d scenes (%.0f%%)" % (good, len(scenes), 100.0 * good / max(1, len(scenes))))


if __name__ == "__main__":
    sys.exit(main())
