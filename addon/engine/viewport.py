"""Interactive viewport rendering: the 3D view's Rendered shading (view_update / view_draw).

One `ViewportRenderer` per viewport (one per RenderEngine instance Blender creates for a
3D view in Rendered mode).  It keeps one engine scene alive and at most one session:

* view_update (depsgraph edits): the session is destroyed (the engine refuses edits while
  one exists), the edits are applied in place - instance transforms
  (rdv_scene_set_instance_transform), one material (rdv_scene_set_material), one light
  (rdv_scene_set_light), the world, one mesh's geometry (rdv_scene_set_mesh), one grid
  medium (a Volume object or a smoke / fire domain: its medium's grids are placed in world
  space, so a move, a material, file, frame or simulation change re-exports that object's
  medium and box, nothing else) - and a new session starts.  Adding, removing, showing or
  hiding objects rebuilds the engine scene.
* Warnings (the final render's, e.g. a missing .vdb naming the object) are printed once to
  the console and shown in the viewport's status text; re-exporting an object drops its old
  ones.
* view_draw: the view (view matrix, window matrix, perspective, region size) is compared with
  the last one; a change only sets the engine camera and restarts (nothing re-exported).
* Every restart renders 1/4 of the resolution first (1 sample), then 1/2, then the full
  resolution up to the viewport samples; view_draw waits up to FIRST_FRAME_WAIT for the
  first pass of a restart so the next frame drawn already shows the change.
* A timer (main thread, every POLL_INTERVAL) copies new film samples, advances the stages and
  tags the 3D views for redraw only when there is something new: no redraws, no CPU once the
  viewport samples are reached (or while paused).  No exception leaves the timer (Blender
  drops a timer whose callback raises, and the viewport would never refine again): a poll's
  exception is reported once per message (console, status text) and the next poll retries;
  an EngineError stops that viewport's session until the next edit or view change.

Threading: Blender calls view_update, view_draw and the timer on the main thread; a
material preview (preview.py) runs on a job thread with its own engine scene and session.
The engine allows calls on different scenes from different threads, and progress /
read_film / cancel from any thread while a session renders; scene edits only when no
session exists.  A lock per renderer serialises its own calls anyway.
"""

import hashlib
import threading
import time
import traceback
import weakref

import numpy as np

from .. import binding, shaders_map
from ..binding import EngineError, LibraryError
from ..export import SceneExporter, ExportError, GEOMETRY_TYPES, gas_domain
from ..export import volumes
from ..export import images as export_images
from ..export.settings import (INTEGRATORS, INTEGRATOR_LABELS, METROPOLIS, light_path_settings, light_paths_for,
                               metropolis_settings)
from ..utils import Messages, blender_version, normalize_frame, is_finite_matrix, determinant3
from ..utils.images import image_average

# (resolution divisor, samples): None = the viewport samples setting.  The first divisor
# grows on big regions so the first pass stays around FIRST_STAGE_PIXELS pixels.
STAGES = ((4, 1), (2, 1), (1, None))
FIRST_STAGE_PIXELS = 16000
MIN_REDUCED_PIXELS = 64 * 64   # below this many full-resolution pixels, skip the reduced stages
FIRST_FRAME_WAIT = 0.25        # s: how long view_draw waits for a restart's first pass
POLL_INTERVAL = 0.025          # s: timer polling the sessions

# For tests and benchmarks: counters and timestamps of what the viewports did.
stats = {"full_exports": 0, "mesh_exports": 0, "material_updates": 0, "light_updates": 0, "world_updates": 0,
         "transform_updates": 0, "volume_updates": 0, "volume_update_seconds": 0.0, "export_seconds": 0.0,
         "image_updates": 0, "warnings": [], "status": "", "camera_restarts": 0, "restarts": 0, "draws": 0, "uploads": 0,
         "last_restart": 0.0, "last_restart_reason": "", "first_new_frame_drawn": 0.0,
         "first_frame_after_restart": 0.0, "errors": []}

_renderers = weakref.WeakSet()
_timer_running = False
_redraw_failed = False  # tagging redraws raised once (printed then, not again)


def _key(inst, ob):
    if inst.is_instance:
        parent = inst.parent
        return (parent.name_full if parent is not None else "", tuple(inst.persistent_id), ob.name_full)
    return ("", (), ob.name_full)


