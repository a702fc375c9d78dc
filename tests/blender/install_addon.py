"""Installs the add-on as ONE folder (addon/ contents + shaders_map/ + the library) into
<scripts>/addons/rendezvous, the layout `cmake --install` produces.  Plain Python.

    python3 tests/blender/install_addon.py --scripts /tmp/x/scripts --lib build/engine/librendezvous.so
"""

import argparse
import os
import shutil

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", ".gitignore", "*.cmake", "README.md")


def install(scripts_dir, lib=None, root=ROOT):
    dest = os.path.join(scripts_dir, "addons", "rendezvous")
    if os.path.exists(dest):
        shutil.rmtree(dest)
    shutil.copytree(os.path.join(root, "addon"), dest, ignore=IGNORE)
    shutil.copytree(os.path.join(root, "shaders_map"), os.path.join(dest, "shaders_map"), ignore=IGNORE)
    if lib:
        shutil.copy2(lib, os.path.join(dest, os.path.basename(lib)))
    return dest


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--scripts", required=True)
    ap.add_argument("--lib", default=None)
    a = ap.parse_args()
    print(install(a.scripts, a.lib))
