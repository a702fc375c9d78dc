"""Headless renders as users run them.  First `blender -b scene.blend -E RENDEZVOUS -o ... -f 1`
must write the frame and exit 0.  Then Ctrl-C during `blender -b scene.blend -E RENDEZVOUS -f 1`: Blender's test_break() turns
true, the engine session is cancelled and Blender exits promptly.  Plain Python driver.

    python3 cancel_sigint.py --blender blender --lib build/engine/librendezvous.so
"""

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import install_addon  # noqa: E402
from run_blender import blender_env  # noqa: E402

MAKE = """
import sys, bpy
sys.path.insert(0, %r)
import build_scenes
scene = build_scenes.build("materials_instances")
scene.render.resolution_x = scene.render.resolution_y = 128
scene.render.engine = "RENDEZVOUS"
scene.rendezvous.samples = 1000000
bpy.ops.wm.save_as_mainfile(filepath=%r)
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--lib", required=True)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="rdv_sigint_") as tmp:
        scripts = os.path.join(tmp, "scripts")
        install_addon.install(scripts, a.lib)
        env = blender_env()
        env["BLENDER_USER_SCRIPTS"] = scripts
        blend = os.path.join(tmp, "long.blend")
        make = os.path.join(tmp, "make.py")
        with open(make, "w") as f:
            f.write(MAKE % (os.path.join(install_addon.ROOT, "scenes", "blend"), blend))
        subprocess.run([a.blender, "-b", "--factory-startup", "--addons", "rendezvous", "--python", make],
                       env=env, check=True, stdout=subprocess.DEVNULL)
        # 1. a normal headless frame (samples overridden small through a tiny Python expression)
        small = os.path.join(tmp, "small.blend")
        subprocess.run([a.blender, "-b", "--factory-startup", "--addons", "rendezvous", blend, "--python-expr",
                        "import bpy; bpy.context.scene.rendezvous.samples = 4; "
                        "bpy.ops.wm.save_as_mainfile(filepath=%r)" % small],
                       env=env, check=True, stdout=subprocess.DEVNULL)
        t = time.monotonic()
        proc = subprocess.run([a.blender, "-b", "--factory-startup", "--addons", "rendezvous", small, "-E",
                               "RENDEZVOUS", "-o", os.path.join(tmp, "frame_"), "-F", "PNG", "-f", "1"],
                              env=env, capture_output=True, text=True)
        frame = os.path.join(tmp, "frame_0001.png")
        print("HEADLESS: exit code %d, %.2f s, wrote %s: %s" % (proc.returncode, time.monotonic() - t, frame,
                                                                os.path.exists(frame)))
        if proc.returncode != 0 or not os.path.exists(frame):
            print(proc.stdout[-3000:], proc.stderr[-3000:])
            print("FAILED: headless frame")
            return 1
        # 2. Ctrl-C during a render that would take forever
        cmd = [a.blender, "-b", "--factory-startup", "--addons", "rendezvous", blend, "-E", "RENDEZVOUS",
               "-o", os.path.join(tmp, "out_"), "-F", "OPEN_EXR", "-f", "1"]
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
        start = time.monotonic()
        saw_progress = False
        for line in proc.stdout:
            if "Sample" in line and "Rendezvous" in line:
                saw_progress = True
                break
            if time.monotonic() - start > 60:
                break
        if not saw_progress:
            proc.kill()
            print("FAILED: no render progress seen")
            return 1
        time.sleep(0.5)
        t0 = time.monotonic()
        proc.send_signal(signal.SIGINT)
        try:
            rest, _ = proc.communicate(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            print("FAILED: Blender still running 20 s after Ctrl-C")
            return 1
        dt = time.monotonic() - t0
        tail = "\n".join(rest.splitlines()[-5:])
        print(tail)
        print("SIGINT: Blender exited %.2f s after Ctrl-C (exit code %s)" % (dt, proc.returncode))
        if dt > 5.0:
            print("FAILED: cancel took too long")
            return 1
        print("CANCEL SIGINT TEST PASSED")
        return 0


if __name__ == "__main__":
    sys.exit(main())
