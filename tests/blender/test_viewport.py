"""The 3D view's Rendered mode with Rendezvous, in a real Blender window (run_viewport.py: Xvfb).

    run_viewport.py --script test_viewport.py -- view        screenshot shows the scene (vs a final
                                                             render), object move and material colour
                                                             follow, updated in place (no re-export)
    run_viewport.py --script test_viewport.py -- reopen      close/reopen 20x: no session/memory growth
    run_viewport.py --script test_viewport.py -- preview     material previews (principled, glass, emission)
    run_viewport.py --script test_viewport.py -- volumes --vdb-writer build/tests/write_test_vdb
                                          a Volume object and a mesh volume show, as bright as in a final
                                          render; Principled Volume edits (density, colour, emission,
                                          blackbody) re-export only that medium; a missing .vdb gives the
                                          final render's warning naming the object, the rest renders
    run_viewport.py --script test_viewport.py -- volume_edits --vdb-writer build/tests/write_test_vdb
                                          moving / scaling a Volume object, another file, another frame of
                                          a sequence (in place), hiding it, adding / removing a World volume
    run_viewport.py --script test_viewport.py -- images      a generated image a script paints: as bright
                                          as a final render; a pixel change re-sends it in place, the
                                          same pixels again do not restart
    run_viewport.py --script test_viewport.py -- fluid       a fire simulation domain (Replay cache): as
                                          bright as a final render; its material, another frame, a move
                                          re-export only its medium
    run_viewport.py --script test_viewport.py -- media_toggles  a World volume and a material volume
                                          toggled 100 times each: no medium stays in the engine scene
                                          (media-free again); prints render speed before / after
    run_viewport.py --script test_viewport.py -- timer_error an unexpected exception in the viewport's
                                          timer (the session's progress poll raises 3 times): reported
                                          once (console, status text), refinement goes on to convergence

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
ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
MODE = ARGS[0] if ARGS else "view"
VDB_WRITER = ARGS[ARGS.index("--vdb-writer") + 1] if "--vdb-writer" in ARGS else None


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
    return srgb(final_render_linear())


def final_render_linear(samples=32):
    """The scene's final render with Rendezvous (scene-linear RGB, rows bottom-up)."""
    scene = bpy.context.scene
    scene.rendezvous.samples = samples
    bpy.ops.render.render()
    path = os.path.join(TMP, "final.exr")
    scene.render.image_settings.file_format = "OPEN_EXR"
    bpy.data.images["Render Result"].save_render(path)
    im = bpy.data.images.load(path, check_existing=False)
    w, h = im.size
    px = np.empty(w * h * 4, np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    return px.reshape(h, w, 4)[:, :, :3]


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
    scene = bpy.context.scene  # materials_instances.blend from scenes/blend, opened by run_viewport.py
    scene.render.engine = "RENDEZVOUS"
    scene.rendezvous.viewport_samples = samples
    scene.cycles.max_bounces = 3  # Light Paths are shared with Cycles: 3 bounces = 4 scattering vertices
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

    # Light Path > Is Camera Ray: the sphere's material glows green to the camera and stays the
    # blue Principled to every other ray. Its objects (the sphere, its twin) go to the engine
    # once per look, so the edit re-exports the scene; a move then moves both copies in place.
    before = dict(viewport.stats)
    nt = m.node_tree
    mix, glow = nt.nodes.new("ShaderNodeMixShader"), nt.nodes.new("ShaderNodeEmission")
    glow.inputs["Color"].default_value = (0.1, 0.9, 0.1, 1.0)
    nt.links.new(nt.nodes.new("ShaderNodeLightPath").outputs["Is Camera Ray"], mix.inputs["Fac"])
    nt.links.new(nt.nodes["Principled BSDF"].outputs[0], mix.inputs[1])
    nt.links.new(glow.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    yield 0.1
    yield from wait_converged()
    d = screenshot("rendered_d")
    dc = d[y0:y1, x0:x1]
    green_gain = float((dc[..., 1] - dc[..., 2]).mean() - (cb[..., 1] - cb[..., 2]).mean())
    print("LIGHT PATH green-minus-blue gain %.4f, full exports %d -> %d" % (
        green_gain, before["full_exports"], viewport.stats["full_exports"]))
    check(green_gain > 0.005, "the camera's look of the sphere did not show in the viewport")
    check(viewport.stats["full_exports"] > before["full_exports"], "a look per kind of ray without a re-export")
    before = dict(viewport.stats)
    bpy.data.objects["Sphere"].location.x += 0.6
    yield 0.1
    yield from wait_converged()
    e = screenshot("rendered_e")
    diff = float(np.abs(e[y0:y1, x0:x1] - dc).mean())
    check(diff > 0.005, "moving the sphere with two looks did not change the viewport image")
    check(viewport.stats["full_exports"] == before["full_exports"], "moving an object with two looks re-exported")
    check(viewport.stats["transform_updates"] > before["transform_updates"], "no instance transform update")
    final = final_render_display()
    corr = float(np.corrcoef(blocks(e[y0:y1, x0:x1]).ravel(), blocks(final).ravel())[0, 1])
    print("LIGHT PATH moved: image change %.4f, correlation with the final render %.3f" % (diff, corr))
    check(corr > 0.8, "the viewport with two looks does not correlate with the final render (r = %.3f)" % corr)
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
        # Ask through ID.asset_generate_preview (what ed.lib_id_generate_preview runs), not the
        # operator: Python refuses every bpy.ops call while Blender's global allow-writes switch
        # is off, and a preview job thread that flips and restores it around a main-thread draw
        # can leave it off for many seconds under CI load (CI failed on that more than once; the
        # forced redraw tried before is an operator too).  An RNA function call is not checked.
        t0 = time.time()
        while bpy.app.is_job_running("RENDER_PREVIEW") and time.time() - t0 < 20:
            yield 0.05
        preview.last_preview.clear()
        with bpy.context.temp_override(window=win, area=area, region=region):
            mat.asset_generate_preview()
        yield 0.1
        t0 = time.time()
        while "samples" not in preview.last_preview and "error" not in preview.last_preview \
                and time.time() - t0 < 20:
            yield 0.05
        lp = dict(preview.last_preview)
        print("PREVIEW %-18s %s" % (mat.name, lp))
        check("error" not in lp, "%s: preview failed: %s" % (mat.name, lp.get("error")))
        check("samples" in lp, "%s: no preview was rendered with Rendezvous" % mat.name)
        check(lp["finite"] and lp["mean"] > 0.0, "%s: preview is black or not finite" % mat.name)

# ---- media ------------------------------------------------------------------------------------------
# The volume scenes: a Volume object 'Cloud' (a ball of smoke from a .vdb, left) and a cube
# 'Fog' with a volume material (right), lit by a sun and a pale sky.  Regions in the camera
# frame as (u0, u1, v0, v1) fractions, rows bottom-up.
CLOUD = (0.16, 0.34, 0.38, 0.62)
CENTRE = (0.42, 0.58, 0.38, 0.62)
FOG = (0.66, 0.84, 0.38, 0.62)
SKY = (0.40, 0.60, 0.80, 0.95)
BOXES = {"cloud": CLOUD, "centre": CENTRE, "fog": FOG, "sky": SKY}
VOLUME_COUNTERS = ("full_exports", "mesh_exports", "material_updates", "volume_updates", "world_updates",
                   "transform_updates")


def write_vdb(name, kind=""):
    import subprocess
    check(VDB_WRITER is not None, "the volume modes need --vdb-writer")
    path = os.path.join(TMP, name)
    subprocess.run([VDB_WRITER, path] + ([kind] if kind else []), check=True)
    return path


def volume_scene(vdb, samples=4):
    """build_scenes.cloud_and_fog in the window: (scene, Volume object, its Principled
    Volume node, the Fog cube's Principled Volume)."""
    sys.path.insert(0, os.path.join(ROOT, "scenes", "blend"))
    import build_scenes
    cloud, pv, fog_pv = build_scenes.cloud_and_fog(vdb)
    return setup_scene(samples), cloud, pv, fog_pv


def viewport_film():
    """The newest viewport film (scene-linear RGB, rows bottom-up) inside the camera frame."""
    r = next(iter(viewport._renderers))
    check(r.frame is not None, "the viewport has no frame")
    arr, w, h = r.frame
    _, _, region, _ = view3d()
    check((w, h) == (region.width, region.height), "the viewport film is %dx%d, not the region's %dx%d"
          % (w, h, region.width, region.height))
    x0, y0, x1, y1 = camera_rect()
    return arr.reshape(h, w, 4)[y0:y1, x0:x1, :3].copy()


def region_mean(img, box):
    h, w = img.shape[:2]
    u0, u1, v0, v1 = box
    return img[int(v0 * h):int(v1 * h), int(u0 * w):int(u1 * w)].reshape(-1, 3).mean(axis=0)


def lum(rgb):
    return float(np.dot(rgb, [0.2126, 0.7152, 0.0722]))


def downsample(img, w, h):
    """Box-filters img to w x h pixels (each output pixel the mean of the input pixels it covers)."""
    ys = np.linspace(0, img.shape[0], h + 1).astype(int)
    xs = np.linspace(0, img.shape[1], w + 1).astype(int)
    rows = np.add.reduceat(img, ys[:-1], axis=0) / np.diff(ys)[:, None, None]
    return np.add.reduceat(rows, xs[:-1], axis=1) / np.diff(xs)[None, :, None]


def matches_final(img, name, boxes=BOXES):
    """The viewport film shows what a final render of the same scene shows: the regions'
    luminances agree within BRIGHTNESS_TOLERANCE.  Returns the regions' luminances."""
    final = final_render_linear(samples=FINAL_SAMPLES)
    small = downsample(img, final.shape[1], final.shape[0])
    out, bad = {}, []
    for label, box in boxes.items():
        v, f = lum(region_mean(small, box)), lum(region_mean(final, box))
        out[label] = v
        print("  %-28s %-6s viewport %.4f final %.4f (%+.1f %%)" % (name, label, v, f, 100.0 * (v - f) / max(f, 1e-6)))
        if abs(v - f) > BRIGHTNESS_TOLERANCE * f + 0.002:
            bad.append("%s (%.4f vs %.4f)" % (label, v, f))
    if bad and os.environ.get("RDV_VIEWPORT_OUT"):
        np.save(os.path.join(TMP, "viewport_small.npy"), small)
        np.save(os.path.join(TMP, "final.npy"), final)
    check(not bad, "%s: the viewport differs from the final render in %s" % (name, ", ".join(bad)))
    return out


def wait_edit(before, timeout=10.0):
    """After an edit: yields until the viewport restarted (view_update ran) and converged."""
    t0 = time.time()
    while viewport.stats["restarts"] == before["restarts"] and time.time() - t0 < 3.0:
        yield 0.05
    check(viewport.stats["restarts"] > before["restarts"], "the edit did not restart the viewport")
    yield from wait_settled(timeout)
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])


