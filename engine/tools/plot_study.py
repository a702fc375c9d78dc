#!/usr/bin/python3
"""Plots of `rendezvous study`: for each scene in study.csv, relative MSE against render
time on log-log axes, one line per integrator, a 1/t slope for comparison (an unbiased
estimator's error falls along it once it has found every light path) and the reference's
own noise (the floor every figure contains).

    /usr/bin/python3 engine/tools/plot_study.py STUDY.csv OUT_DIR   -> OUT_DIR/<scene>.png

Needs matplotlib (Debian: python3-matplotlib; a pyenv python lacks it)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display
import matplotlib.pyplot as plt  # noqa: E402

# One colour and marker per integrator, the same in every plot.
STYLE = {
    "path": ("tab:blue", "o"),
    "bdpt": ("tab:orange", "s"),
    "pssmlt": ("tab:green", "^"),
    "mmlt": ("tab:red", "v"),
}
OTHER = [("tab:purple", "D"), ("tab:brown", "P"), ("tab:pink", "X"), ("tab:gray", "*")]


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def plot_scene(scene, rows, out_dir):
    fig, ax = plt.subplots(figsize=(5.2, 3.9), dpi=100)
    integrators = list(dict.fromkeys(r["integrator"] for r in rows))
    all_t, all_e = [], []
    for i, name in enumerate(integrators):
        pts = sorted((float(r["time_s"]), float(r["rel_mse"])) for r in rows if r["integrator"] == name)
        pts = [(t, e) for t, e in pts if t > 0 and e > 0]  # log axes
        if not pts:
            continue
        colour, marker = STYLE.get(name, OTHER[i % len(OTHER)])
        ax.plot([t for t, _ in pts], [e for _, e in pts], marker=marker, color=colour, label=name)
        all_t += [t for t, _ in pts]
        all_e += [e for _, e in pts]
    if not all_t:
        plt.close(fig)
        return None
    # The 1/t slope through the lowest error at the shortest time of any integrator.
    t0 = min(all_t)
    e0 = min(e for t, e in zip(all_t, all_e) if t == t0)
    t1 = max(all_t)
    ax.plot([t0, t1], [e0, e0 * t0 / t1], "k--", linewidth=1, label="1/t")
    noise = float(rows[0]["reference_noise"])
    if noise > 0:
        ax.axhline(noise, color="0.5", linestyle=":", linewidth=1, label="reference noise")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time [s]")
    ax.set_ylabel("relative MSE")
    ref = "%s %s s reference, %sx%s" % (rows[0]["reference_integrator"], rows[0]["reference_s"], rows[0]["width"],
                                        rows[0]["height"])
    ax.set_title("%s (%s)" % (scene, ref), fontsize=9)
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, scene + ".png")
    fig.savefig(path)
    plt.close(fig)
    return path


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: plot_study.py STUDY.csv OUT_DIR\n")
        return 2
    rows = read_rows(argv[1])
    os.makedirs(argv[2], exist_ok=True)
    for scene in dict.fromkeys(r["scene"] for r in rows):
        plot_scene(scene, [r for r in rows if r["scene"] == scene], argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
