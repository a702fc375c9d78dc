"""Images without a single file on disk render as Cycles renders them (issue 12 case 4):
each scene is an emissive plane filling an orthographic view, its colour an Image Texture
of one kind, rendered by Cycles and by Rendezvous in this Blender process. The image
means agree within 1% (each channel) and every bright 16x16 block's mean within 5%.
Before images went to the engine these rendered as the image's average colour (flat).

    run_blender.py --script test_images.py -- [--samples N] SCENE [SCENE ...]

SCENE: generated (Blender's UV grid, generated, Linear), script_float (a float image a
script filled, Closest, Repeat), script_byte (a byte image a script filled, sRGB, Cubic,
Extend), sequence (an image sequence at a frame: start, offset, cyclic), udim (two UDIM
tiles on a plane spanning both), movie (a movie's frame, read by OpenImageIO).
"""

import argparse
import os
import sys

import bpy
import numpy as np

ROOT = os.environ.get("RDV_REPO_ROOT") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scenes", "blend"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import build_scenes  # noqa: E402
import verdicts  # noqa: E402
from test_brightness import factory_state, finish_family, out_dir, render_cycles, render_rendezvous  # noqa: E402

TMP = os.environ.get("RDV_TEST_TMP") or bpy.app.tempdir
MEAN_TOLERANCE = 0.01
BLOCK = 16
BLOCK_TOLERANCE = 0.05
BRIGHT = 0.1  # a block is bright if its mean is at least this fraction of the brightest block's


# ---- scenes -------------------------------------------------------------------------------
def screen(image, interpolation="Linear", extension="REPEAT", uv_scale=(1.0, 1.0), uv_offset=(0.0, 0.0),
           size=(2.0, 2.0)):
    """An emissive plane showing `image`, filling an orthographic camera's view; returns the
    Image Texture node (after build_scenes.reset())."""
    scene = bpy.context.scene
    me = build_scenes.quad_mesh("Screen", *size)
    uv = me.uv_layers.new(name="UVMap")
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
    for loop in me.loops:
        cu, cv = corners[loop.vertex_index]
        uv.data[loop.index].uv = (uv_offset[0] + cu * uv_scale[0], uv_offset[1] + cv * uv_scale[1])
    m = build_scenes.emission_material("ScreenMat", strength=1.0)
    nt = m.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = interpolation
    tex.extension = extension
    nt.links.new(tex.outputs["Color"], nt.nodes["Emission"].inputs["Color"])
    me.materials.append(m)
    build_scenes.link(bpy.data.objects.new("Screen", me))
    cam = build_scenes.camera_down(3.0)
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = 0.9 * max(size)  # the plane covers every pixel's filter
    scene.render.resolution_x = int(64 * size[0] / max(size))
    scene.render.resolution_y = int(64 * size[1] / max(size))
    return tex