def wait_settled(timeout=10.0):
    """Yields until the viewport converged and no further update restarted it (some edits
    reach view_update in steps: a domain move is a transform, then its simulation)."""
    while True:
        restarts = viewport.stats["restarts"]
        yield from wait_converged(timeout)
        yield 0.3
        if viewport.stats["restarts"] == restarts:
            return


def edit(name, action, boxes=BOXES, against_final=True):
    """Applies action(), waits for the new viewport image and checks it against a final
    render (not for a viewport-only change): (region luminances, counter deltas)."""
    before = dict(viewport.stats)
    action()
    yield from wait_edit(before)
    delta = {k: viewport.stats[k] - before[k] for k in VOLUME_COUNTERS}
    print("EDIT %-28s %s" % (name, " ".join("%s %d" % kv for kv in delta.items() if kv[1]) or "no updates"))
    img = viewport_film()
    if not against_final:
        return {label: lum(region_mean(img, box)) for label, box in boxes.items()}, delta
    return matches_final(img, name, boxes), delta


def in_place(delta, what, counter="volume_updates"):
    """The edit was applied in place (`counter` moved) without re-exporting the scene or a mesh."""
    check(delta["full_exports"] == 0, "%s re-exported the whole scene" % what)
    check(delta["mesh_exports"] == 0, "%s re-exported a mesh" % what)
    check(delta[counter] >= 1, "%s: no in-place update (%s)" % (what, counter))


