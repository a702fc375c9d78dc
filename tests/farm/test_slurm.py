"""A real single-node Slurm cluster, started and stopped by this test (label: farm).

munged, slurmctld and slurmd from Debian's packages (slurmctld slurmd slurm-client munge) run as
this user from a generated slurm.conf for this host only, in a temporary folder, on their own
ports. The test submits a 4-task split of a BDPT render with addon/farm/submit.py; the render of
task 2 is killed (SIGKILL) mid-render on its first attempt and must be retried; the merge job
must produce the image one render of all 128 samples gives, bit for bit (image channels). With
--blender and --lib, a .blend built by the test is split the same way into 4 headless Blender
tasks (the add-on installed for them) and merged, equal to one Blender render of all samples. Exit 77
(ctest: skipped) when the Slurm or munge programs are not installed.

    python3 tests/farm/test_slurm.py --renderer build/engine/rendezvous
"""

import argparse
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SUBMIT = os.path.join(ROOT, "addon", "farm", "submit.py")
PROGRAMS = ("munged", "munge", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    def __init__(self, root):
        self.root = root
        self.run = os.path.join(root, "run")
        for d in ("state", "spool", "log"):
            os.makedirs(os.path.join(self.run, d))
        os.chmod(self.run, 0o700)
        self.key = os.path.join(self.run, "munge.key")
        with open(self.key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(self.key, 0o400)
        self.sock = os.path.join(self.run, "munge.sock")
        self.conf = os.path.join(self.run, "slurm.conf")
        host = socket.gethostname().split(".")[0]
        r = self.run
        with open(self.conf, "w") as f:
            f.write("\n".join([
                "ClusterName=rdvtest", "SlurmctldHost=%s" % host, "SlurmUser=%s" % os.environ.get("USER", "root"),
                "SlurmctldPort=%d" % free_port(), "SlurmdPort=%d" % free_port(),
                "AuthType=auth/munge", "AuthInfo=socket=%s" % self.sock, "CredType=cred/munge",
                "StateSaveLocation=%s/state" % r, "SlurmdSpoolDir=%s/spool" % r,
                "SlurmctldPidFile=%s/slurmctld.pid" % r, "SlurmdPidFile=%s/slurmd.pid" % r,
                "SlurmctldLogFile=%s/log/slurmctld.log" % r, "SlurmdLogFile=%s/log/slurmd.log" % r,
                "ProctrackType=proctrack/linuxproc", "TaskPlugin=task/none",
                "SelectType=select/cons_tres", "SelectTypeParameters=CR_CPU", "SchedulerType=sched/backfill",
                "MpiDefault=none", "ReturnToService=2", "JobCompType=jobcomp/none",
                "NodeName=%s CPUs=%d State=UNKNOWN" % (host, os.cpu_count() or 1),
                "PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP", ""]))
        self.env = dict(os.environ, SLURM_CONF=self.conf)

    def start(self):
        subprocess.run(["munged", "--key-file=" + self.key, "-S", self.sock, "--force",
                        "--pid-file=" + os.path.join(self.run, "munged.pid"),
                        "--log-file=" + os.path.join(self.run, "munged.log"),
                        "--seed-file=" + os.path.join(self.run, "munged.seed")], check=True)
        subprocess.run(["slurmctld", "-f", self.conf], check=True, env=self.env)
        subprocess.run(["slurmd", "-f", self.conf], check=True, env=self.env)
        deadline = time.time() + 30
        while time.time() < deadline:
            out = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True, env=self.env).stdout
            if out.strip() == "idle":
                return
            time.sleep(0.5)
        raise RuntimeError("the node did not come up: sinfo says %r\n%s" % (out, self.logs()))

    def logs(self):
        text = ""
        for name in ("slurmctld.log", "slurmd.log"):
            path = os.path.join(self.run, "log", name)
            if os.path.exists(path):
                text += "--- %s\n%s" % (name, open(path).read()[-3000:])
        return text

    def stop(self):
        for name in ("slurmd.pid", "slurmctld.pid", "munged.pid"):
            path = os.path.join(self.run, name)
            try:
                pid = int(open(path).read().split()[0])
                os.kill(pid, signal.SIGTERM)
            except (OSError, ValueError, IndexError):
                continue
            for _ in range(50):  # wait for it to go (its files are removed with the folder)
                try:
                    os.kill(pid, 0)
                except OSError:
                    break
                time.sleep(0.1)

    def wait_empty(self, timeout):
        deadline = time.time() + timeout
        while time.time() < deadline:
            out = subprocess.run(["squeue", "-h"], capture_output=True, text=True, env=self.env).stdout
            if not out.strip():
                return True
            time.sleep(1)
        return False


def run_farm(cluster, submit_args, env, timeout):
    """Submits with submit.py and waits for the array and the merge; returns the wall time."""
    t0 = time.time()
    proc = subprocess.run([sys.executable, SUBMIT, "--scheduler", "slurm"] + submit_args, capture_output=True,
                          text=True, env=env)
    print(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        raise RuntimeError("submit failed")
    if not cluster.wait_empty(timeout):
        raise RuntimeError("the jobs did not finish in %d s\n%s" % (timeout, cluster.logs()))
    return time.time() - t0


def image_channels_equal(a, b, tmp):
    chans = "R,G,B,A,Depth.Z,Normal.X,Normal.Y,Normal.Z,Albedo.R,Albedo.G,Albedo.B"
    ia, ib = os.path.join(tmp, "a.exr"), os.path.join(tmp, "b.exr")
    subprocess.run(["oiiotool", a, "--ch", chans, "-o", ia], check=True)
    subprocess.run(["oiiotool", b, "--ch", chans, "-o", ib], check=True)
    proc = subprocess.run(["idiff", "-fail", "0", "-warn", "0", ia, ib], capture_output=True, text=True)
    print(proc.stdout.strip())
    return proc.returncode == 0


# A renderer that is killed (SIGKILL) mid-render the first time it renders part 2: the farm
# task must run the render again. Merges and every other render pass straight through.
KILLER = """#!/bin/bash
real=%(real)s
out=""
prev=""
for a in "$@"; do [ "$prev" = "-o" ] && out="$a"; prev="$a"; done
if [ "$1" != merge ] && [[ "$out" == *_2.exr ]] && [ ! -e "$out.killed" ]; then
  touch "$out.killed"
  "$real" "$@" & pid=$!
  sleep 0.3
  [ -e "$out" ] && echo "the part was already written when the render was killed" >&2
  kill -9 $pid
  wait $pid
  exit $?
fi
exec "$real" "$@"
"""


BUILD_BLEND = """
import sys, bpy
sys.path.insert(0, %(scenes)r)
import build_scenes
scene = build_scenes.build("cornell_lamp_near_ceiling")
scene.render.resolution_x, scene.render.resolution_y = 48, 36
scene.render.engine = "RENDEZVOUS"
scene.rendezvous.integrator = "BDPT"
scene.rendezvous.seed = 5
scene.frame_current = 1
bpy.ops.wm.save_as_mainfile(filepath=%(path)r)
"""


def blender_split(args, cluster, renderer, tmp):
    """A .blend split into 4 Slurm tasks of headless Blender (the add-on installed for them), merged,
    equal to one headless Blender render of all the samples."""
    sys.path.insert(0, os.path.join(ROOT, "tests", "blender"))
    import run_blender  # noqa: E402  (installs the add-on, Blender's environment)
    env = run_blender.addon_test_env(os.path.join(tmp, "blender"), args.lib)
    env["SLURM_CONF"] = cluster.conf
    blend = os.path.join(tmp, "cornell.blend")
    subprocess.run([args.blender, "-b", "--factory-startup", "--addons", "rendezvous", "--python-expr",
                    BUILD_BLEND % {"scenes": os.path.join(ROOT, "scenes", "blend"), "path": blend}],
                   check=True, env=env, capture_output=True)
    out = os.path.join(tmp, "farm_blend")
    farm_seconds = run_farm(cluster, [blend, "--split", "4", "--samples", "8", "--frames", "1", "--out", out,
                                      "--renderer", renderer, "--blender", args.blender, "--threads", "1"], env, 240)
    final = os.path.join(out, "final_0001.exr")
    if not os.path.exists(final):
        for name in sorted(os.listdir(os.path.join(out, "logs"))):
            print("--- %s\n%s" % (name, open(os.path.join(out, "logs", name)).read()[-2000:]))
        raise RuntimeError("the merge job wrote no %s" % final)
    whole = os.path.join(tmp, "blend_whole.exr")
    t1 = time.time()
    subprocess.run([args.blender, "-b", blend, "--addons", "rendezvous", "--python-expr",
                    "import bpy; r = bpy.context.scene.rendezvous; r.samples = 32; r.threads = 1; "
                    "r.part_output = %r" % whole, "-o", os.path.join(tmp, "blend_whole_####"), "-f", "1"],
                   check=True, env=env, capture_output=True)
    whole_seconds = time.time() - t1
    if not image_channels_equal(whole, final, tmp):
        raise RuntimeError("the Blender farm's merged image differs from one Blender render of all 32 samples")
    print("FARM SLURM BLENDER: 4 blender -b tasks of 8 spp + merge in %.1f s wall; one blender -b render of 32 spp "
          "%.1f s" % (farm_seconds, whole_seconds))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--renderer", required=True)
    ap.add_argument("--blender", default=None, help="also split a .blend over Slurm (with --lib)")
    ap.add_argument("--lib", default=None, help="librendezvous.so for the add-on the Blender tasks use")
    args = ap.parse_args()
    missing = [p for p in PROGRAMS if not shutil.which(p)]
    if missing or not shutil.which("oiiotool") or not shutil.which("idiff"):
        print("SKIPPED: not installed: %s (apt-get install slurmctld slurmd slurm-client munge openimageio-tools)"
              % " ".join(missing or ["oiiotool/idiff"]))
        return 77
    renderer = os.path.abspath(args.renderer)
    tmp = tempfile.mkdtemp(prefix="rdv-slurm-")
    cluster = Cluster(tmp)
    ok = False
    try:
        cluster.start()
        scene = json.load(open(os.path.join(ROOT, "scenes", "cornell_box.json")))
        scene.setdefault("settings", {}).update({"width": 64, "height": 48, "integrator": "bdpt", "max_bounces": 6,
                                                 "seed": 11})
        scene_path = os.path.join(tmp, "cornell_bdpt.json")
        json.dump(scene, open(scene_path, "w"))
        killer = os.path.join(tmp, "rendezvous_killed_once")
        with open(killer, "w") as f:
            f.write(KILLER % {"real": renderer})
        os.chmod(killer, 0o755)
        out = os.path.join(tmp, "farm")
        farm_seconds = run_farm(cluster, [scene_path, "--split", "4", "--samples", "32", "--out", out,
                                          "--renderer", killer, "--threads", "1"], cluster.env, 180)
        logs = {name: open(os.path.join(out, "logs", name)).read() for name in os.listdir(os.path.join(out, "logs"))}
        for name, text in sorted(logs.items()):
            print("--- %s\n%s" % (name, text.strip()))
        if any("already written when" in text for text in logs.values()):
            raise RuntimeError("the render finished before it was killed: make the tasks longer")
        retried = [name for name, text in logs.items() if "attempt 1 failed" in text and "attempt 2" in text]
        if len(retried) != 1:
            raise RuntimeError("expected one task to be retried after its render was killed, got %s" % retried)
        final = os.path.join(out, "final_0001.exr")
        if not os.path.exists(final):
            raise RuntimeError("the merge job wrote no %s" % final)
        t1 = time.time()
        whole = os.path.join(tmp, "whole.exr")
        subprocess.run([renderer, scene_path, "--samples", "128", "--threads", "1", "--quiet", "-o", whole], check=True)
        whole_seconds = time.time() - t1
        if not image_channels_equal(whole, final, tmp):
            raise RuntimeError("the farm's merged image differs from one render of all 128 samples")
        print("FARM SLURM: 4 tasks of 32 spp (one killed and retried) + merge in %.1f s wall; one render of 128 spp %.1f s"
              % (farm_seconds, whole_seconds))
        if args.blender and os.path.exists(args.blender) and args.lib:
            blender_split(args, cluster, renderer, tmp)
        else:
            print("no Blender given (--blender, --lib): the .blend split is not tested")
        ok = True
    except Exception as exc:
        print("FAILED: %s" % exc)
    finally:
        cluster.stop()
        if ok:
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            print("left for inspection: %s" % tmp)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
