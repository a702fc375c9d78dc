"""Motion blur as Cycles 3.4 reads it: the shutter (Render Properties > Motion Blur: Shutter,
Cycles' Position), each object's Object Properties > Motion Blur (use_motion_blur, Steps) and
the transforms of the objects and the camera at evenly spaced times over the open shutter.

Cost. A static scene pays nothing: with motion blur off nothing is sampled, and with it on
the depsgraph is evaluated at the step times only when something in the file is animated
(an action with users, a driver, a rigid body world); only objects whose transform differs
between steps are sent as moving. Measured in Blender 3.4 headless (2 cores): a frame change
of a scene with 200 static spheres and one animated cube, `frame_set` with a subframe, costs
0.17 ms (the depsgraph re-evaluates only what is time-dependent) and one sweep over its
object_instances 0.15 ms; an animated scene with motion blur on costs one such evaluation and
sweep per step time other than the frame's (2 for Cycles' default Steps 1, Position Center),
whatever its meshes (they are not exported again). The `square` Blender test: 0.000 s.

Deformation blur (Object > Motion Blur > Deformation, Cycles' `use_deform_motion`): an object
whose mesh may change over time (shape keys, modifiers such as an armature, animated mesh
data: may_deform) has its evaluated mesh sampled at the same step times, in the layout it
was exported in at the frame (mesh.mesh_arrays with the same UV and attribute needs), and
sent as vertex steps only when some vertex moves. A vertex count that changes over the
shutter leaves it without deformation blur, with a warning naming it (Cycles: "Topology
differs, disabling motion blur"). Instanced copies (collection instances, particles) share their
mesh and so its deformation, which the copy that exported the mesh samples (it is followed
by its persistent id); emitting meshes deform (and move) with their light, as in Cycles. Cost in
bench_motion_blur's `deforming` case (12 sheared balls of 482 vertices, 2 step times besides the
frame's): 0.004 s of sampling.
Not yet: rolling shutter and shutter curves.
"""

import math

# Cycles' Object::MAX_MOTION_STEPS.
MAX_STEPS = 129


def shutter_interval(scene):
    """(open, close) in frames relative to the current frame, or None when motion blur is off.
    Cycles 3.4: the shutter lasts `motion_blur_shutter` frames, centred on the frame (Center,
    the default), starting at it (Start) or ending at it (End)."""
    r = scene.render
    if not getattr(r, "use_motion_blur", False):
        return None
    shutter = float(r.motion_blur_shutter)
    if not (shutter > 0.0) or not math.isfinite(shutter):
        return None
    position = getattr(getattr(scene, "cycles", None), "motion_blur_position", "CENTER")
    opening = {"START": 0.0, "END": -shutter}.get(position, -0.5 * shutter)
    return opening, opening + shutter


def object_steps(ob):
    """How many transforms Cycles samples for an object over the shutter (0: its motion blur
    is off): 2^Steps + 1, so objects with more or fewer steps share their sample times."""
    c = getattr(ob, "cycles", None)
    if c is None:  # the Cycles add-on is off: Cycles' defaults (on, Steps 1)
        return 3
    if not c.use_motion_blur:
        return 0
    return min((2 << (max(1, int(c.motion_steps)) - 1)) + 1, MAX_STEPS)


def may_deform(ob):
    """The object's mesh may change over the shutter and Cycles would blur it: Deformation is
    on (Cycles' default) and it has shape keys, modifiers or animated mesh data."""
    c = getattr(ob, "cycles", None)
    if c is not None and not getattr(c, "use_deform_motion", True):
        return False
    if ob.type != "MESH":
        return False
    original = getattr(ob, "original", ob)
    if len(getattr(original, "modifiers", ())):
        return True
    data = getattr(original, "data", None)
    if data is None:
        return False
    keys = getattr(data, "shape_keys", None)
    return keys is not None or getattr(data, "animation_data", None) is not None


def scene_is_animated(data):
    """Something in the file can move over time: an action in use, a driver, a rigid body
    world. Without, no transform changes within the shutter and nothing is sampled."""
    if any(a.users for a in data.actions):
        return True
    for collection in (data.objects, data.cameras, data.scenes):
        for idb in collection:
            ad = getattr(idb, "animation_data", None)
            if ad is not None and (ad.action is not None or len(ad.drivers)):
                return True
    return any(getattr(s, "rigidbody_world", None) is not None for s in data.scenes)


def instance_key(inst, ob):
    """Names an object instance across depsgraph evaluations (the entries are temporary)."""
    if inst.is_instance:
        parent = inst.parent.original.name if inst.parent is not None else ""
        return (ob.original.name, parent, tuple(inst.persistent_id))
    return (ob.original.name, "", ())


def _rows(m):
    return [float(x) for row in m for x in row]