def start_volume_viewport(vdb):
    scene, cloud, pv, fog_pv = volume_scene(vdb)
    yield 0.3
    set_shading("RENDERED")
    yield from wait_converged()
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])
    regions = matches_final(viewport_film(), "first image")
    check(regions["cloud"] < 0.9 * regions["sky"], "the Volume object does not show in the viewport")
    check(regions["fog"] < 0.9 * regions["sky"], "the mesh volume does not show in the viewport")
    return scene, cloud, pv, fog_pv, regions


def mode_volumes():
    """A Volume object and a mesh volume in the viewport, as bright as the final render;
    material edits (density, colour, emission, blackbody) update only that medium; a
    missing .vdb is the final render's warning naming the object, the rest renders."""
    scene, cloud, pv, fog_pv, base = yield from start_volume_viewport(write_vdb("cloud.vdb"))

    def set_input(node, socket, value):
        return lambda: setattr(node.inputs[socket], "default_value", value)

    r, d = yield from edit("cloud density 8 -> 0.5", set_input(pv, "Density", 0.5))
    check(r["cloud"] > base["cloud"] * 1.1, "lowering the density did not show")
    in_place(d, "a density edit")
    prev = r
    r, d = yield from edit("cloud colour -> blue", set_input(pv, "Color", (0.1, 0.2, 0.9, 1.0)))
    check(abs(r["cloud"] - prev["cloud"]) > 0.01, "the colour edit did not show")
    in_place(d, "a colour edit")
    prev = r
    r, d = yield from edit("cloud emission 2", set_input(pv, "Emission Strength", 2.0))
    check(r["cloud"] > prev["cloud"] + 0.05, "the emission did not show")
    in_place(d, "an emission edit")

    def blackbody():
        pv.inputs["Emission Strength"].default_value = 0.0
        pv.inputs["Blackbody Intensity"].default_value = 1.0
        pv.inputs["Temperature"].default_value = 1500.0
    prev = r
    r, d = yield from edit("cloud blackbody 1500 K", blackbody)
    in_place(d, "a blackbody edit")
    prev = r
    r, d = yield from edit("cloud temperature 2500 K", set_input(pv, "Temperature", 2500.0))
    check(r["cloud"] > prev["cloud"] + 0.05, "raising the temperature did not brighten the glow")
    in_place(d, "a temperature edit")

    # The mesh's volume material: an ordinary in-place material update.
    prev = r
    r, d = yield from edit("fog density 1.5 -> 6", set_input(fog_pv, "Density", 6.0))
    check(abs(r["fog"] - prev["fog"]) > 0.02, "the mesh volume's density edit did not show")
    in_place(d, "a mesh volume material edit", "material_updates")

    # A missing file: the final render's warning naming the object; the fog still renders.
    from rendezvous.engine import final as final_engine
    missing = os.path.join(TMP, "no_such_cloud.vdb")
    r, d = yield from edit("cloud file missing", lambda: setattr(cloud.data, "filepath", missing))
    warnings = viewport.stats["warnings"]
    final_warnings = [m for m in final_engine.last_render["messages"] if "Cloud" in m]
    print("VIEWPORT WARNINGS: %s\nFINAL WARNINGS: %s" % (warnings, final_warnings))
    check(final_warnings and any("no_such_cloud" in m for m in final_warnings), "the final render gave no warning")
    check(all(m in warnings for m in final_warnings), "the viewport does not give the final render's warning")
    print("VIEWPORT STATUS: %s" % viewport.stats["status"])
    check(any(m in viewport.stats["status"] for m in final_warnings), "the viewport's status text does not show the warning")
    check(abs(r["cloud"] - r["sky"]) < 0.05 * r["sky"], "the missing volume still shows")
    check(r["fog"] < 0.9 * r["sky"], "the rest of the scene no longer renders")
    r, d = yield from edit("cloud file back", lambda: setattr(cloud.data, "filepath", os.path.join(TMP, "cloud.vdb")))
    check(not any("no_such_cloud" in w for w in viewport.stats["warnings"]), "the warning stays after the file is back")


