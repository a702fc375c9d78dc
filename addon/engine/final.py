"""Final renders (F12, `blender -b ... -f N` / `-a`): export, start the engine session in
its own threads, stream the film into the RenderResult every ~0.5 s, poll test_break()."""

import os
import time
import traceback

import bpy
import numpy as np

from .. import binding
from ..binding import EngineError, LibraryError
from ..export import SceneExporter, ExportError, SettingsError, session_settings, resolution, border_rect
from ..export.settings import INTEGRATOR_LABELS, auto_choice_text, part_output_path, scene_hash
from ..utils import Messages
from .passes import enabled_passes, light_pass_settings, wants_cryptomatte
from ..utils.images import image_average, clear_cache

PUSH_INTERVAL = 0.5   # seconds between film copies into Blender

# For tests and tools: what the last render did, and an extra cancel request.
last_render = {}
cancel_hook = None  # callable() -> bool; True cancels like test_break()
POLL_INTERVAL = 0.02  # seconds between test_break() polls (cancel within 100 ms)

def _integrator_label(settings):
    return INTEGRATOR_LABELS.get(settings.get("integrator"), "?")


def stop_and_close(session, rscene):
    """Stops the engine's render threads and frees the session and scene (either may be None)."""
    if session is not None:
        try:
            session.cancel()
        except EngineError:
            pass
        session.close()
    if rscene is not None:
        rscene.close()


def _metropolis_text(session):
    """Acceptance per mutation type and the brightness estimate of a Metropolis render."""
    try:
        st = session.stats()
    except EngineError:
        return ""
    if "warning" in st:
        return st["warning"]
    if "b" not in st:
        return ""
    if st.get("integrator") == "mlt":
        return "Accepted: bidirectional %.0f%%, large %.0f%% | %d chains | b %.4g +- %.2g" % (
            100 * st["bidirectional_acceptance"], 100 * st["large_step_acceptance"], st["chains"], st["b"],
            st["b_standard_error"])
    return "Accepted: small %.0f%%, large %.0f%% | %d chains | b %.4g +- %.2g" % (
        100 * st["small_step_acceptance"], 100 * st["large_step_acceptance"], st["chains"], st["b"],
        st["b_standard_error"])


