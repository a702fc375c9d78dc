"""ctest driver: installs the add-on into a temporary BLENDER_USER_SCRIPTS and runs a test
script under `blender -b --factory-startup --addons rendezvous`.

    python3 run_blender.py --blender /usr/bin/blender --lib librendezvous.so --script test_x.py [-- args]
"""

import argparse
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import install_addon  # noqa: E402


def blender_env():
    """Blender's embedded Python derives its prefix from the python3 found on PATH: drop
    pyenv/virtualenv interpreters (which lack Debian's numpy) so it uses the system one."""
    path = [p for p in os.environ.get("PATH", "").split(os.pathsep)
            if ".pyenv" not in p and "virtualenv" not in p and p]
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join(path)
    for k in list(env):
        if k.startswith("PYENV") or k in ("PYTHONHOME", "PYTHONPATH", "VIRTUAL_ENV"):
            del env[k]
    return env


def addon_test_env(tmp, lib):
    """The environment a test Blender runs in: the add-on installed into tmp/scripts as
    BLENDER_USER_SCRIPTS, tmp and the repository named for the test script."""
    scripts = os.path.join(tmp, "scripts")
    install_addon.install(scripts, lib)
    env = blender_env()
    env["BLENDER_USER_SCRIPTS"] = scripts
    env["RDV_TEST_TMP"] = tmp
    env["RDV_REPO_ROOT"] = install_addon.ROOT
    env.pop("RDV_LIBRARY", None)
    return env


def run_with_timeout(cmd, env, timeout):
    """Runs a test Blender; its exit code, or 1 after the time limit."""
    try:
        return subprocess.run(cmd, env=env, timeout=timeout).returncode
    except subprocess.TimeoutExpired:
        print("TIMEOUT after %.0f s" % timeout)
        return 1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--lib", default=None)
    ap.add_argument("--script", required=True)
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--no-addon", action="store_true", help="do not pass --addons rendezvous")
    ap.add_argument("rest", nargs="*")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="rdv_blender_") as tmp:
        env = addon_test_env(tmp, a.lib)
        cmd = [a.blender, "-b", "--factory-startup", "-noaudio"]
        if not a.no_addon:
            cmd += ["--addons", "rendezvous"]
        cmd += ["--python-exit-code", "1", "--python", os.path.join(HERE, a.script), "--"] + a.rest
        print(" ".join(cmd), flush=True)
        return run_with_timeout(cmd, env, a.timeout)


if __name__ == "__main__":
    sys.exit(main())