class MotionSampler:
    """Collects what may move while exporting the frame, then samples its transforms at the
    step times with `frame_set(frame, subframe)` (RenderEngine.frame_set in a final render)."""

    def __init__(self, interval):
        self.interval = interval
        self._tracked = {}  # key -> (steps, [engine instance ids], m16 at the frame)
        self.camera_key = None
        self.seconds = 0.0
        self.evaluations = 0
        # Deformation blur: key -> (steps, [mesh ids], name, frame arrays, need_uvs, attribute names)
        # (several meshes: the object's copies per look, export/__init__.py).
        self._deforming = {}
        self.deformed = []  # (mesh id, [positions per step], [normals per step] or None), by sample()
        self.warnings = []  # for the user, by sample()

    def track(self, key, steps, instance, m16):
        if steps < 2:
            return
        entry = self._tracked.setdefault(key, (steps, [], m16))
        entry[1].append(instance)

    def track_deform(self, key, steps, mesh, name, arrays, need_uvs, attributes):
        """An object whose evaluated mesh (exported as `mesh` in `arrays`' layout, and as any
        mesh tracked under the same key since) may deform."""
        if steps >= 2:
            meshes = self._deforming[key][1] if key in self._deforming else []
            self._deforming[key] = (steps, meshes + [mesh], name, arrays, need_uvs, attributes)

    def _sample_deform(self, ob, key, u, shapes):
        """The evaluated mesh of a tracked object at step time u, in its frame layout."""
        from .mesh import mesh_arrays
        _, _, name, _, need_uvs, attributes = self._deforming[key]
        if ob.mode == "EDIT":
            return
        arrays = mesh_arrays(ob.data, need_uvs=need_uvs, attributes=attributes)
        shapes.setdefault(key, {})[u] = arrays

    def _deformations(self, shapes):
        import numpy as np
        for key, (steps, meshes, name, frame, _, _) in self._deforming.items():
            by_u = shapes.get(key, {})
            positions, normals = [], []
            changes = False
            for i in range(steps):
                arrays = by_u.get(i / (steps - 1), frame)
                if arrays is None or arrays.num_vertices != frame.num_vertices or \
                        arrays.num_triangles != frame.num_triangles:
                    self.warnings.append("Object '%s': its mesh changes its vertices or faces while the shutter is "
                                         "open; rendered without deformation blur" % name)
                    break
                if (arrays.normals is None) != (frame.normals is None) or not np.isfinite(arrays.positions).all():
                    self.warnings.append("Object '%s': its mesh changes its shading or gets non-finite vertices "
                                         "while the shutter is open; rendered without deformation blur" % name)
                    break
                changes = changes or not np.array_equal(arrays.positions, frame.positions)
                positions.append(arrays.positions)
                normals.append(arrays.normals)
            else:
                if changes:
                    for mesh in meshes:
                        self.deformed.append((mesh, positions, None if frame.normals is None else normals))

    def track_camera(self, key, steps, m16):
        self.camera_key = key
        self._tracked[key] = (steps, [], m16)

    def _times(self):
        """Frame offsets to evaluate -> the step fractions u in [0, 1] they stand for."""
        opening, closing = self.interval
        times = {}
        for steps in [e[0] for e in self._tracked.values()] + [e[0] for e in self._deforming.values()]:
            for i in range(steps):
                u = i / (steps - 1)
                times.setdefault(round(opening + u * (closing - opening), 9), u)
        return times

    def sample(self, depsgraph, frame_set, frame):
        """{key: [m16 per step]} for the tracked objects that move (others are left out)."""
        import time
        t0 = time.perf_counter()
        at = {}  # key -> {u: m16}
        shapes = {}  # key -> {u: MeshArrays} of the deforming objects
        for offset, u in sorted(self._times().items()):
            if offset == 0.0:
                for key, (_, _, m16) in self._tracked.items():
                    at.setdefault(key, {})[u] = m16
                continue
            t = frame + offset
            whole = math.floor(t)
            frame_set(int(whole), t - whole)
            self.evaluations += 1
            for inst in depsgraph.object_instances:
                ob = inst.instance_object if inst.is_instance else inst.object
                if ob is None:
                    continue
                key = instance_key(inst, ob)
                if key in self._tracked:
                    at.setdefault(key, {})[u] = _rows(inst.matrix_world)
                if key in self._deforming:
                    self._sample_deform(ob, key, u, shapes)
        if self.evaluations:
            frame_set(int(frame), 0.0)
        moving = {}
        for key, (steps, _, m16) in self._tracked.items():
            by_u = at.get(key, {})
            matrices = [by_u.get(i / (steps - 1), m16) for i in range(steps)]
            if any(m != m16 for m in matrices):
                moving[key] = matrices
        self._deformations(shapes)
        self.seconds = time.perf_counter() - t0
        return moving

    def instances(self, key):
        return self._tracked[key][1]