def mode_volume_edits():
    """Moving / scaling a Volume object, another file, another frame of a sequence, hiding
    it, adding and removing a World volume: the viewport shows what a final render shows."""
    cloud_vdb, fire_vdb = write_vdb("cloud.vdb"), write_vdb("fire.vdb", "fire")
    scene, cloud, pv, fog_pv, base = yield from start_volume_viewport(cloud_vdb)

    r, d = yield from edit("cloud moved to the centre", lambda: setattr(cloud.location, "x", -0.2))
    check(r["centre"] < 0.9 * r["sky"] and r["cloud"] > base["cloud"] * 1.1, "the move did not show")
    in_place(d, "a Volume object move")
    r, d = yield from edit("cloud scaled 0.7 -> 1", lambda: setattr(cloud, "scale", (1.0, 1.0, 1.0)))
    in_place(d, "a Volume object scale")
    r, d = yield from edit("cloud file -> two balls", lambda: setattr(cloud.data, "filepath", fire_vdb))
    in_place(d, "another .vdb file")

    # A two-frame sequence: frame 1 the ball, frame 2 the two balls.
    import shutil
    shutil.copy(cloud_vdb, os.path.join(TMP, "seq_0001.vdb"))
    shutil.copy(fire_vdb, os.path.join(TMP, "seq_0002.vdb"))

    def sequence():
        vol = cloud.data
        vol.filepath = os.path.join(TMP, "seq_0001.vdb")
        vol.is_sequence, vol.frame_start, vol.frame_duration, vol.sequence_mode = True, 1, 2, "CLIP"
        scene.frame_set(1)
    r1, d = yield from edit("cloud sequence at frame 1", sequence)
    r2, d = yield from edit("frame 1 -> 2", lambda: scene.frame_set(2))
    check(abs(r2["centre"] - r1["centre"]) > 0.01, "the frame change did not show")
    in_place(d, "a frame change")

    # Visibility (the viewport's own: the final render still has the object).
    r, d = yield from edit("cloud hidden", lambda: cloud.hide_set(True), against_final=False)
    check(abs(r["centre"] - r["sky"]) < 0.03 * r["sky"], "the hidden volume still shows (%.4f vs sky %.4f)"
          % (r["centre"], r["sky"]))
    r, d = yield from edit("cloud shown", lambda: cloud.hide_set(False))
    check(abs(r["centre"] - r2["centre"]) < 0.03 * r2["centre"], "the volume did not come back")

    # A World volume: glowing fog everywhere (it hides the sky and the sun), added and
    # removed in place.
    world = scene.world
    nt = world.node_tree
    fog = nt.nodes.new("ShaderNodeVolumePrincipled")
    fog.inputs["Density"].default_value = 0.05
    fog.inputs["Emission Strength"].default_value = 0.02
    out = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputWorld")
    r, d = yield from edit("world volume added", lambda: nt.links.new(fog.outputs["Volume"], out.inputs["Volume"]))
    check(abs(r["sky"] - base["sky"]) > 0.05 * base["sky"], "the world volume did not show")
    in_place(d, "adding a world volume", "world_updates")
    r, d = yield from edit("world volume removed", lambda: nt.links.remove(out.inputs["Volume"].links[0]))
    check(abs(r["sky"] - base["sky"]) < 0.02 * base["sky"], "the world volume stays after its removal")
    in_place(d, "removing a world volume", "world_updates")


