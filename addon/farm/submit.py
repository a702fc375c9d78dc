"""Submits a render to Slurm as sample-range tasks plus a merge (docs/farm.md).

    python3 addon/farm/submit.py --scheduler slurm scene.blend --split 8 --samples 128 --frames 1-24 --out farm/
    python3 addon/farm/submit.py --scheduler slurm scenes/cornell_box.json --split 4 --samples 64 --out farm/

Writes farm/slurm/task.sh and merge.sh and submits `sbatch --array=0-(frames x split - 1)`: task i
renders frame frames[i // split], samples [k * samples, (k + 1) * samples) with k = i % split,
headless (`blender -b` with the add-on, or the command-line renderer for a JSON scene), as a render
part farm/parts/part_FRAME_K.exr; a task whose render fails is run once more. The merge job
(`--dependency=afterany` on the array, so that it also runs, and names the missing ranges, when a
task failed twice) runs `rendezvous merge --samples split x samples` per frame into
farm/final_FRAME.exr. `--dry-run` writes the scripts and prints the sbatch commands only.
"""

import argparse
import os
import shlex
import shutil
import subprocess
import sys


def parse_frames(text):
    """'1-24', '1,5,9-12' -> [1, ..., 24] / [1, 5, 9, 10, 11, 12]."""
    frames = []
    for item in text.split(","):
        item = item.strip()
        if not item:
            continue
        if "-" in item[1:]:
            a, b = item[0] + item[1:].split("-", 1)[0], item[1:].split("-", 1)[1]
            a, b = int(a), int(b)
            if b < a:
                raise ValueError("frame range %s ends before it begins" % item)
            frames.extend(range(a, b + 1))
        else:
            frames.append(int(item))
    if not frames:
        raise ValueError("no frames in '%s'" % text)
    return frames


def task_command(scene, frame, k, samples, part, blender, renderer, threads):
    """The command one task runs (the per-task command line of docs/farm.md)."""
    offset = k * samples
    if scene.endswith(".blend"):
        expr = ("import bpy; r = bpy.context.scene.rendezvous; r.samples = %d; r.sample_offset = %d; "
                "r.threads = %d; r.part_output = %r" % (samples, offset, threads, part))
        out = os.path.join(os.path.dirname(part), "blender_%d_####" % k)
        return [blender, "-b", scene, "--addons", "rendezvous", "--python-expr", expr, "-o", out, "-f", str(frame)]
    return [renderer, scene, "--samples", str(samples), "--sample-offset", str(offset), "--threads", str(threads),
            "--quiet", "-o", part]


def write_scripts(args, frames):
    out = os.path.abspath(args.out)
    scene = os.path.abspath(args.scene)
    for d in ("slurm", "parts", "logs"):
        os.makedirs(os.path.join(out, d), exist_ok=True)
    n = len(frames) * args.split
    cases = []
    for i in range(n):
        frame, k = frames[i // args.split], i % args.split
        part = os.path.join(out, "parts", "part_%04d_%d.exr" % (frame, k))
        cmd = task_command(scene, frame, k, args.samples, part, args.blender, args.renderer, args.threads or args.cpus)
        cases.append("  %d) cmd=(%s) ;;" % (i, " ".join(shlex.quote(c) for c in cmd)))
    task = "\n".join([
        "#!/bin/bash",
        "# Rendezvous farm task: one sample range of one frame (docs/farm.md). Written by submit.py.",
        "case \"$SLURM_ARRAY_TASK_ID\" in",
        *cases,
        "  *) echo \"no task $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;",
        "esac",
        "for attempt in 1 2; do  # a render that fails (killed, crashed) is run once more",
        "  echo \"task $SLURM_ARRAY_TASK_ID attempt $attempt: ${cmd[*]}\"",
        "  \"${cmd[@]}\" && exit 0",
        "  echo \"task $SLURM_ARRAY_TASK_ID attempt $attempt failed (exit $?)\" >&2",
        "done",
        "exit 1",
        ""])
    merges = []
    for frame in frames:
        parts = os.path.join(out, "parts", "part_%04d_*.exr" % frame)
        final = os.path.join(out, "final_%04d.exr" % frame)
        merges.append("%s merge %s --samples %d -o %s || status=1" % (
            shlex.quote(args.renderer), parts, args.split * args.samples, shlex.quote(final)))
    merge = "\n".join([
        "#!/bin/bash",
        "# Rendezvous farm merge: the parts of each frame into final_FRAME.exr; missing ranges are named.",
        "status=0",
        *merges,
        "exit $status",
        ""])
    paths = {}
    for name, text in (("task.sh", task), ("merge.sh", merge)):
        path = os.path.join(out, "slurm", name)
        with open(path, "w") as f:
            f.write(text)
        os.chmod(path, 0o755)
        paths[name] = path
    return out, n, paths


def sbatch(cmd, dry_run):
    print(" ".join(shlex.quote(c) for c in cmd))
    if dry_run:
        return "DRYRUN"
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError("sbatch failed: %s" % (proc.stderr.strip() or proc.stdout.strip()))
    return proc.stdout.strip().split(";")[0]


def submit(args):
    frames = parse_frames(args.frames)
    if args.split < 1 or args.samples < 1:
        raise ValueError("--split and --samples must be at least 1")
    if not os.path.exists(args.scene):
        raise ValueError("scene '%s' does not exist" % args.scene)
    out, n, paths = write_scripts(args, frames)
    logs = os.path.join(out, "logs")
    extra = shlex.split(args.sbatch_args) if args.sbatch_args else []
    array = sbatch(["sbatch", "--parsable", "--job-name", "rdv-render", "--array", "0-%d" % (n - 1),
                    "--cpus-per-task", str(args.cpus), "--requeue", "-o", os.path.join(logs, "task_%A_%a.log")]
                   + extra + [paths["task.sh"]], args.dry_run)
    merge = sbatch(["sbatch", "--parsable", "--job-name", "rdv-merge", "--dependency", "afterany:%s" % array,
                    "-o", os.path.join(logs, "merge_%j.log")] + extra + [paths["merge.sh"]], args.dry_run)
    print("submitted: render array %s (%d tasks: %d frames x %d ranges of %d samples), merge %s; output %s"
          % (array, n, len(frames), args.split, args.samples, merge, out))
    return array, merge


def parse_args(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene", help=".blend (rendered by blender -b with the add-on) or a JSON scene")
    ap.add_argument("--scheduler", default="slurm", choices=["slurm"])
    ap.add_argument("--split", type=int, default=4, help="sample ranges (tasks) per frame")
    ap.add_argument("--samples", type=int, required=True, help="samples per task (Metropolis: mutations per pixel)")
    ap.add_argument("--frames", default="1", help="frames, e.g. 1-24 or 1,5,9-12 (JSON scenes: one)")
    ap.add_argument("--out", required=True, help="shared folder for scripts, parts, logs and final images")
    ap.add_argument("--threads", type=int, default=0, help="render threads per task (0: --cpus)")
    ap.add_argument("--cpus", type=int, default=1, help="sbatch --cpus-per-task")
    ap.add_argument("--blender", default=shutil.which("blender") or "blender")
    ap.add_argument("--renderer", default=shutil.which("rendezvous") or os.path.join(here, "rendezvous"),
                    help="the command-line renderer (merges; renders JSON scenes)")
    ap.add_argument("--sbatch-args", default="", help="extra sbatch options, e.g. '--partition render'")
    ap.add_argument("--dry-run", action="store_true")
    return ap.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    try:
        submit(args)
    except (ValueError, RuntimeError, OSError) as exc:
        print("rendezvous farm: %s" % exc, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