def _digest(text):
    return hashlib.blake2b(text, digest_size=16).digest()


def _m16(matrix):
    return [*matrix[0], *matrix[1], *matrix[2], *matrix[3]]


class _Record:
    """What one depsgraph instance became: kind "mesh" (an instance of mesh_id), "light"
    (params) or "medium" (a grid medium: material_id over its grids in the box mesh_id, made
    from the object's materials)."""
    __slots__ = ("kind", "engine_id", "m16", "ob_name", "mesh_id", "params", "material_id", "box", "materials", "settings",
                 "copies", "kinds")

    def __init__(self, kind, engine_id, m16, ob_name, mesh_id=None, params=None):
        self.kind, self.engine_id, self.m16, self.ob_name = kind, engine_id, m16, ob_name
        self.mesh_id, self.params = mesh_id, params
        self.material_id = self.box = self.materials = None
        self.settings = {}  # meshes: rdv_scene_set_instance_params (holdout, ray visibility)
        # A mesh whose materials look different to different kinds of ray: its other copies
        # (export/materials.py), each a record of its own, and the kinds each copy is seen by.
        self.copies = []
        self.kinds = None


class _Sink:
    """Forwards the exporter's calls to the engine scene and records ids per depsgraph instance."""

    def __init__(self, rscene, exporter):
        self.rscene = rscene
        self.exp = exporter

    def add_material(self, name, params):
        text = binding.params_json(params)
        mid = self.rscene.add_material(name, text)
        self.exp.material_digests[mid] = self.exp.material_digest(text, params)
        return mid

    def add_grid(self, name, values, resolution):
        self.rscene.add_grid(name, values, resolution)
        self.exp.grid_digests[name] = volumes.buffer_digest(values)

    def add_image(self, name, pixels, width, height, channels, colorspace):
        self.rscene.add_image(name, pixels, width, height, channels, colorspace)

    def add_mesh(self, name, positions, indices, **kw):
        if self.exp.replace_mesh is not None:
            return self.rscene.set_mesh(self.exp.replace_mesh, positions, indices, **kw)
        return self.rscene.add_mesh(name, positions, indices, **kw)

    def add_instance(self, mesh_id, m16):
        iid = self.rscene.add_instance(mesh_id, m16)
        e = self.exp
        rec = _Record("mesh", iid, list(m16), e.current_name, mesh_id=mesh_id)
        rec.kinds = e.copy_kinds
        if e.current_first is None:
            e.records[e.current_key] = e.current_first = rec
        else:  # another copy of the same object (another look of its materials)
            e.current_first.copies.append(rec)
        e.current_record = rec
        return iid

    def set_instance_params(self, instance, params):
        self.rscene.set_instance_params(instance, params)
        self.exp.current_record.settings = params

    def add_light(self, name, params):
        lid = self.rscene.add_light(name, params)
        e = self.exp
        e.records[e.current_key] = _Record("light", lid, None, e.current_name, params=params)
        return lid

    def set_world(self, params):
        self.rscene.set_world(params)

    def set_camera(self, params):
        self.rscene.set_camera(params)