def pattern(w, h, hdr):
    """A test pattern: rings, diagonal stripes and a ramp, RGBA (bottom row first)."""
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    r = np.hypot(x - w * 0.3, y - h * 0.6)
    px = np.empty((h, w, 4), np.float32)
    px[..., 0] = 0.5 + 0.5 * np.sin(r * 0.6)
    px[..., 1] = ((x + y) // 4 % 2) * 0.8 + 0.1
    px[..., 2] = x / (w - 1)
    px[..., 3] = 1.0
    if hdr:
        px[..., :3] *= 1.0 + 2.0 * (y / (h - 1))[..., None]
    return px


def write_png(path, px):
    h, w = px.shape[:2]
    im = bpy.data.images.new("tmp_write", w, h)
    im.pixels.foreach_set(px.reshape(-1))
    im.filepath_raw = path
    im.file_format = "PNG"
    im.save()
    bpy.data.images.remove(im)


def scene_generated():
    # About a texel a pixel: at 4 texels a pixel (256 x 256) the engine's MIP levels average
    # the grid's linear texels while Cycles averages bilinear sRGB samples after conversion
    # (1.2% brighter on this grid; the same for files: not the image's source).
    build_scenes.reset()
    im = bpy.data.images.new("UV Grid", 64, 64)
    im.generated_type = "UV_GRID"
    screen(im)


def scene_script_float():
    build_scenes.reset()
    im = bpy.data.images.new("Script Float", 32, 24, float_buffer=True)
    screen(im, "Closest", "REPEAT", uv_scale=(2.0, 2.0))
    im.pixels.foreach_set(pattern(32, 24, hdr=True).reshape(-1))


def scene_script_byte():
    build_scenes.reset()
    im = bpy.data.images.new("Script Byte", 48, 40)
    screen(im, "Cubic", "EXTEND", uv_scale=(1.5, 1.5), uv_offset=(-0.25, -0.25))
    im.pixels.foreach_set(pattern(48, 40, hdr=False).reshape(-1))


def scene_sequence():
    build_scenes.reset()
    d = os.path.join(TMP, "sequence")
    os.makedirs(d, exist_ok=True)
    for f in range(1, 5):
        px = pattern(32, 32, hdr=False)
        px[..., f % 3] *= 0.2  # each frame its own colours
        px[..., :3] = np.roll(px[..., :3], 6 * f, axis=1)
        write_png(os.path.join(d, "frame_%03d.png" % f), px)
    im = bpy.data.images.load(os.path.join(d, "frame_001.png"))
    im.source = "SEQUENCE"
    tex = screen(im)
    iu = tex.image_user
    iu.frame_duration = 4
    iu.frame_start = 3
    iu.frame_offset = 1
    iu.use_cyclic = True
    bpy.context.scene.frame_set(8)  # (8 - 3 + 1) cyclic over 4 -> 2, offset 1: frame_003.png


def check_sequence_frames():
    """The sequence scene at other frames, small and quick: before its start, past its end
    (cyclic), and a frame whose file does not exist (magenta in both)."""
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = 32  # about a texel a pixel
    failures = []
    for f in (1, 2, 3, 6, 7, 12):
        scene.frame_set(f)
        ref, _ = render_cycles(scene, 4, os.path.join(out_dir(), "images_sequence_%d_cycles.exr" % f))
        test, _ = render_rendezvous(scene, 4, os.path.join(out_dir(), "images_sequence_%d_rendezvous.exr" % f))
        mref, mtest = ref.reshape(-1, 3).mean(axis=0), test.reshape(-1, 3).mean(axis=0)
        print("  sequence at frame %2d: cycles mean %s  rendezvous mean %s" % (f, np.round(mref, 4), np.round(mtest, 4)))
        if np.abs(mtest - mref).max() > 0.02 * max(mref.max(), 0.05):
            failures.append("frame %d: Cycles %s, Rendezvous %s" % (f, np.round(mref, 3), np.round(mtest, 3)))
    return failures


def scene_udim():
    build_scenes.reset()
    d = os.path.join(TMP, "udim")
    os.makedirs(d, exist_ok=True)
    for tile, scale in ((1001, 1.0), (1002, 0.6)):
        px = pattern(32, 32, hdr=False)
        px[..., :3] *= scale
        write_png(os.path.join(d, "tiles.%d.png" % tile), px)
    im = bpy.data.images.load(os.path.join(d, "tiles.1001.png"))
    im.source = "TILED"
    screen(im, uv_scale=(2.0, 1.0), size=(4.0, 2.0))


def scene_movie():
    build_scenes.reset()
    d = os.path.join(TMP, "movie")
    os.makedirs(d, exist_ok=True)
    movie = os.path.join(d, "movie.mp4")
    scene = bpy.context.scene
    # Three patterned frames through the sequencer into a movie, by Blender's own encoder.
    for f in range(1, 4):
        px = pattern(32, 32, hdr=False)
        px[..., :3] = np.roll(px[..., :3], 10 * f, axis=0)
        write_png(os.path.join(d, "src_%d.png" % f), px)
    scene.render.resolution_x = scene.render.resolution_y = 32
    scene.frame_start, scene.frame_end = 1, 3
    se = scene.sequence_editor_create()
    strip = se.sequences.new_image("frames", os.path.join(d, "src_1.png"), channel=1, frame_start=1)
    for f in (2, 3):
        strip.elements.append("src_%d.png" % f)
    scene.render.image_settings.file_format = "FFMPEG"
    scene.render.ffmpeg.format = "MPEG4"
    scene.render.ffmpeg.codec = "H264"
    scene.render.ffmpeg.constant_rate_factor = "LOSSLESS"
    scene.render.filepath = movie
    scene.render.use_file_extension = False
    bpy.ops.render.render(animation=True)
    scene.sequence_editor_clear()
    scene.render.use_file_extension = True
    im = bpy.data.images.load(movie)
    tex = screen(im)
    tex.image_user.frame_duration = 3
    tex.image_user.frame_start = 1
    bpy.context.scene.frame_set(2)


def scene_painted():
    build_scenes.reset()
    path = os.path.join(TMP, "painted.png")
    write_png(path, pattern(32, 32, hdr=False))
    im = bpy.data.images.load(path)
    screen(im)
    px = pattern(32, 32, hdr=False)
    px[8:24, 8:24, :3] = (0.9, 0.2, 0.1)  # a stroke over the file's pixels, not saved
    im.pixels.foreach_set(px.reshape(-1))
    print("painted: is_dirty", im.is_dirty, "source", im.source)


SCENES = {"painted": scene_painted, "generated": scene_generated, "script_float": scene_script_float, "script_byte": scene_script_byte,
          "sequence": scene_sequence, "udim": scene_udim, "movie": scene_movie}


# ---- comparison ---------------------------------------------------------------------------
def compare(name, ref, test):
    """(ok, mean ratio of the worst channel, worst bright block's relative difference)."""
    mref, mtest = ref.reshape(-1, 3).mean(axis=0), test.reshape(-1, 3).mean(axis=0)
    ratios = [t / r for t, r in zip(mtest, mref) if r > 0.02]
    worst_ratio = max(ratios, key=lambda x: abs(x - 1.0))
    h, w = ref.shape[0] // BLOCK, ref.shape[1] // BLOCK
    blocks = lambda a: a[:h * BLOCK, :w * BLOCK].mean(axis=2).reshape(h, BLOCK, w, BLOCK).mean(axis=(1, 3))
    bref, btest = blocks(ref), blocks(test)
    bright = bref >= BRIGHT * bref.max()
    rel = np.abs(btest - bref) / np.maximum(bref, 1e-9)
    worst_block = float(rel[bright].max())
    ok = abs(worst_ratio - 1.0) <= MEAN_TOLERANCE and worst_block <= BLOCK_TOLERANCE
    print("IMAGES %-13s cycles mean %s  rendezvous mean %s  worst channel ratio %.4f  worst bright block %.4f "
          "(%d blocks)  -> %s" % (name, np.round(mref, 4), np.round(mtest, 4), worst_ratio, worst_block,
                                  int(bright.sum()), "ok" if ok else "FAIL"))
    return ok, worst_ratio, worst_block


def check_scene(name, samples, odir, failures):
    SCENES[name]()
    scene = bpy.context.scene
    bpy.context.view_layer.update()
    ref, tc = render_cycles(scene, samples, os.path.join(odir, "images_%s_cycles.exr" % name))
    test, tr = render_rendezvous(scene, samples, os.path.join(odir, "images_%s_rendezvous.exr" % name))
    print("  %s: Cycles %.2f s, Rendezvous %.2f s" % (name, tc, tr))
    ok, ratio, block = compare(name, ref, test)
    if not ok:
        failures.append("%s: mean ratio %.4f, worst bright block %.1f%% off" % (name, ratio, 100 * block))
    if name == "sequence":
        failures += ["sequence " + f for f in check_sequence_frames()]


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=32)
    ap.add_argument("--verdicts", help="write each scene's verdict into this directory (verdicts.py)")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args(argv)
    odir = out_dir()
    names = a.scenes or list(SCENES)
    failures = verdicts.run_members(names, lambda name, f: check_scene(name, a.samples, odir, f), a.verdicts,
                                   factory_state)
    finish_family("IMAGES", names, failures, odir, a.verdicts)

main()
