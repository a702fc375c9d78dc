"""ctest driver for tests that need a real Blender window (the viewport): starts Xvfb on a
free display, installs the add-on into a temporary BLENDER_USER_SCRIPTS, and runs
`blender --factory-startup --addons rendezvous --python SCRIPT` (no -b) on that display.

    python3 run_viewport.py --blender /usr/bin/blender --lib librendezvous.so --script test_viewport.py [-- args]

Exits 77 (ctest SKIP_RETURN_CODE) only when Xvfb is missing or cannot start.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import install_addon  # noqa: E402
from run_blender import addon_test_env, run_with_timeout  # noqa: E402

SKIP = 77


def start_xvfb(screen):
    """Starts Xvfb (screen: WIDTHxHEIGHT) on a display it picks itself (-displayfd), so tests
    running in parallel never share or race for a display number."""
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        print("SKIP: Xvfb not installed (apt-get install xvfb)")
        return None, None
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen([xvfb, "-displayfd", str(write_fd), "-screen", "0", screen + "x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, pass_fds=(write_fd,))
    os.close(write_fd)
    with os.fdopen(read_fd) as f:
        number = f.readline().strip()  # written once the server listens; empty if it died
    if proc.poll() is None and number.isdigit():
        return proc, ":" + number
    if proc.poll() is None:
        proc.terminate()
        proc.wait()
    print("SKIP: Xvfb could not start")
    return None, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--lib", default=None)
    ap.add_argument("--script", required=True)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--scene", default="materials_instances", help="scenes/blend/build_scenes.py scene opened in the window "
                    "(a file on the command line also keeps the splash screen away)")
    # The window fills the screen. Tests use a small one: Xvfb draws with the CPU (llvmpipe) and
    # the viewport renders the region's pixels, so 800x500 halves a test's time against
    # 1280x800 (viewport_view 16.3 -> 8.9 s alone). The benchmarks keep 1280x800 (README figures).
    ap.add_argument("--screen", default="800x500", help="Xvfb screen size, WIDTHxHEIGHT")
    ap.add_argument("rest", nargs="*")
    a = ap.parse_args()
    xvfb, display = start_xvfb(a.screen)
    if xvfb is None:
        return SKIP
    try:
        with tempfile.TemporaryDirectory(prefix="rdv_viewport_") as tmp:
            env = addon_test_env(tmp, a.lib)
            env["DISPLAY"] = display
            build = os.path.join(install_addon.ROOT, "scenes", "blend", "build_scenes.py")
            subprocess.run([a.blender, "-b", "--factory-startup", "-noaudio", "--python", build, "--", "--out", tmp,
                            a.scene], env=env, check=True, stdout=subprocess.DEVNULL, timeout=120)
            blend = os.path.join(tmp, a.scene + ".blend")
            cmd = [a.blender, "--factory-startup", "-noaudio", "--addons", "rendezvous", blend,
                   "--python-exit-code", "1", "--python", os.path.join(HERE, a.script), "--"] + a.rest
            print("DISPLAY=%s %s" % (display, " ".join(cmd)), flush=True)
            return run_with_timeout(cmd, env, a.timeout)
    finally:
        xvfb.terminate()
        xvfb.wait()


if __name__ == "__main__":
    sys.exit(main())
