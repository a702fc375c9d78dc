"""Brightness agrees with Cycles: each scene is rendered by Cycles and by Rendezvous in
this Blender process; the image means must agree within 2% and 8x8-pixel block means
within their noise.

    run_blender.py --script test_brightness.py -- [--samples N] [--verdicts DIR] SCENE [SCENE ...]

ctest runs every scene in one Blender process, each scene's verdict a test of its own
(verdicts.py; tests/blender/CMakeLists.txt, rdv_blender_family).
"""

import argparse
import os
import shutil
import sys
import time
import traceback

import bpy
import numpy as np

ROOT = os.environ.get("RDV_REPO_ROOT") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scenes", "blend"))
import build_scenes  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import verdicts  # noqa: E402

MEAN_TOLERANCE = 0.02
BLOCK = 8
BLOCK_REL = 0.03      # a block passes if within 3% ...
BLOCK_Z = 5.0         # ... or within 5 standard errors of the noise


def out_dir():
    d = os.path.join(os.getcwd(), "blender_test_output")
    os.makedirs(d, exist_ok=True)
    return d


def read_render(scene, path, alpha=False):
    """The Render Result saved as a float EXR and read back: RGB (RGBA with alpha)."""
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGBA"
    bpy.data.images["Render Result"].save_render(path)
    im = bpy.data.images.load(path, check_existing=False)
    px = np.empty(im.size[0] * im.size[1] * 4, np.float32)
    im.pixels.foreach_get(px)
    shape = (im.size[1], im.size[0], 4)
    bpy.data.images.remove(im)
    return px.reshape(shape)[:, :, :4 if alpha else 3].astype(np.float64)