class ViewportExporter(SceneExporter):
    """The final render's exporter, remembering which engine ids each depsgraph instance got."""

    def __init__(self, depsgraph, rscene, messages):
        self.records = {}      # instance key -> _Record
        self.visited = set()   # keys of every geometry/light instance seen (exported or skipped)
        self.current_key = None
        self.current_name = None
        self.current_first = self.current_record = None  # the object's first record, the last one made
        self.replace_mesh = None
        self.material_digests = {}  # engine material id -> digest of the params it was given
        self.grid_digests = {}  # grid buffer name -> digest of the voxels it was given
        self.image_digests = {}  # image buffer name -> digest of the pixels it was given
        self.edits = 0         # in-place edits applied (a selection change applies none)
        super().__init__(depsgraph, _Sink(rscene, self), image_average=image_average, messages=messages,
                         is_viewport=True)

    def export_camera(self):
        pass  # the viewport's own camera comes from the region (ViewportRenderer.view_camera)

    def export_objects(self):
        for inst, ob in self._instances(self.depsgraph):
            self.current_key = _key(inst, ob)
            self.current_name = ob.name_full
            self.current_first = None
            self.visited.add(self.current_key)
            if ob.type == "LIGHT":
                self._light(ob, inst.matrix_world)
            elif ob.type == "VOLUME":
                self._volume(ob, inst.matrix_world)
            else:
                self._geometry(ob, inst.matrix_world)
        self.current_key = None

    def _grid_medium(self, ob, m16, source):
        ids = super()._grid_medium(ob, m16, source)
        if ids is not None:
            rec = self.records[self.current_key]
            rec.kind, rec.material_id, rec.box = "medium", ids[0], (source[1], source[2])
            rec.materials = self._material_names(ob)
        return ids

    def _material_names(self, ob):
        return [m.name_full if m is not None else None for m in self._object_materials(ob)]

    @staticmethod
    def _instances(depsgraph):
        for inst in depsgraph.object_instances:
            is_instance = inst.is_instance
            ob = inst.instance_object if is_instance else inst.object
            if ob is None or (not is_instance and not inst.show_self):
                continue
            if ob.type == "LIGHT" or ob.type == "VOLUME" or ob.type in GEOMETRY_TYPES:
                yield inst, ob

    # ---- in-place updates -----------------------------------------------------------------
    def sync_instances(self, depsgraph):
        """Applies changed transforms and light parameters; False if objects were added or
        removed (the caller rebuilds the scene)."""
        self.depsgraph = depsgraph
        seen = 0
        rscene = self.sink.rscene
        for inst, ob in self._instances(depsgraph):
            key = _key(inst, ob)
            if key not in self.visited:
                return False
            seen += 1
            rec = self.records.get(key)
            if rec is None:
                continue  # skipped at export (e.g. no faces) and still there
            m16 = _m16(inst.matrix_world)
            if rec.kind == "medium":
                # Its grids sit in world space: a move re-exports the medium, as does
                # another material in its slot (no depsgraph update names that material).
                if (m16 != rec.m16 or self._material_names(ob) != rec.materials) and not self.update_grid(rec, ob, m16):
                    return False
            elif rec.kind == "mesh":
                if m16 != rec.m16:
                    if not is_finite_matrix(m16) or abs(determinant3(m16)) < 1e-24:
                        return False
                    for r in [rec] + rec.copies:
                        rscene.set_instance_transform(r.engine_id, m16)
                        r.m16 = m16
                    self.edits += 1
                    stats["transform_updates"] += 1
                settings = self.object_settings(ob, inst, rec.kinds, self.object_attribute_names(self._object_materials(ob)))
                if settings != rec.settings:  # holdout, ray visibility or an object attribute changed
                    if rec.kinds is not None:
                        return False  # copies per look of its materials: which of them any ray sees may change
                    rscene.set_instance_params(rec.engine_id, settings)
                    rec.settings = settings
                    self.edits += 1
            else:
                if not is_finite_matrix(m16):
                    return False
                params = self.light_settings(ob, m16)
                if params is None:
                    return False
                if params != rec.params:
                    rscene.set_light(rec.engine_id, params)
                    rec.params = params
                    self.edits += 1
                    stats["light_updates"] += 1
        return seen == len(self.visited)

    def update_geometry(self, ob):
        """Re-exports the meshes object `ob` (evaluated) uses, in place. False: rebuild."""
        if ob.type == "VOLUME" or gas_domain(ob) is not None:
            # A grid medium (a new file or frame, a simulation step): re-export its medium.
            recs = [rec for rec in self.records.values() if rec.kind == "medium" and rec.ob_name == ob.name_full]
            return bool(recs) and all(self.update_grid(rec, ob, rec.m16) for rec in recs)
        recs = [rec for rec in self.records.values() if rec.kind == "mesh" and rec.ob_name == ob.name_full]
        if any(rec.copies for rec in recs):
            return False  # copies per look of its materials: re-export the scene
        mesh_ids = {rec.mesh_id for rec in recs}
        for mesh_id in mesh_ids:
            self.replace_mesh = mesh_id
            try:
                if self._add_mesh(ob, self._object_materials(ob)) is None:
                    return False
            finally:
                self.replace_mesh = None
            stats["mesh_exports"] += 1
            self.edits += 1
        return True

    def material_digest(self, text, params):
        """Digest of a material's params text and of the grid and image buffers it names."""
        volume = params.get("volume") if isinstance(params, dict) else None
        names = [g["buffer"] for g in (volume or {}).values() if isinstance(g, dict) and "buffer" in g]
        images = _image_buffer_names(params)
        return _digest(text + b"".join(self.grid_digests.get(n, b"") for n in names) +
                       b"".join(self.image_digests.get(n, b"") for n in images))

    def send_image(self, name, pixels, width, height, channels, colorspace):
        """An image's pixels reach the engine only when they changed (a paint stroke, a
        script); the material digest covers them, so its material is set again then."""
        digest = export_images.pixels_digest(pixels)
        if digest != self.image_digests.get(name):
            self.sink.add_image(name, pixels, width, height, channels, colorspace)
            self.image_digests[name] = digest
        return digest

    def update_images(self, changed):
        """Materials showing an image of `changed` (names) are translated again: those whose
        pixels (or anything else) changed are set in place. False: rebuild."""
        for name in changed:
            self._image_buffers.pop(name, None)  # read their pixels again
        for material in self.depsgraph.ids:
            if type(material).__name__ == "Material" and material.name_full in self.materials._ids and \
                    _uses_images(getattr(material, "node_tree", None), changed):
                if not self.update_material(material):
                    return False
        return True

    def update_grid(self, rec, ob, m16):
        """Re-exports one grid medium (a Volume object or a gas domain instance) in place:
        its material over the grids, its box and its transform; only what differs reaches
        the engine (a final render re-evaluates a domain: its unchanged grids come back
        here and must not restart the viewport). False: rebuild (it has nothing to render
        now, or a bad transform)."""
        t0 = time.perf_counter()
        if not is_finite_matrix(m16) or abs(determinant3(m16)) < 1e-24:
            return False
        self.messages.drop(("Volume '%s'" % ob.name, "Fluid domain '%s'" % ob.name))
        source = self.grid_source(ob, m16)
        params = self.grid_material(ob, source[0], source[3]) if source is not None else None
        if params is None:
            return False
        rscene = self.sink.rscene
        rec.materials = self._material_names(ob)
        edits = self.edits
        # A simulation step changes a domain's voxels, not its params' text: only changed
        # buffers are sent, and the digest covers them (a medium copies its buffers when
        # its material is parsed, so the material is set again).
        params = self.with_grid_buffers(
            ob, params, lambda name, values: volumes.buffer_digest(values) != self.grid_digests.get(name))
        text = binding.params_json(params)
        digest = self.material_digest(text, params)
        if digest != self.material_digests.get(rec.material_id):
            rscene.set_material(rec.material_id, text)
            self.material_digests[rec.material_id] = digest
            self.edits += 1
        box = (source[1], source[2])
        if box != rec.box:
            positions, indices = volumes.box_arrays(*box)
            rscene.set_mesh(rec.mesh_id, positions, indices, default_material=rec.material_id)
            rec.box = box
            self.edits += 1
        if m16 != rec.m16:
            rscene.set_instance_transform(rec.engine_id, m16)
            rec.m16 = m16
            self.edits += 1
        if self.edits == edits:
            return True
        stats["volume_updates"] += 1
        stats["volume_update_seconds"] = time.perf_counter() - t0
        return True

    def update_material(self, material):
        """Re-translates one material in place, the grid media made from it included.
        False: rebuild (a grid medium has nothing to render now)."""
        name = material.name_full
        recs = [rec for rec in self.records.values() if rec.kind == "medium" and name in rec.materials]
        if recs:
            evaluated = {ob.name_full: ob for ob in self.depsgraph.objects if ob.type == "VOLUME" or ob.type == "MESH"}
            for rec in recs:
                ob = evaluated.get(rec.ob_name)
                if ob is None or not self.update_grid(rec, ob, rec.m16):
                    return False
        mid = self.materials._ids.get(name)
        if mid is None:
            return True  # no mesh uses it
        self._uv_cache.pop(material.name_full, None)
        # Object / Instancer attributes it reads changed: every object's values must be sent again.
        known = self._object_attribute_cache.pop(material.name_full, None)
        if known is not None and known != self.object_attribute_names([material]):
            return False
        try:
            variants, warning = shaders_map.convert_material_variants(material, image_average=self.image_average,
                                                                      view_layer_attribute=self.view_layer_attribute,
                                                                      image_file=self.image_file,
                                                                      blender_version=blender_version())
        except Exception as exc:  # a node handler bug must not break the viewport
            variants, warning = [(None, dict(shaders_map.DEFAULT_SURFACE))], \
                "Material '%s': translation failed (%s: %s)" % (material.name_full, type(exc).__name__, exc)
        if len(variants) > 1 or len(self.materials._looks.get(name, ())) > 1:
            return False  # a look per kind of ray, before or now: the objects' copies change
        params = variants[0][1]
        if warning:
            self.warn(warning)
        text = binding.params_json(params)
        digest = self.material_digest(text, params)
        if digest == self.material_digests.get(mid):
            return True  # nothing the engine sees changed: no restart
        self.sink.rscene.set_material(mid, text)
        self.material_digests[mid] = digest
        self.edits += 1
        stats["material_updates"] += 1
        return True