# The fire scene: the domain fills the middle of the frame, the flames rise in its lower half.
FIRE_BOXES = {"frame": (0.0, 1.0, 0.0, 1.0), "lower": (0.3, 0.8, 0.1, 0.5), "upper": (0.3, 0.8, 0.5, 0.9)}


def camera_only_scene(samples=4):
    """setup_scene with every object but the camera removed, and the build_scenes module the
    modes that build their own objects use: (scene, build_scenes)."""
    sys.path.insert(0, os.path.join(ROOT, "scenes", "blend"))
    import build_scenes
    scene = setup_scene(samples=samples)
    for ob in list(scene.objects):
        if ob.type != "CAMERA":
            bpy.data.objects.remove(ob)
    return scene, build_scenes


def mode_fluid():
    """A smoke / fire simulation domain (Replay cache) in the viewport, as bright as in a
    final render; its material, another frame of the simulation and a move re-export only
    its medium."""
    import math
    scene, build_scenes = camera_only_scene()
    cam = scene.camera
    cam.location, cam.rotation_euler = (0.0, -6.0, 1.0), (math.radians(90), 0.0, 0.0)
    cam.data.lens, cam.data.sensor_fit = 50.0, "AUTO"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 64, 48, 100
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    domain = build_scenes.fire_domain(os.path.join(TMP, "fluid_cache"), 8)
    bpy.data.objects["Burner"].hide_set(True)  # hidden in final renders only (hide_render); frames cached
    pv = domain.data.materials[0].node_tree.nodes["Principled Volume"]
    yield 0.3
    set_shading("RENDERED")
    yield from wait_converged()
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])
    base = matches_final(viewport_film(), "fire at frame 8", FIRE_BOXES)
    check(base["lower"] > 0.01, "the fire does not glow in the viewport")

    r, d = yield from edit("fire density 5 -> 1", lambda: setattr(pv.inputs["Density"], "default_value", 1.0),
                           FIRE_BOXES)
    check(abs(r["frame"] - base["frame"]) > 0.05 * base["frame"], "the density edit did not show")
    in_place(d, "a domain's material edit")
    r, d = yield from edit("fire frame 8 -> 5", lambda: scene.frame_set(5), FIRE_BOXES)
    in_place(d, "a simulation frame change")
    # A final render re-evaluates the domain, which sends the viewport a geometry update
    # for it: the same grids must not restart the viewport.
    before = dict(viewport.stats)
    final_render_linear(samples=1)
    yield from wait_settled()
    print("FLUID after a final render: %d restarts, %d volume updates" % (
        viewport.stats["restarts"] - before["restarts"], viewport.stats["volume_updates"] - before["volume_updates"]))
    check(viewport.stats["restarts"] == before["restarts"], "a final render restarted the viewport")
    x_before = centroid_x(viewport_film())
    r, d = yield from edit("domain moved", lambda: setattr(domain.location, "x", -0.3), FIRE_BOXES)
    x_after = centroid_x(viewport_film())
    print("FLUID glow centroid x %.3f -> %.3f of the frame" % (x_before, x_after))
    check(x_after < x_before - 0.05, "the fire did not move with its domain")
    in_place(d, "a domain move")
    check(not any("Smoke Domain" in w for w in viewport.stats["warnings"]), "warnings about the domain: %s"
          % viewport.stats["warnings"])


