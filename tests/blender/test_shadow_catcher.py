"""Shadow catcher (Object > Visibility > Shadow Catcher) against Cycles 3.4: build_scenes.
shadow_catcher (48x48: a floor that is a shadow catcher under a red ball and a green card, a
point lamp, a blue world seen past the floor's edge), Film > Transparent on. Cycles renders
it, then Rendezvous with --integrator (PATH, the default, or BDPT) in this process (256
samples each, seed 1):
- View Layer > Passes > Shadow Catcher on (`view_layer.cycles.use_pass_shadow_catcher`): the
  Shadow Catcher pass (the floor's light with the objects over its light without them) and
  Combined, which is then the matte (the objects over a transparent floor): colour and alpha;
- the pass off (Cycles' approximate shadow catcher): Combined holds the shadow as alpha over
  black: colour and alpha;
- the lamp's own Shadow Catcher off (a light of the synthetic objects: it lights the image,
  not the Shadow Catcher pass, which then exceeds 1): the pass;
- Film > Transparent off, the pass off: Combined is the world behind the floor darkened by the
  shadow, the objects over it: colour (alpha is 1);
each as test_brightness.compare (means within 2%, 8x8 blocks within 3% or 5 standard errors);
the pass is registered with Blender (the compositor's Render Layers node lists it);
- (PATH run) Metropolis (PSSMLT) renders the catcher as an ordinary object and warns naming it.

    run_blender.py --script test_shadow_catcher.py -- [--samples N] [--integrator PATH|BDPT]
"""

import argparse
import os
import shutil
import subprocess
import sys
import traceback

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_brightness import build_scenes, compare, finish, out_dir  # noqa: E402
from test_light_paths import render as render_engine  # noqa: E402
import numpy as np  # noqa: E402


def read_layer(path, layer, name, chans, odir):
    """One pass of a multilayer EXR as H x W x len(chans), rows from the top."""
    one = os.path.join(odir, "sc_one_%d.exr" % os.getpid())  # ctest may run the variants at once
    subprocess.run(["oiiotool", path, "--ch", ",".join("%s.%s.%s" % (layer, name, c) for c in chans),
                    "--chnames", ",".join("RGBA"[:len(chans)]), "-d", "float", "-o", one], check=True,
                   capture_output=True)
    im = bpy.data.images.load(one, check_existing=False)
    px = np.empty(im.size[0] * im.size[1] * 4, np.float32)
    im.pixels.foreach_get(px)
    shape = (im.size[1], im.size[0], 4)
    bpy.data.images.remove(im)
    return px.reshape(shape)[::-1, :, :len(chans)].astype(np.float64)


def render(scene, engine, samples, path, integrator="PATH"):
    """{"Combined": RGBA, "Shadow Catcher": RGB (when the pass is on)} of a render."""
    render_engine(scene, engine, samples, path + ".single.exr", integrator, alpha=True)
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    bpy.data.images["Render Result"].save_render(path)
    layer = bpy.context.view_layer
    odir = os.path.dirname(path)
    out = {"Combined": read_layer(path, layer.name, "Combined", "RGBA", odir)}
    if layer.cycles.use_pass_shadow_catcher:
        out["Shadow Catcher"] = read_layer(path, layer.name, "Shadow Catcher", "RGB", odir)
    return out


def check(label, ref, test, failures):
    if not np.isfinite(test).all():
        failures.append("%s: non-finite pixels" % label)
    ok_mean, ok_blocks, ratio = compare(label, ref, test)
    if not ok_mean:
        failures.append("%s: mean ratio Rendezvous/Cycles = %.4f" % (label, ratio))
    if not ok_blocks:
        failures.append("%s: block means differ beyond noise" % label)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--integrator", default="PATH", choices=("PATH", "BDPT"))
    a = ap.parse_args(argv)
    name = a.integrator.lower()
    odir = out_dir()
    failures = []
    if not shutil.which("oiiotool"):
        finish("SHADOW CATCHER", ["oiiotool (Debian's openimageio-tools) is needed to read the passes"], odir)
    try:
        scene = build_scenes.build("shadow_catcher")
        scene.render.film_transparent = True
        layer = bpy.context.view_layer
        lamp = bpy.data.objects["Point"]
        for tag in ("pass", "approximate", "synthetic_lamp", "opaque_film"):
            pass_on = tag in ("pass", "synthetic_lamp")
            layer.cycles.use_pass_shadow_catcher = pass_on
            lamp.is_shadow_catcher = tag != "synthetic_lamp"  # Blender's default for lights: on
            scene.render.film_transparent = tag != "opaque_film"
            if pass_on:
                from rendezvous.engine import passes as addon_passes
                registered = [p[0] for p in addon_passes.enabled_passes(layer, scene)]
                if "Shadow Catcher" not in registered:
                    failures.append("the Shadow Catcher pass is not registered")
            ref = render(scene, "CYCLES", a.samples, os.path.join(odir, "shadow_catcher_%s_cycles_%s.exr" % (tag, name)))
            test = render(scene, "RENDEZVOUS", a.samples, os.path.join(odir, "shadow_catcher_%s_%s.exr" % (tag, name)),
                          a.integrator)
            rc, tc = ref["Combined"], test["Combined"]
            print("SHADOW CATCHER %s %s: Cycles Combined mean %s, Rendezvous %s"
                  % (name, tag, np.round(rc.reshape(-1, 4).mean(0), 4), np.round(tc.reshape(-1, 4).mean(0), 4)))
            check("%s colour" % tag, rc[:, :, :3], tc[:, :, :3], failures)
            check("%s alpha" % tag, np.repeat(rc[:, :, 3:], 3, axis=2), np.repeat(tc[:, :, 3:], 3, axis=2), failures)
            if pass_on:
                rs, ts = ref["Shadow Catcher"], test["Shadow Catcher"]
                print("SHADOW CATCHER pass: Cycles mean %.4f min %.4f, Rendezvous mean %.4f min %.4f"
                      % (rs.mean(), rs.min(), ts.mean(), ts.min()))
                if tag == "pass" and not rs.min() < 0.5:
                    failures.append("Cycles' Shadow Catcher pass shows no shadow (min %.3f): the scene tests nothing"
                                    % rs.min())
                if tag == "synthetic_lamp" and not rs.max() > 1.5:
                    failures.append("Cycles' Shadow Catcher pass is not brightened by the synthetic lamp (max %.3f)"
                                    % rs.max())
                check("%s Shadow Catcher" % tag, rs, ts, failures)

        # Metropolis: the catcher as an ordinary object, and a warning naming it.
        if a.integrator == "PATH":
            from rendezvous.engine import final
            layer.cycles.use_pass_shadow_catcher = False
            lamp.is_shadow_catcher = True
            scene.render.film_transparent = True
            q = render(scene, "RENDEZVOUS", 8, os.path.join(odir, "shadow_catcher_pssmlt.exr"), "PSSMLT")
            warned = [line for line in final.last_render.get("messages", [])
                      if "shadow catcher" in line and "Floor" in line]
            print("PSSMLT: Combined alpha mean %.4f, warning: %s" % (q["Combined"][:, :, 3].mean(), warned))
            if not warned:
                failures.append("PSSMLT with a shadow catcher did not warn naming the object")
    except Exception:
        traceback.print_exc()
        failures.append("exception (see above)")
    finish("SHADOW CATCHER %s" % a.integrator, failures, odir)


main()
