"""Material / light / world previews (bl_use_preview): Blender calls render() with
is_preview=True on a job thread, at small sizes, and restarts it on every edit.  Render a few
samples of the preview scene, push the image a few times a second, and stop within a few
milliseconds of test_break() (the next edit)."""

import time
import traceback

import numpy as np

from .. import binding
from ..binding import EngineError, LibraryError
from ..export import SceneExporter, ExportError, resolution
from ..utils import Messages
from ..utils.images import image_average
from .final import stop_and_close

SAMPLES = 32
MAX_BOUNCES = 8
PUSH_INTERVAL = 0.2
POLL_INTERVAL = 0.005

last_preview = {}  # for tests: what the last preview did


def render(engine, depsgraph):
    try:
        _render(engine, depsgraph)
    except (LibraryError, EngineError, ExportError) as exc:
        last_preview["error"] = str(exc)
        print("Rendezvous preview: %s" % exc)
    except Exception as exc:
        last_preview["error"] = "%s: %s" % (type(exc).__name__, exc)
        traceback.print_exc()


def _render(engine, depsgraph):
    lib = binding.load()
    scene = depsgraph.scene
    width, height = resolution(scene.render)
    last_preview.clear()
    last_preview.update(size=(width, height), cancelled=False, started=time.perf_counter())
    rscene = binding.Scene(lib)
    session = None
    try:
        SceneExporter(depsgraph, rscene, image_average=image_average, messages=Messages()).export()
        if engine.test_break():
            last_preview["cancelled"] = True
            return
        settings = {"width": width, "height": height, "samples": SAMPLES, "integrator": "path",
                    "max_bounces": MAX_BOUNCES, "seed": 0, "threads": 0}
        session = binding.Session(rscene, settings)
        session.start()
        result = engine.begin_result(0, 0, width, height)
        rp = result.layers[0].passes["Combined"]
        arr = np.zeros((width * height, 4), dtype=np.float32)
        last_push = time.monotonic()
        pushed = 0
        while True:
            if engine.test_break():
                session.cancel()
                last_preview["cancelled"] = True
                break
            p = session.progress()
            if p.finished:
                break
            if p.samples_done > pushed and time.monotonic() - last_push >= PUSH_INTERVAL:
                session.read_film(binding.PASS_COMBINED, 0, 0, width, height, arr.reshape(-1), top_down=False)
                rp.rect.foreach_set(arr)
                engine.update_result(result)
                pushed = p.samples_done
                last_push = time.monotonic()
            time.sleep(POLL_INTERVAL)
        session.wait()
        p = session.progress()
        if p.samples_done > 0:
            session.read_film(binding.PASS_COMBINED, 0, 0, width, height, arr.reshape(-1), top_down=False)
            rp.rect.foreach_set(arr)
        engine.end_result(result)
        last_preview.update(samples=p.samples_done, seconds=time.perf_counter() - last_preview["started"],
                            mean=float(arr[:, :3].mean()), finite=bool(np.isfinite(arr).all()))
    finally:
        stop_and_close(session, rscene)