# The image scene: an emissive plane filling the camera's view, its colour a generated image
# a script fills (left half bright, right half dark; a stroke swaps them).
IMAGE_BOXES = {"left": (0.1, 0.4, 0.1, 0.9), "right": (0.6, 0.9, 0.1, 0.9)}


def mode_images():
    """A generated image a script paints: the viewport shows its pixels as a final render
    does; changing them re-sends the image and sets its material in place; setting the same
    pixels again (an update that changes nothing) does not restart the viewport."""
    scene, build_scenes = camera_only_scene()
    cam = scene.camera
    cam.location, cam.rotation_euler = (0.0, 0.0, 3.0), (0.0, 0.0, 0.0)
    cam.data.type, cam.data.ortho_scale, cam.data.sensor_fit = "ORTHO", 1.8, "AUTO"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 64, 64, 100
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    image = bpy.data.images.new("Painted", 32, 32)
    halves = np.zeros((32, 32, 4), np.float32)
    halves[..., 3] = 1.0
    halves[:, :16, :3] = (0.9, 0.7, 0.3)
    halves[:, 16:, :3] = (0.1, 0.2, 0.3)
    image.pixels.foreach_set(halves.reshape(-1))
    m = build_scenes.emission_material("PaintedMat")
    nt = m.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    nt.links.new(tex.outputs["Color"], nt.nodes["Emission"].inputs["Color"])
    me = build_scenes.quad_mesh("Canvas", 2.0)
    uv = me.uv_layers.new(name="UVMap")
    for loop in me.loops:
        uv.data[loop.index].uv = [(0, 0), (1, 0), (1, 1), (0, 1)][loop.vertex_index]
    me.materials.append(m)
    build_scenes.link(bpy.data.objects.new("Canvas", me))
    yield 0.3
    set_shading("RENDERED")
    yield from wait_converged()
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])
    base = matches_final(viewport_film(), "painted image", IMAGE_BOXES)
    check(base["left"] > 2 * base["right"], "the image's halves do not show (left %.3f, right %.3f)"
          % (base["left"], base["right"]))

    def stroke():
        image.pixels.foreach_set(halves[:, ::-1].reshape(-1))
        image.update()
    r, d = yield from edit("stroke swaps the halves", stroke, IMAGE_BOXES)
    check(r["right"] > 2 * r["left"], "the new pixels do not show (left %.3f, right %.3f)" % (r["left"], r["right"]))
    in_place(d, "a pixel change", "material_updates")

    # The same pixels again: Blender sends an update, nothing the engine sees changed.
    before = dict(viewport.stats)
    image.pixels.foreach_set(halves[:, ::-1].reshape(-1))
    image.update()
    t0 = time.time()
    while time.time() - t0 < 1.5:
        yield 0.1
    delta = {k: viewport.stats[k] - before[k] for k in ("image_updates", "restarts", "material_updates")}
    print("IMAGES unchanged pixels: %(image_updates)d image updates, %(restarts)d restarts, "
          "%(material_updates)d material updates" % delta)
    check(delta["image_updates"] >= 1, "Blender sent no image update (the check below would prove nothing)")
    check(delta["restarts"] == 0, "unchanged pixels restarted the viewport")