def _stats_text(settings, p, session=None):
    parts = ["Rendezvous", _integrator_label(settings)]
    if p.samples_target:
        parts.append("Sample %d/%d" % (min(p.samples_done, p.samples_target), p.samples_target))
    else:
        parts.append("Sample %d" % p.samples_done)
    t = p.elapsed_seconds
    parts.append("Time %02d:%05.2f" % (int(t // 60), t % 60))
    if p.time_limit_seconds > 0:
        parts[-1] += "/%ds" % int(p.time_limit_seconds)
    parts.append("%.2f Mrays/s" % (p.rays_per_second / 1e6))
    if p.noise_estimate >= 0:
        noise = "Noise -" if p.noise_estimate == float("inf") else "Noise %.2e" % p.noise_estimate
        if p.noise_target > 0:
            noise += "/%.2e" % p.noise_target
        parts.append(noise)
    if p.samples_dropped:
        parts.append("%d NaN samples dropped" % p.samples_dropped)
    if session is not None and settings.get("integrator") == "auto":
        try:
            choice = session.stats().get("auto") or {}
        except EngineError:
            choice = {}
        pick = choice.get("integrator")
        parts[1] = "Automatic: " + (INTEGRATOR_LABELS.get(pick, pick) if pick else "pilots")
    if session is not None and settings.get("integrator") in ("pssmlt", "mmlt", "mlt", "auto"):
        text = _metropolis_text(session)
        if text:
            parts.append(text)
    return " | ".join(parts)


class _Film:
    """Preallocated float32 arrays for each pass of the RenderResult layer."""

    def __init__(self, session, result, rect, wanted):
        """wanted: enabled_passes() of the view layer rendered."""
        self.session = session
        self.result = result
        self.x, self.y, self.w, self.h = rect
        self.passes = []
        layer = result.layers[0]
        by_name = {name: (engine_pass, channels) for name, engine_pass, channels, _, _ in wanted}
        for rp in layer.passes:
            info = by_name.get(rp.name)
            if info is None:
                continue
            engine_pass, channels = info
            if rp.channels != channels:
                continue
            arr = np.empty((self.w * self.h, channels), dtype=np.float32)
            arr.fill(0.0)  # touch the pages now, not during the first push
            self.passes.append((rp, engine_pass, arr))

    def push(self, combined_only=False):
        t0 = time.perf_counter()
        self._push(combined_only)
        last_render.setdefault("push_seconds", []).append(time.perf_counter() - t0)

    def _push(self, combined_only):
        for rp, engine_pass, arr in self.passes:
            if combined_only and engine_pass != binding.PASS_COMBINED:
                continue
            self.session.read_film(engine_pass, self.x, self.y, self.w, self.h, arr.reshape(-1), top_down=False)
            rp.rect.foreach_set(arr)


def render(engine, depsgraph):
    try:
        _render(engine, depsgraph)
    except LibraryError as exc:
        print(str(exc))
        engine.report({"ERROR"}, str(exc))
    except (EngineError, ExportError, SettingsError) as exc:
        print("Rendezvous: %s" % exc)
        engine.report({"ERROR"}, "Rendezvous: %s" % exc)
    except Exception as exc:  # a bug: say so loudly instead of saving a blank frame
        traceback.print_exc()
        engine.report({"ERROR"}, "Rendezvous: internal error %s: %s (see the console)" % (type(exc).__name__, exc))


def _write_part(session, scene, props):
    """The render as a part for `rendezvous merge` (docs/farm.md)."""
    path = part_output_path(bpy.path.abspath(props.part_output), scene.frame_current)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    session.write_image(path)
    last_render["part_file"] = path
    print("Rendezvous: wrote render part %s (samples %d..%d)" % (path, props.sample_offset,
                                                                props.sample_offset + props.samples - 1))


def _render(engine, depsgraph):
    lib = binding.load()
    scene = depsgraph.scene
    props = scene.rendezvous
    messages = Messages()
    settings = session_settings(scene, props, frame=scene.frame_current, warn=messages.warn)
    settings.update(light_pass_settings(depsgraph.view_layer, scene, settings.get("integrator"), messages.warn))
    if props.part_output:
        settings["scene_hash"] = scene_hash(bpy.data.filepath, scene.name, scene.frame_current)
    last_render.clear()
    last_render.update(messages=messages.lines, settings=settings, cancelled=False)

    engine.update_stats("", "Rendezvous | Exporting scene")
    clear_cache()
    rscene = binding.Scene(lib)
    session = None
    try:
        exporter = SceneExporter(depsgraph, rscene, image_average=image_average, messages=messages,
                                 frame_set=engine.frame_set, cryptomatte=wants_cryptomatte(depsgraph.view_layer))
        stats = exporter.export()
        if engine.test_break():
            return
        engine.update_stats("", "Rendezvous | Building acceleration structures")
        rscene.commit()
        messages.extend(rscene.messages())
        for line in messages.lines:
            engine.report({"WARNING"}, line)
        print("Rendezvous: exported %d meshes (%d triangles), %d instances, %d lights, %d materials in %.3f s"
              % (stats.meshes, stats.triangles, stats.instances, stats.lights, stats.materials, stats.seconds))
        if stats.moving or stats.deforming:
            print("Rendezvous: motion blur: %d moving objects, %d deforming meshes, sampled in %.3f s"
                  % (stats.moving, stats.deforming, stats.motion_seconds))

        session = binding.Session(rscene, settings)
        # The session's own warnings (a setting its integrator does not apply) join the scene's.
        reported = len(messages.lines)
        messages.extend(rscene.messages())
        for line in messages.lines[reported:]:
            engine.report({"WARNING"}, line)
        engine.session = session
        width, height = resolution(scene.render)
        rect = border_rect(scene.render, width, height) or (0, 0, width, height)
        session.start()
        result = engine.begin_result(0, 0, rect[2], rect[3], layer=depsgraph.view_layer.name)
        film = _Film(session, result, rect, enabled_passes(depsgraph.view_layer, scene))
        cancelled = False
        last_push = time.monotonic()
        while True:
            if engine.test_break() or (cancel_hook is not None and cancel_hook()):
                session.cancel()
                cancelled = True
                last_render["cancel_requested"] = time.monotonic()
                break
            p = session.progress()
            if p.finished:
                break
            now = time.monotonic()
            if now - last_push >= PUSH_INTERVAL:
                film.push(combined_only=True)
                engine.update_result(result)
                engine.update_progress(min(max(p.fraction_done, 0.0), 1.0))
                engine.update_stats("", _stats_text(settings, p, session))
                last_push = now
            time.sleep(POLL_INTERVAL)
        session.wait()
        p = session.progress()
        last_render.update(stats=stats.as_dict(), progress=p.as_dict(), cancelled=cancelled,
                           engine_stopped=time.monotonic(), integrator_stats=session.stats())
        if "warning" in last_render["integrator_stats"]:
            engine.report({"WARNING"}, last_render["integrator_stats"]["warning"])
        choice = auto_choice_text(last_render["integrator_stats"])
        if choice:
            engine.report({"INFO"}, choice)
        film.push()
        # Cryptomatte's metadata (layer names, manifests), which the compositor's Cryptomatte
        # node and multilayer EXRs take, stamped on the render's whole result as Cycles does
        # (a tile result's own stamps are not kept).
        crypto = last_render["integrator_stats"].get("cryptomatte", {})
        whole = engine.get_result() if crypto else None
        for key, value in crypto.items():
            whole.stamp_data_add_field(key, value)
        if props.part_output and not cancelled:
            _write_part(session, scene, props)
        engine.update_progress(1.0 if not cancelled else min(max(p.fraction_done, 0.0), 1.0))
        engine.update_stats("", _stats_text(settings, p, session) + (" | Cancelled" if cancelled else ""))
        engine.end_result(result)
    finally:
        engine.session = None
        stop_and_close(session, rscene)