def _image_buffer_names(params, depth=0):
    """Names of the image buffers ({"node": "image", "buffer": name}) a material uses."""
    names = []
    if depth > 100:
        return names
    if isinstance(params, dict):
        if params.get("node") == "image" and "buffer" in params:
            names.append(params["buffer"])
        for v in params.values():
            if isinstance(v, (dict, list)):
                names += _image_buffer_names(v, depth + 1)
    elif isinstance(params, list):
        for v in params:
            if isinstance(v, (dict, list)):
                names += _image_buffer_names(v, depth + 1)
    return names


def _uses_images(tree, names, depth=0):
    """True if a node tree (or a group inside it) has an image node showing one of `names`."""
    if tree is None or depth > 20:
        return False
    for node in tree.nodes:
        image = getattr(node, "image", None)
        if image is not None and image.name_full in names:
            return True
        if node.type == "GROUP" and _uses_images(getattr(node, "node_tree", None), names, depth + 1):
            return True
    return False


def view_camera(region, rv3d, width, height):
    """Engine camera parameters for the 3D view's current view (any perspective, camera view
    zoom/offset included: everything comes from the view and window matrices)."""
    view_inv = rv3d.view_matrix.inverted()
    P = rv3d.window_matrix
    frame, _ = normalize_frame(_m16(view_inv))
    p = {"sensor_fit": "HORIZONTAL", "sensor_width": 36.0, "sensor_height": 24.0}
    if rv3d.is_perspective:
        n = P[2][3] / (P[2][2] - 1.0)
        f = P[2][3] / (P[2][2] + 1.0)
        p.update(type="perspective", focal_length=18.0 * P[0][0], shift_x=P[0][2] / 2.0,
                 shift_y=P[1][2] * P[0][0] / (2.0 * P[1][1]), clip_start=max(n, 1e-5), clip_end=max(f, n * 2.0),
                 transform=frame)
    else:
        n = (P[2][3] + 1.0) / P[2][2]
        f = (P[2][3] - 1.0) / P[2][2]
        # The view's near plane may lie behind the view point: start the rays there.
        back = -n
        m = list(frame)
        for r in range(3):
            m[4 * r + 3] += m[4 * r + 2] * back
        p.update(type="orthographic", ortho_scale=2.0 / P[0][0], shift_x=-P[0][3] / 2.0,
                 shift_y=-P[1][3] * P[0][0] / (2.0 * P[1][1]), clip_start=0.0, clip_end=max(f - n, 1e-3),
                 transform=m)
    return p