def media_count(r):
    """How many media the viewport's engine scene holds (0: has_media() is false)."""
    media = r.rscene.summary().get("media", "none")
    return 0 if media == "none" else media["homogeneous"] + media["grid"]


def engine_seconds(r, samples=4):
    """Fastest of three renders of the viewport's engine scene at its region size (the
    viewport idle: converged, no session), in seconds."""
    best = 1e30
    with r.lock:
        w, h = r.size
        for _ in range(3):
            t0 = time.perf_counter()
            s = binding.Session(r.rscene, {"width": w // 2, "height": h // 2, "samples": samples, "max_bounces": 4,
                                           "seed": 1, "threads": 0})
            s.start()
            s.wait()
            s.close()
            best = min(best, time.perf_counter() - t0)
    return best


def mode_media_toggles():
    """A World volume and a material volume each linked and unlinked 100 times (every edit
    reaches the viewport in place): afterwards the engine scene holds no medium, as before
    the first toggle; the engine's render time media-free and after the toggles is printed."""
    scene = setup_scene(samples=4)
    world_nt = scene.world.node_tree
    world_out = next(n for n in world_nt.nodes if n.bl_idname == "ShaderNodeOutputWorld")
    world_fog = world_nt.nodes.new("ShaderNodeVolumePrincipled")
    world_fog.inputs["Density"].default_value = 0.02
    mat_nt = bpy.data.materials["Metal"].node_tree
    mat_out = mat_nt.nodes["Material Output"]
    mat_fog = mat_nt.nodes.new("ShaderNodeVolumePrincipled")
    yield 0.3
    set_shading("RENDERED")
    yield from wait_converged()
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])
    r = next(iter(viewport._renderers))
    check(media_count(r) == 0, "the scene has media before any volume was added")
    media_free = engine_seconds(r)

    toggles = (("world", world_nt, world_fog, world_out, "world_updates"),
               ("material", mat_nt, mat_fog, mat_out, "material_updates"))
    t0 = time.time()
    for label, nt, fog, out, counter in toggles:
        before, base, t1 = viewport.stats[counter], media_count(r), time.time()
        for i in range(100):
            nt.links.new(fog.outputs["Volume"], out.inputs["Volume"])
            bpy.context.view_layer.update()  # evaluates the edit: Blender calls view_update
            if i == 0:
                check(media_count(r) == base + 1, "the %s volume did not reach the engine" % label)
            nt.links.remove(out.inputs["Volume"].links[0])
            bpy.context.view_layer.update()
            if i % 10 == 9:
                yield 0.0  # let the window draw now and then
        updates = viewport.stats[counter] - before
        print("TOGGLES %s volume: 100 on/off in %.1f s, %d in-place %s, %d media after" % (
            label, time.time() - t1, updates, counter, media_count(r)))
        check(updates >= 200, "only %d of the 200 %s volume edits reached the viewport" % (updates, label))
    toggle_seconds = time.time() - t0
    yield from wait_converged()
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])
    left = media_count(r)
    after = engine_seconds(r)
    print("MEDIA after 200 volume toggles (%.1f s): %d media in the engine scene; render %dx%d 4 spp: media-free "
          "%.1f ms, after the toggles %.1f ms (x%.3f)" % (toggle_seconds, left, r.size[0] // 2, r.size[1] // 2,
                                                          1e3 * media_free, 1e3 * after, after / media_free))
    check(left == 0, "%d media taken away by edits stay in the engine scene (has_media() stays true)" % left)


