"""The 3D view's Rendered mode with Rendezvous, in a real Blender window (run_viewport.py: Xvfb).

    run_viewport.py --script test_viewport.py -- view        screenshot shows the scene (vs a final
                                                             render), object move and material colour
                                                             follow, updated in place (no re-export)
    run_viewport.py --script test_viewport.py -- reopen      close/reopen 20x: no session/memory growth
    run_viewport.py --script test_viewport.py -- preview     material previews (principled, glass, emission)

The steps run from a bpy.app.timers generator (the window must be up); the result is printed
and Blender exits with os._exit (0 = pass).  No timing assertions.
"""

import os
import sys
import time
import traceback

import bpy
import numpy as np

ROOT = os.environ.get("RDV_REPO_ROOT") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from rendezvous import binding  # noqa: E402
from rendezvous.engine import viewport, preview  # noqa: E402

TMP = os.environ.get("RDV_VIEWPORT_OUT") or os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir  # _OUT: keep images
MODE = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv and len(sys.argv) > sys.argv.index("--") + 1 else "view"


class Failure(AssertionError):
    pass


def check(cond, msg):
    if not cond:
        raise Failure(msg)


def view3d():
    win = bpy.context.window_manager.windows[0]
    areas = [a for a in win.screen.areas if a.type == "VIEW_3D"]
    area = max(areas, key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return win, area, region, area.spaces.active


def set_shading(kind):
    _, area, _, space = view3d()
    space.shading.type = kind
    area.tag_redraw()


def screenshot(name):
    """The 3D view's WINDOW region as float RGB (rows bottom-up), display-referred 0..1."""
    win, area, region, _ = view3d()
    path = os.path.join(TMP, name + ".png")
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.screen.screenshot_area(filepath=path)
    im = bpy.data.images.load(path, check_existing=False)
    w, h = im.size
    px = np.empty(w * h * 4, np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    px = px.reshape(h, w, 4)[:, :, :3]
    # The area screenshot includes the header: crop the WINDOW region (offsets from the area).
    x0, y0 = region.x - area.x, region.y - area.y
    return px[y0:y0 + region.height, x0:x0 + region.width]


def dump_frame(name):
    """Saves the newest viewport film (scene-linear) for debugging."""
    for r in viewport._renderers:
        if r.frame is not None:
            arr, w, h = r.frame
            im = bpy.data.images.new(name, w, h, float_buffer=True)
            im.pixels.foreach_set(arr)
            im.filepath_raw = os.path.join(TMP, name + ".exr")
            im.file_format = "OPEN_EXR"
            im.save()
            bpy.data.images.remove(im)
            print("viewport camera:", r.camera)
            return


def camera_rect():
    """Pixel rectangle (x0, y0, x1, y1) of the camera frame in the region (camera view)."""
    from bpy_extras.view3d_utils import location_3d_to_region_2d
    _, _, region, space = view3d()
    scene = bpy.context.scene
    cam = scene.camera
    pts = [cam.matrix_world @ v for v in cam.data.view_frame(scene=scene)]
    xy = [location_3d_to_region_2d(region, space.region_3d, p) for p in pts]
    xs, ys = [p.x for p in xy], [p.y for p in xy]
    return int(round(min(xs))), int(round(min(ys))), int(round(max(xs))), int(round(max(ys)))


def blocks(img, n=12):
    """n x n block means of luminance."""
    h, w = img.shape[:2]
    lum = img[..., :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    ys = np.linspace(0, h, n + 1).astype(int)
    xs = np.linspace(0, w, n + 1).astype(int)
    return np.array([[lum[ys[i]:ys[i + 1], xs[j]:xs[j + 1]].mean() for j in range(n)] for i in range(n)])


def srgb(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def final_render_display():
    scene = bpy.context.scene
    scene.rendezvous.samples = 32
    bpy.ops.render.render()
    path = os.path.join(TMP, "final.exr")
    scene.render.image_settings.file_format = "OPEN_EXR"
    bpy.data.images["Render Result"].save_render(path)
    im = bpy.data.images.load(path, check_existing=False)
    w, h = im.size
    px = np.empty(w * h * 4, np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    return srgb(px.reshape(h, w, 4)[:, :, :3])


def wait_converged(timeout=8.0):
    """Yields until every viewport renderer reached its samples (or timeout)."""
    t0 = time.time()
    while time.time() - t0 < timeout:
        rs = list(viewport._renderers)
        if rs and all(r.converged for r in rs):
            yield 0.2  # one more redraw with the final frame
            return
        yield 0.05
    print("note: viewport not converged after %.0f s" % timeout)


def setup_scene(samples=8):
    scene = bpy.context.scene  # showcase.blend from scenes/blend, opened by run_viewport.py
    scene.render.engine = "RENDEZVOUS"
    scene.rendezvous.viewport_samples = samples
    scene.rendezvous.max_bounces = 4
    _, area, region, space = view3d()
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.region_3d.view_perspective = "CAMERA"
    space.region_3d.view_camera_zoom = 0
    space.region_3d.view_camera_offset = (0, 0)
    return scene


# ---- modes ------------------------------------------------------------------------------------------
def mode_view():
    scene = setup_scene()
    yield 0.5
    set_shading("SOLID")
    yield 0.3
    solid = screenshot("solid")
    set_shading("RENDERED")
    yield from wait_converged()
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])
    a = screenshot("rendered_a")
    dump_frame("frame_a")
    x0, y0, x1, y1 = camera_rect()
    print("camera frame in region: %s, region %dx%d" % ((x0, y0, x1, y1), a.shape[1], a.shape[0]))
    crop = a[y0:y1, x0:x1]
    check(crop.size > 0, "empty camera frame")
    # Not the empty viewport: differs from the solid-mode screenshot and has structure.
    check(float(np.abs(a - solid).mean()) > 0.02, "rendered viewport looks like solid mode")
    check(float(crop.std()) > 0.02, "rendered viewport is flat (std %.4f)" % crop.std())
    final = final_render_display()
    corr = float(np.corrcoef(blocks(crop).ravel(), blocks(final).ravel())[0, 1])
    print("VIEW correlation with the final render: %.3f" % corr)
    check(corr > 0.8, "viewport does not correlate with the final render (r = %.3f)" % corr)

    # Move an object: the image changes, only an instance transform is updated.
    before = dict(viewport.stats)
    cube = bpy.data.objects["Cube"]
    cube.location.x -= 1.0
    yield 0.1
    yield from wait_converged()
    b = screenshot("rendered_b")
    diff = float(np.abs(b[y0:y1, x0:x1] - crop).mean())
    print("MOVE image change %.4f, transform updates %d, full exports %d -> %d" % (
        diff, viewport.stats["transform_updates"] - before["transform_updates"], before["full_exports"],
        viewport.stats["full_exports"]))
    check(diff > 0.005, "moving the cube did not change the viewport image")
    check(viewport.stats["transform_updates"] > before["transform_updates"], "no instance transform update")
    check(viewport.stats["full_exports"] == before["full_exports"], "an object move re-exported the scene")
    check(viewport.stats["mesh_exports"] == before["mesh_exports"], "an object move re-exported a mesh")

    # Material colour: the sphere turns from orange-red to blue; only that material is re-translated.
    before = dict(viewport.stats)
    m = bpy.data.materials["Principled"]
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.05, 0.1, 0.9, 1.0)
    yield 0.1
    yield from wait_converged()
    c = screenshot("rendered_c")
    cb, bb = c[y0:y1, x0:x1], b[y0:y1, x0:x1]
    blue_gain = float((cb[..., 2] - cb[..., 0]).mean() - (bb[..., 2] - bb[..., 0]).mean())
    print("MATERIAL blue-minus-red gain %.4f, material updates %d" % (
        blue_gain, viewport.stats["material_updates"] - before["material_updates"]))
    check(blue_gain > 0.005, "the material colour change did not show in the viewport")
    check(viewport.stats["material_updates"] > before["material_updates"], "no in-place material update")
    check(viewport.stats["full_exports"] == before["full_exports"], "a material edit re-exported the scene")
    check(viewport.stats["mesh_exports"] == before["mesh_exports"], "a material edit re-exported a mesh")
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1048576.0


def mode_reopen():
    setup_scene(samples=4)
    yield 0.5
    counts, rss = [], []
    for i in range(20):
        set_shading("RENDERED")
        yield 0.15
        t0 = time.time()
        while not any(r.frame is not None for r in viewport._renderers) and time.time() - t0 < 5:
            yield 0.05
        open_counts = binding.live_objects()
        check(open_counts[0] <= 1 and open_counts[1] <= 1, "open %d: %d scenes, %d sessions alive" % (
            i, open_counts[0], open_counts[1]))
        set_shading("SOLID")
        yield 0.15
        import gc
        gc.collect()
        counts.append(binding.live_objects())
        rss.append(rss_mb())
    print("REOPEN live (scenes, sessions) after each close: %s" % counts)
    print("REOPEN RSS MB: %s" % ", ".join("%.0f" % r for r in rss))
    check(all(c == (0, 0) for c in counts[1:]), "engine objects leak across viewport close: %s" % counts)
    growth = rss[-1] - rss[4]
    check(growth < 40.0, "memory grows by %.1f MB over 15 reopenings" % growth)


def mode_preview():
    scene = setup_scene()
    mats = []
    p = bpy.data.materials.new("PreviewPrincipled")
    p.use_nodes = True
    mats.append(p)

    def material_with(name, node_type):
        """A material whose surface is one shader node in place of the Principled BSDF."""
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.remove(nt.nodes["Principled BSDF"])
        node = nt.nodes.new(node_type)
        nt.links.new(node.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
        mats.append(m)
        return m, node

    material_with("PreviewGlass", "ShaderNodeBsdfGlass")
    _, em = material_with("PreviewEmission", "ShaderNodeEmission")
    em.inputs["Strength"].default_value = 3.0
    bpy.data.objects["Sphere"].data.materials[0] = p
    yield 0.3
    win, area, region, _ = view3d()
    for mat in mats:
        preview.last_preview.clear()
        with bpy.context.temp_override(window=win, area=area, region=region, id=mat):
            bpy.ops.ed.lib_id_generate_preview()
        t0 = time.time()
        while "samples" not in preview.last_preview and "error" not in preview.last_preview \
                and time.time() - t0 < 20:
            yield 0.05
        lp = dict(preview.last_preview)
        print("PREVIEW %-18s %s" % (mat.name, lp))
        check("error" not in lp, "%s: preview failed: %s" % (mat.name, lp.get("error")))
        check("samples" in lp, "%s: no preview was rendered with Rendezvous" % mat.name)
        check(lp["finite"] and lp["mean"] > 0.0, "%s: preview is black or not finite" % mat.name)


MODES = {"view": mode_view, "reopen": mode_reopen, "preview": mode_preview}


def run():
    gen = MODES[MODE]()

    def step():
        try:
            return next(gen)
        except StopIteration:
            print("PASS viewport %s" % MODE, flush=True)
            os._exit(0)
        except Exception:
            traceback.print_exc()
            print("FAIL viewport %s" % MODE, flush=True)
            os._exit(1)

    bpy.app.timers.register(step, first_interval=0.5)


run()