def _view_key(region, rv3d):
    return (tuple(tuple(r) for r in rv3d.view_matrix), tuple(tuple(r) for r in rv3d.window_matrix),
            rv3d.view_perspective, region.width, region.height)


_settings_warnings = set()


def _warn_once(text):
    """A warning about the viewport's settings, on the console the first time it comes up
    (viewport_settings runs on every update)."""
    if text not in _settings_warnings:
        _settings_warnings.add(text)
        print("Rendezvous viewport: WARNING: %s" % text)


def viewport_settings(scene):
    props = scene.rendezvous
    integrator = INTEGRATORS.get(props.viewport_integrator, "path")
    s = {"integrator": integrator, "samples": max(1, int(props.viewport_samples)),
         "light_paths": light_paths_for(integrator, light_path_settings(scene), warn=_warn_once),
         "clamp": float(props.clamp), "threads": int(props.threads), "seed": int(props.seed) & 0x7FFFFFFF,
         "pause": bool(props.viewport_pause)}
    if s["integrator"] in METROPOLIS:
        s.update(metropolis_settings(props))
    return s


class ViewportRenderer:
    def __init__(self):
        self.lock = threading.RLock()
        self.lib = binding.load()
        self.rscene = None
        self.exporter = None
        self.messages = Messages()
        self.session = None
        self.stage = 0
        self.size = (0, 0)           # region size
        self.session_size = (0, 0)   # film size of the running session
        self.camera = None
        self.view_key = None
        self.settings = None
        self.frame = None            # (float32 array (h*w*4), w, h), bottom-up rows
        self.read_samples = 0
        self.frame_dirty = False
        self.first_drawn = True
        self.frame_new_since_restart = False
        self.texture = None
        self.restarted_at = 0.0
        self.converged = False
        self.error = None            # shown in the status text until the next restart
        self._errors_reported = set()
        self.progress_text = ""
        self.warnings = []           # the current export's warnings (exporter's and engine's)
        self._printed = set()
        _renderers.add(self)
        _ensure_timer()

    # ---- scene --------------------------------------------------------------------------------
    def export(self, depsgraph):
        t0 = time.perf_counter()
        self._stop()
        if self.rscene is not None:
            self.rscene.close()
        self.messages = Messages()
        self.rscene = binding.Scene(self.lib)
        self.exporter = ViewportExporter(depsgraph, self.rscene, self.messages)
        self._printed = set()
        self.exporter.export()
        stats["full_exports"] += 1
        stats["export_seconds"] = time.perf_counter() - t0

    def update(self, depsgraph):
        """Applies depsgraph.updates in place. Returns True if something changed."""
        if self.rscene is None:
            self.export(depsgraph)
            return True
        geometry, materials, world, instances, images = [], [], False, False, set()
        for u in depsgraph.updates:
            idt = type(u.id).__name__
            if idt == "Image":
                images.add(u.id.name_full)
            if idt == "Object":
                instances = True
                if u.is_updated_geometry and (u.id.type in GEOMETRY_TYPES or u.id.type == "VOLUME"):
                    geometry.append(u.id)
            elif idt == "Material":
                materials.append(u.id)
            elif idt == "World":
                world = True
            elif idt in ("Collection", "Scene", "Light", "Mesh"):
                instances = True
        if not (geometry or materials or world or instances or images):
            return False
        self._stop()  # the engine refuses edits while a session exists
        exp = self.exporter
        edits = exp.edits
        exp.depsgraph = depsgraph
        exp.scene = depsgraph.scene
        try:
            if instances and not exp.sync_instances(depsgraph):
                self.export(depsgraph)
                return True
            for ob in geometry:
                if not exp.update_geometry(ob.evaluated_get(depsgraph)):
                    self.export(depsgraph)
                    return True
            for m in materials:
                if not exp.update_material(m):
                    self.export(depsgraph)
                    return True
            stats["image_updates"] += len(images)
            if images and not exp.update_images(images):
                self.export(depsgraph)
                return True
            if world:
                exp.export_world()
                stats["world_updates"] += 1
                exp.edits += 1
        except EngineError as exc:  # e.g. a parameter the in-place call refuses: start over
            print("Rendezvous viewport: %s; re-exporting the scene" % exc)
            self.export(depsgraph)
            return True
        return exp.edits != edits

    # ---- sessions -----------------------------------------------------------------------------
    def _stop(self):
        s, self.session = self.session, None
        if s is not None:
            try:
                s.cancel()
            except EngineError:
                pass
            s.close()

    def restart(self, reason):
        """(Re)starts rendering from the first stage with the current camera and settings."""
        with self.lock:
            self._stop()
            self.converged = False
            stats["restarts"] += 1
            stats["last_restart"] = self.restarted_at = time.perf_counter()
            stats["last_restart_reason"] = reason
            self.frame_new_since_restart = False
            self.first_drawn = False
            self.error = None
            if self.rscene is None or self.camera is None or self.settings is None:
                return
            if self.settings["pause"]:
                return
            self.rscene.set_camera(self.camera)
            self.rscene.commit()  # here, not in the session: its warnings are read now
            self._gather_warnings()
            w, h = self.size
            self.stage = 0 if w * h >= MIN_REDUCED_PIXELS else len(STAGES) - 1
            self._start_stage()

    def _gather_warnings(self):
        """The exporter's current warnings and the engine's; new ones go to the console."""
        lines = list(self.messages.lines)
        lines += [line for line in self.rscene.messages() if line not in lines]
        for line in lines:
            if line not in self._printed:
                self._printed.add(line)
                print("Rendezvous viewport: WARNING: %s" % line)
        self.warnings = lines
        stats["warnings"] = list(lines)

    def _start_stage(self):
        div, samples = STAGES[self.stage]
        w, h = self.size
        if self.stage == 0:
            div = max(div, int((w * h / FIRST_STAGE_PIXELS) ** 0.5 + 0.999))
        sw, sh = max(1, (w + div - 1) // div), max(1, (h + div - 1) // div)
        st = self.settings
        settings = {"width": sw, "height": sh, "samples": samples or st["samples"], "integrator": st["integrator"],
                    "seed": st["seed"], "threads": st["threads"], "clamp": st["clamp"]}
        settings.update(st["light_paths"])
        settings.update({k: v for k, v in st.items() if k.startswith("mlt_")})
        self.session = binding.Session(self.rscene, settings)
        self.session_size = (sw, sh)
        self.session_samples = settings["samples"]
        self.read_samples = 0
        self.session.start()

    def poll(self):
        """Copies new samples, advances stages. Returns True when a redraw is wanted."""
        with self.lock:
            s = self.session
            if s is None:
                return self.frame_dirty
            p = s.progress()
            done = p.samples_done
            if done > self.read_samples:
                w, h = self.session_size
                arr = np.empty(w * h * 4, dtype=np.float32)
                s.read_film(binding.PASS_COMBINED, 0, 0, w, h, arr, top_down=False)
                self.frame = (arr, w, h)
                self.read_samples = done
                self.frame_dirty = True
                if not self.frame_new_since_restart:
                    self.frame_new_since_restart = True
                    stats["first_frame_after_restart"] = time.perf_counter() - self.restarted_at
            self.progress_text = self._stats_text(p)
            if p.finished:
                if p.cancelled:
                    self._stop()
                elif self.stage + 1 < len(STAGES):
                    self._stop()
                    self.stage += 1
                    self._start_stage()
                else:
                    self._stop()  # converged: the film is copied, the threads are gone
                    self.converged = True
            return self.frame_dirty

    def poll_safely(self):
        """poll() for the timer and view_draw: an exception is reported once and rendering
        goes on (the next poll retries); an EngineError stops the session. True: redraw."""
        try:
            return self.poll()
        except EngineError as exc:  # the session failed: an edit or a view change restarts it
            self._report(str(exc), None)
            self._stop()
        except Exception as exc:
            self._report("internal error %s: %s (see the console)" % (type(exc).__name__, exc),
                         traceback.format_exc())
        return True  # show the message

    def _report(self, message, details):
        self.error = message
        if message in self._errors_reported:
            return
        self._errors_reported.add(message)
        print("Rendezvous viewport: ERROR: %s" % message)
        if details:
            print(details, end="")
        stats["errors"].append(message)

    def _stats_text(self, p):
        label = INTEGRATOR_LABELS.get(self.settings["integrator"], "?")
        if STAGES[self.stage][0] > 1:
            w = self.session_size[0]
            return "Rendezvous | %s | Preview 1/%d resolution" % (label, max(1, round(self.size[0] / max(w, 1))))
        return "Rendezvous | %s | Sample %d/%d" % (label, min(p.samples_done, self.session_samples),
                                                  self.session_samples)

    def wait_first_frame(self, timeout):
        end = time.perf_counter() + timeout
        while True:
            self.poll_safely()
            if self.frame_new_since_restart or self.session is None or time.perf_counter() > end:
                return
            time.sleep(0.001)

    def free(self):
        with self.lock:
            self._stop()
            if self.rscene is not None:
                self.rscene.close()
                self.rscene = None
            self.texture = None
            self.frame = None
        _renderers.discard(self)


# ---- the timer that polls all viewports ------------------------------------------------------
def _timer():
    global _timer_running, _redraw_failed
    live = list(_renderers)
    if not live:
        _timer_running = False
        return None
    want = False
    for r in live:
        want = r.poll_safely() or want
    if want:
        try:
            _tag_redraw()
        except Exception:  # never let Blender drop the timer
            if not _redraw_failed:
                traceback.print_exc()
            _redraw_failed = True
    return POLL_INTERVAL


def _ensure_timer():
    global _timer_running
    if _timer_running:
        return
    import bpy
    _timer_running = True
    bpy.app.timers.register(_timer, first_interval=POLL_INTERVAL, persistent=True)


def _tag_redraw():
    import bpy
    wm = bpy.context.window_manager
    if wm is None:
        return
    for window in wm.windows:
        for area in window.screen.areas:
            if area.type != "VIEW_3D":
                continue
            for space in area.spaces:
                if space.type == "VIEW_3D" and space.shading.type in ("RENDERED", "MATERIAL"):
                    area.tag_redraw()
                    break


def stop_all():
    """Unregistering the add-on: stop every viewport's threads."""
    for r in list(_renderers):
        r.free()


# ---- RenderEngine hooks ------------------------------------------------------------------------
def _report_error(engine, exc):
    msg = str(exc) if isinstance(exc, (LibraryError, EngineError, ExportError)) else \
        "internal error %s: %s (see the console)" % (type(exc).__name__, exc)
    if not isinstance(exc, (LibraryError, EngineError, ExportError)):
        traceback.print_exc()
    stats["errors"].append(msg)
    engine.update_stats("", "Rendezvous | Error: %s" % msg)


def view_update(engine, context, depsgraph):
    try:
        r = engine.viewport
        if r is None:
            r = engine.viewport = ViewportRenderer()
        with r.lock:
            changed = r.update(depsgraph)
            settings = viewport_settings(depsgraph.scene)
            if settings != r.settings:
                r.settings = settings
                changed = True
            # No real edit (e.g. a selection change) on an unfinished render: resume it too.
            if (changed or (r.session is None and not r.converged)) and r.camera is not None:
                r.restart("edit")
                r.wait_first_frame(FIRST_FRAME_WAIT)
    except Exception as exc:
        _report_error(engine, exc)


def view_draw(engine, context, depsgraph):
    import gpu
    from gpu_extras.presets import draw_texture_2d
    r = engine.viewport
    if r is None:
        return
    region = context.region
    rv3d = context.region_data
    scene = depsgraph.scene
    try:
        with r.lock:
            stats["draws"] += 1
            key = _view_key(region, rv3d)
            settings = viewport_settings(scene)
            restart = None
            if key != r.view_key:
                r.view_key = key
                r.size = (region.width, region.height)
                r.camera = view_camera(region, rv3d, region.width, region.height)
                restart = "camera"
                stats["camera_restarts"] += 1
            if settings != r.settings:
                r.settings = settings
                restart = restart or "settings"
            if restart:
                r.restart(restart)
                r.wait_first_frame(FIRST_FRAME_WAIT)
            r.poll_safely()
            if r.frame_dirty and r.frame is not None:
                arr, w, h = r.frame
                buf = gpu.types.Buffer("FLOAT", w * h * 4, arr)
                r.texture = gpu.types.GPUTexture((w, h), format="RGBA32F", data=buf)
                r.frame_dirty = False
                stats["uploads"] += 1
                if r.frame_new_since_restart and not r.first_drawn:
                    r.first_drawn = True
                    stats["first_new_frame_drawn"] = time.perf_counter()
            if r.texture is not None:
                gpu.state.blend_set("ALPHA_PREMULT")
                engine.bind_display_space_shader(scene)
                draw_texture_2d(r.texture, (0, 0), region.width, region.height)
                engine.unbind_display_space_shader()
                gpu.state.blend_set("NONE")
            text = r.progress_text
            if r.settings and r.settings["pause"]:
                text += " | Paused"
            if r.error:
                text += " | Error: %s" % r.error
            if r.warnings:
                text += " | Warning: %s%s" % (r.warnings[0], " (+%d more in the console)" % (len(r.warnings) - 1)
                                              if len(r.warnings) > 1 else "")
            engine.update_stats("", text)
            stats["status"] = text
    except Exception as exc:
        _report_error(engine, exc)