class _Tee:
    """Copies what is written to a stream (the console) into a list, for counting reports."""

    def __init__(self, stream, lines):
        self.stream, self.lines = stream, lines

    def write(self, text):
        self.lines.append(text)
        return self.stream.write(text)

    def __getattr__(self, name):
        return getattr(self.stream, name)


def mode_timer_error():
    """An unexpected exception in the viewport's timer (the binding's progress poll raises
    RuntimeError on three polls in a row, during the full-resolution stage) is reported once
    (console, status text, viewport.stats["errors"]), and the timer lives on: the viewport
    goes on refining (samples read grow, new frames uploaded) up to its sample count."""
    setup_scene(samples=12)
    yield 0.3
    set_shading("RENDERED")
    t0 = time.time()
    while time.time() - t0 < 10:
        rs = list(viewport._renderers)
        if rs and rs[0].stage == len(viewport.STAGES) - 1 and rs[0].read_samples >= 1:
            break
        yield 0.01
    r = next(iter(viewport._renderers))
    check(r.stage == len(viewport.STAGES) - 1 and not r.converged, "the viewport is not refining at full resolution "
          "(stage %d, %d samples, converged %s)" % (r.stage, r.read_samples, r.converged))
    check(not viewport.stats["errors"], "viewport errors: %s" % viewport.stats["errors"])

    message = "injected poll failure"
    raised = []
    original = binding.Session.progress

    def failing_progress(session):
        # Only the timer's polls raise (view_draw catches its own exceptions anyway).
        if len(raised) < 3 and any(f.f_code.co_name == "_timer" for f in _frames()):
            raised.append(time.time())
            raise RuntimeError(message)
        return original(session)

    console = []
    sys.stdout, sys.stderr = _Tee(sys.stdout, console), _Tee(sys.stderr, console)
    binding.Session.progress = failing_progress
    try:
        t0 = time.time()
        while len(raised) < 3 and time.time() - t0 < 3:
            yield 0.01
        check(raised, "the timer did not poll the session")
        samples, uploads, status = r.read_samples, viewport.stats["uploads"], ""
        t0 = time.time()
        while not r.converged and time.time() - t0 < 15:
            status = status if message in status else viewport.stats["status"]
            yield 0.05
        status = status if message in status else viewport.stats["status"]
    finally:
        binding.Session.progress = original
        sys.stdout, sys.stderr = sys.stdout.stream, sys.stderr.stream
    printed = "".join(console).count(message)
    errors = [e for e in viewport.stats["errors"] if message in e]
    print("TIMER ERROR: samples %d -> %d of %d, uploads %d -> %d, converged %s; reported %d times on the console, "
          "%d in stats; status: %s" % (samples, r.read_samples, 12, uploads,
                                        viewport.stats["uploads"], r.converged, printed, len(errors), status))
    check(len(raised) == 3, "the timer stopped polling after %d exceptions" % len(raised))
    check(r.read_samples > samples and r.converged, "the viewport stopped refining after the exception "
          "(samples %d -> %d, converged %s)" % (samples, r.read_samples, r.converged))
    check(viewport.stats["uploads"] > uploads, "no new frame was drawn after the exception")
    check(len(errors) == 1, "the exception was reported %d times in viewport.stats['errors']" % len(errors))
    check(printed >= 1, "the exception was not printed to the console")
    check("".join(console).count("Traceback") == 1, "the traceback was printed %d times, not once"
          % "".join(console).count("Traceback"))
    check(message in status, "the status text never showed the error")


def _frames():
    f = sys._getframe(1)
    while f is not None:
        yield f
        f = f.f_back


def centroid_x(img):
    """The luminance centroid's x as a fraction of the image width."""
    l = img.sum(axis=2)
    return float((l.sum(axis=0) * np.arange(l.shape[1])).sum() / max(l.sum(), 1e-12)) / l.shape[1]


# Region means of the viewport (4 spp on the whole region, box-filtered to 64x48) against the
# final render (64x48 at FINAL_SAMPLES spp, fixed seeds): see the printed differences.
FINAL_SAMPLES = 64
BRIGHTNESS_TOLERANCE = 0.04


MODES = {"view": mode_view, "reopen": mode_reopen, "preview": mode_preview, "volumes": mode_volumes, "volume_edits": mode_volume_edits,
         "fluid": mode_fluid, "images": mode_images, "timer_error": mode_timer_error,
         "media_toggles": mode_media_toggles}


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