def cycles_sampling(scene, samples, seed):
    """Cycles on the CPU, a fixed sample count and seed, no adaptive sampling, denoising or
    light threshold; its Light Paths left as they are."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = seed
    c.light_sampling_threshold = 0.0
    c.use_auto_tile = False
    return c


def use_cycles_settings(scene, samples, seed=1):
    """The scene set up as render_cycles renders it: its sampling, no clamps, 12 bounces. The
    add-on reads Light Paths from scene.cycles, so Rendezvous renders after this with the
    same limits (a test whose Cycles image comes from a reference calls it itself)."""
    c = cycles_sampling(scene, samples, seed)
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.max_bounces = 12
    c.volume_bounces = 12  # as Rendezvous (Cycles' default is 0: no scattered volume emission)
    scene.render.threads_mode = "AUTO"


def render_cycles(scene, samples, path, seed=1):
    use_cycles_settings(scene, samples, seed)
    t = time.time()
    bpy.ops.render.render()
    dt = time.time() - t
    return read_render(scene, path), dt


def render_rendezvous(scene, samples, path, integrator="PATH", seed=1):
    scene.render.engine = "RENDEZVOUS"
    p = scene.rendezvous
    p.integrator = integrator
    p.samples = samples
    p.time_limit = 0.0
    p.max_bounces = 12
    p.seed = seed
    p.clamp = 0.0
    t = time.time()
    bpy.ops.render.render()
    dt = time.time() - t
    return read_render(scene, path), dt


def local_noise_var(img):
    """Per-pixel noise variance from neighbour differences (signal assumed smooth)."""
    lum = img.mean(axis=2)
    d = np.diff(lum, axis=1)
    var = np.zeros_like(lum)
    var[:, :-1] += 0.25 * d * d
    var[:, 1:] += 0.25 * d * d
    return var


def block_means(a):
    h, w = a.shape[:2]
    hb, wb = h // BLOCK, w // BLOCK
    a = a[:hb * BLOCK, :wb * BLOCK]
    return a.reshape(hb, BLOCK, wb, BLOCK, *a.shape[2:]).mean(axis=(1, 3))


def setting_effect(with_setting, without):
    """The largest relative change of an 8x8 block's mean that a setting makes (over the blocks
    lit in either image): a test shows with it that it would see the setting ignored."""
    a, b = block_means(with_setting.mean(axis=2)), block_means(without.mean(axis=2))
    lit = np.maximum(a, b) > 0.1 * with_setting.mean()
    return float((np.abs(a - b)[lit] / np.maximum(a, b)[lit]).max())


def compare(name, ref, test):
    mref, mtest = ref.reshape(-1, 3).mean(axis=0), test.reshape(-1, 3).mean(axis=0)
    lum_ref, lum_test = mref.mean(), mtest.mean()
    ratio = lum_test / lum_ref if lum_ref > 0 else float("inf")
    ok_mean = abs(ratio - 1.0) <= MEAN_TOLERANCE
    bref = block_means(ref.mean(axis=2))
    btest = block_means(test.mean(axis=2))
    var = block_means(local_noise_var(ref) + local_noise_var(test)) / (BLOCK * BLOCK)
    se = np.sqrt(np.maximum(var, 1e-12))
    diff = np.abs(btest - bref)
    rel = diff / np.maximum(np.abs(bref), 1e-6)
    z = diff / se
    bad = (rel > BLOCK_REL) & (z > BLOCK_Z)
    ok_blocks = not bad.any()
    # Diagnostic only: the median of block ratios ignores a few outlying blocks (e.g. a lamp
    # that one renderer shows to the camera and the other does not).
    median_block_ratio = float(np.median(btest / np.maximum(bref, 1e-9)))
    print("BRIGHTNESS %-24s cycles mean %s  rendezvous mean %s  ratio %.4f  median block ratio %.4f  "
          "worst block rel %.3f z %.1f  bad blocks %d/%d  -> %s"
          % (name, np.round(mref, 4), np.round(mtest, 4), ratio, median_block_ratio, rel.max(), z.max(),
             int(bad.sum()), bad.size, "ok" if ok_mean and ok_blocks else "FAIL"))
    return ok_mean, ok_blocks, ratio


def check_setting(title, name, scene, apply, samples, odir, failures, min_effect=0.05):
    """A setting against Cycles: Cycles renders the scene without it, then apply() sets it and
    Cycles, Rendezvous' path tracer (samples) and BDPT (samples / 2) render it. Appends to
    failures: a mean or block difference from Cycles (compare), or a setting that changes no
    lit 8x8 block of Cycles' image by min_effect (the test would not see it ignored)."""
    plain, _ = render_cycles(scene, samples, os.path.join(odir, name + "_cycles_plain.exr"))
    apply()
    ref, tc = render_cycles(scene, samples, os.path.join(odir, name + "_cycles.exr"))
    print("%s %s: Cycles %d spp %.1f s" % (title, name, samples, tc))
    for integrator, n in (("PATH", samples), ("BDPT", samples // 2)):
        test, tr = render_rendezvous(scene, n, os.path.join(odir, "%s_%s.exr" % (name, integrator.lower())), integrator)
        print("  Rendezvous %s %d spp: %.1f s" % (integrator, n, tr))
        ok_mean, ok_blocks, ratio = compare("%s %s" % (name, integrator), ref, test)
        if not ok_mean:
            failures.append("%s %s: mean ratio Rendezvous/Cycles = %.4f" % (name, integrator, ratio))
        if not ok_blocks:
            failures.append("%s %s: block means differ beyond noise" % (name, integrator))
    effect = setting_effect(ref, plain)
    print("  Cycles without the setting: mean %.4f of Cycles' with it, largest block change %.1f%%"
          % (plain.mean() / ref.mean(), 100 * effect))
    if effect < min_effect:
        failures.append("%s: the setting changes no block by %.0f%% (the test would not see it ignored)"
                        % (name, 100 * min_effect))


def finish(title, failures, odir):
    """Prints the verdict; exits 1 on failures (listing them and where the images are)."""
    if failures:
        print("%s TEST FAILED (images in %s):\n  %s" % (title, odir, "\n  ".join(failures)))
        sys.exit(1)
    print("%s TEST PASSED" % title)


def brightness_failures(label, ref, test, blocks=True):
    """compare() of test against Cycles' ref (means within 2%, 8x8 blocks within 3% or 5
    standard errors; blocks=False: the mean only) as failure messages."""
    ok_mean, ok_blocks, ratio = compare(label, ref, test)
    failures = [] if ok_mean else ["%s: mean ratio Rendezvous/Cycles = %.4f" % (label, ratio)]
    if blocks and not ok_blocks:
        failures.append("%s: block means differ beyond noise" % label)
    return failures


def run_test(title, body, samples, add_arguments=None, needs_oiiotool=False, members=None):
    """main() of a test against Cycles: parses the arguments after '--' (--samples N, `samples`
    by default, and those add_arguments(parser) adds), checks for oiiotool if asked, calls
    body(args, odir, failures) and prints the verdict (exit 1 on failures or an exception).
    members: the name of a positional argument naming what to check (a scene, a variant): one or
    more may be given, body runs for each in this process with args.<members> set to it
    (verdicts.run_members), and with --verdicts DIR each one's verdict is written there for its
    own ctest test (the process then exits 0 once every verdict is written)."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=samples)
    if members:
        ap.add_argument(members, nargs="+")
        ap.add_argument("--verdicts", help="write each member's verdict into this directory (verdicts.py)")
    if add_arguments:
        add_arguments(ap)
    a = ap.parse_args(argv)
    odir = out_dir()
    failures = []
    if needs_oiiotool and not shutil.which("oiiotool"):
        finish(title, ["oiiotool (Debian's openimageio-tools) is needed to read the passes"], odir)
    if members:
        def check_member(member, member_failures):
            setattr(a, members, member)
            body(a, odir, member_failures)
        names = getattr(a, members)
        failures = verdicts.run_members(names, check_member, a.verdicts, factory_state)
        finish_family(title, names, failures, odir, a.verdicts)
        return
    try:
        body(a, odir, failures)
    except Exception as exc:
        traceback.print_exc()
        failures.append("%s: %s (traceback above)" % (title.lower(), exc))
    finish(title, failures, odir)


def factory_state():
    """Blender as it started (--factory-startup), the add-on enabled again if it was: each member
    of a family starts from what a process of its own would (a scene's setting that the
    scene builders do not reset, such as Light Paths' refractive caustics, stays otherwise)."""
    import addon_utils
    enabled = addon_utils.check("rendezvous")[1]
    bpy.ops.wm.read_factory_settings(use_empty=False)
    if enabled:
        addon_utils.enable("rendezvous", default_set=True)


def finish_family(title, members, failures, odir, verdict_dir):
    """The end of a family's process: with verdict_dir its members' tests give the verdicts (exit
    0 here), else as finish()."""
    if verdict_dir:
        print("%s: %d members, %d failures; each member's verdict is its own test (%s)"
              % (title, len(members), len(failures), verdict_dir))
        sys.exit(0)
    finish(title, failures, odir)


# Scenes whose materials or world light paths see differently from camera paths (view factors,
# the baked sky, looks by ray type, moved shading normals) or whose lamps emit by direction (IES,
# an area lamp's spread, textures over a lamp):
# BDPT against Cycles too, at half the samples.
BDPT_TOO = ("view_dependent_mixes", "nishita_sky", "light_path_rays", "light_path_shadow_rays", "mapped_normals", "bevel", "displacement", "true_displacement",
            "incoming_facing", "ies_lamps", "area_spread", "light_falloff", "lamp_textures")


def check_scene(name, samples, odir, failures):
    """One brightness scene: Rendezvous' path tracer (and BDPT for BDPT_TOO) against Cycles."""
    scene = build_scenes.build(name)
    ref, tc = render_cycles(scene, samples, os.path.join(odir, name + "_cycles.exr"))
    test, tr = render_rendezvous(scene, samples, os.path.join(odir, name + "_rendezvous.exr"))
    print("  %s: Cycles %.2f s, Rendezvous %.2f s" % (name, tc, tr))
    ok_mean, ok_blocks, ratio = compare(name, ref, test)
    if not ok_mean:
        failures.append("%s: mean ratio Rendezvous/Cycles = %.4f (tolerance %.0f%%)" % (name, ratio, 100 * MEAN_TOLERANCE))
    if not ok_blocks:
        failures.append("%s: block means differ beyond noise" % name)
    if name in BDPT_TOO:
        test, tr = render_rendezvous(scene, samples // 2, os.path.join(odir, name + "_bdpt.exr"), "BDPT")
        print("  %s: Rendezvous BDPT %.2f s" % (name, tr))
        failures += brightness_failures(name + " BDPT", ref, test)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=128)
    ap.add_argument("--verdicts", help="write each scene's verdict into this directory (verdicts.py)")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args(argv)
    names = a.scenes or build_scenes.BRIGHTNESS_SCENES
    odir = out_dir()
    failures = verdicts.run_members(names, lambda name, f: check_scene(name, a.samples, odir, f), a.verdicts,
                                   factory_state)
    finish_family("BRIGHTNESS", names, failures, odir, a.verdicts)


if __name__ == "__main__":
    main()
