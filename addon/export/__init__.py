"""Evaluated depsgraph -> engine scene calls.

The exporter talks to a *sink* with the engine's scene calls (add_material, add_mesh,
add_instance, add_light, set_world, set_camera): the ctypes binding's Scene for a render,
or dump.JsonSink for the bug-report JSON.  So both paths run the same export.
"""

import time

from .. import shaders_map
from ..utils import Messages, determinant3, is_finite_matrix, normalize_frame
from .camera import camera_params
from .lights import light_params
from .materials import MaterialCache, ray_kind_cells
from . import images
from . import motion
from .mesh import mesh_arrays, TANGENT_ATTRIBUTE
from .object_attributes import instance_attributes, tree_object_attributes, view_layer_lookup
from . import volumes
from . import visibility
from .settings import session_settings, resolution, border_rect, SettingsError  # noqa: F401

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT"}
UV_NODES = {"ShaderNodeTexImage", "ShaderNodeNormalMap", "ShaderNodeTexCoord", "ShaderNodeBsdfAnisotropic",
            "ShaderNodeVectorDisplacement"}


class ExportStats:
    def __init__(self):
        self.meshes = 0
        self.instances = 0
        self.lights = 0
        self.triangles = 0
        self.materials = 0
        self.seconds = 0.0
        self.moving = 0  # objects (and the camera) sent with motion steps
        self.deforming = 0  # meshes sent with deformation steps
        self.motion_seconds = 0.0  # of seconds: sampling their transforms over the shutter

    def as_dict(self):
        return dict(self.__dict__)


def _tree_uses_uvs(tree, depth=0):
    """(uses_default_uvs, set of attribute names) for a material node tree (groups followed a few
    levels): the default UV map (image textures, tangents, ...) and the named UV maps / colour
    attributes that UV Map, Color Attribute and Attribute nodes read."""
    if tree is None or depth > 4:
        return False, set()
    uses, names = False, set()
    for node in tree.nodes:
        idname = node.bl_idname
        if idname in UV_NODES:
            uses = True
            if idname in ("ShaderNodeNormalMap", "ShaderNodeVectorDisplacement") and \
                    getattr(node, "space", "TANGENT") == "TANGENT":
                names.add(TANGENT_ATTRIBUTE)  # Blender's tangents, as Cycles maps with them
        elif idname == "ShaderNodeUVMap":
            if node.uv_map:
                names.add(node.uv_map)
            else:
                uses = True
        elif idname == "ShaderNodeVertexColor":
            names.add(node.layer_name or shaders_map.DEFAULT_COLOR_ATTRIBUTE)
        elif idname == "ShaderNodeAttribute":
            if getattr(node, "attribute_type", "GEOMETRY") == "GEOMETRY" and node.attribute_name:
                names.add(node.attribute_name)
        elif idname == "ShaderNodeNewGeometry":  # Pointiness, Random Per Island: attributes the exporter derives
            for output, name in shaders_map.MESH_DERIVED_ATTRIBUTES.items():
                if node.outputs[output].is_linked:
                    names.add(name)
        elif idname == "ShaderNodeGroup" and node.node_tree is not None:
            u, n = _tree_uses_uvs(node.node_tree, depth + 1)
            uses = uses or u
            names |= n
    return uses, names


def gas_domain(ob):
    """The domain settings of a smoke / fire simulation domain object, else None."""
    for m in getattr(ob, "modifiers", ()):
        if m.type == "FLUID" and getattr(m, "fluid_type", "") == "DOMAIN" and m.show_render:
            ds = m.domain_settings
            return ds if ds.domain_type == "GAS" else None
    return None


def _lookup3_final(a, b, c):
    def rot(x, k):
        return ((x << k) | (x >> (32 - k))) & 0xFFFFFFFF
    for x, y, k in (("c", "b", 14), ("a", "c", 11), ("b", "a", 25), ("c", "b", 16), ("a", "c", 4), ("b", "a", 14),
                    ("c", "b", 24)):
        v = {"a": a, "b": b, "c": c}
        v[x] = ((v[x] ^ v[y]) - rot(v[y], k)) & 0xFFFFFFFF
        a, b, c = v["a"], v["b"], v["c"]
    return c


def name_random_id(name):
    """Cycles' random id of an object that is not an instance: hash_uint2(hash_string(name), 0)
    (Bob Jenkins' lookup3 of the name's 37-polynomial hash), what Object Info > Random reads."""
    h = 0
    for ch in name.encode("utf-8"):
        h = (h * 37 + ch) & 0xFFFFFFFF
    seed = (0xDEADBEEF + (2 << 2) + 13) & 0xFFFFFFFF
    return _lookup3_final((seed + h) & 0xFFFFFFFF, seed, seed)


class SceneExporter:
    def __init__(self, depsgraph, sink, image_average=None, messages=None, is_viewport=False, image_file=None,
                 frame_set=None, cryptomatte=False):
        """frame_set(frame, subframe): evaluates the depsgraph at another time (RenderEngine.frame_set);
        given, objects that move while the shutter is open are sent with their motion steps.
        cryptomatte: the render keeps Cryptomatte passes; objects and materials go with the names
        they show there."""
        self.depsgraph = depsgraph
        self.frame_set = frame_set
        self.scene = depsgraph.scene
        self.sink = sink
        self.messages = messages if messages is not None else Messages()
        self._image_buffers = {}  # image name_full -> digest of the pixels sent in this export
        if image_file is None:
            images.clear_cache()
            image_file = self.image_source
        self.image_file = image_file
        # Attribute nodes of type View Layer: the view layer's, scene's or world's value.
        self.view_layer_attribute = view_layer_lookup(depsgraph.view_layer, self.scene)
        self.materials = MaterialCache(sink, self.messages, image_average, image_file, cryptomatte=cryptomatte,
                                       view_layer_attribute=self.view_layer_attribute)
        self.cryptomatte = cryptomatte
        self.image_average = image_average
        self.stats = ExportStats()
        self._meshes = {}  # ((data pointer, materials), ray kinds of the copy or None) -> engine mesh id or None
        self._mesh_names = set()
        self._light_names = set()
        self._uv_cache = {}
        self._object_attribute_cache = {}  # material name_full -> its Object / Instancer attribute names
        self.is_viewport = is_viewport
        self.motion = None  # motion.MotionSampler while exporting a frame with motion blur
        self.copy_kinds = None  # the ray kinds of the object copy being sent (None: the whole object)
        self._camera_params = None

    def warn(self, text):
        self.messages.warn(text)

    def image_source(self, image, image_user=None):
        """shaders_map's image callback: what the engine reads for `image` (images.image_source
        at this scene frame); an image without a file goes to the sink as a pixel buffer
        named after it (once per export; scene files, whose sink takes no buffers, keep
        its average colour)."""
        source = images.image_source(image, image_user, self.scene.frame_current)
        if source != images.BUFFER:
            return source
        if not hasattr(self.sink, "add_image"):
            return None
        name = image.name_full
        if name not in self._image_buffers:
            pixels = images.image_pixels(image)
            if pixels is None:
                self._image_buffers[name] = None
            else:
                self._image_buffers[name] = self.send_image(name, *pixels)
        return None if self._image_buffers[name] is None else {"buffer": name}

    def send_image(self, name, pixels, width, height, channels, colorspace):
        """Sends an image's pixels to the sink; returns their digest (the viewport skips
        an unchanged one)."""
        self.sink.add_image(name, pixels, width, height, channels, colorspace)
        return images.pixels_digest(pixels)

    # ---- whole scene ------------------------------------------------------------
    def export(self):
        t0 = time.perf_counter()
        # Motion blur (Cycles shows none in the viewport, nor do we).
        self.interval = None if self.is_viewport else motion.shutter_interval(self.scene)
        if self.interval is not None and self.frame_set is not None:
            import bpy
            if motion.scene_is_animated(bpy.data):
                self.motion = motion.MotionSampler(self.interval)
        self.export_camera()
        self.export_world()
        self.export_objects()
        if self.motion is not None:
            self.export_motion()
        self.stats.materials = len(self.materials._ids)
        self.stats.seconds = time.perf_counter() - t0
        return self.stats

    def export_camera(self):
        cam = self.scene.camera
        if cam is None:
            raise ExportError("Scene '%s' has no camera" % self.scene.name)
        cam_eval = cam.evaluated_get(self.depsgraph)
        self._camera_params = camera_params(cam_eval, self.warn)
        if self.interval is not None:
            self._camera_params["shutter_open"], self._camera_params["shutter_close"] = self.interval
        if self.motion is not None:
            self.motion.track_camera((cam.name, "", ()), motion.object_steps(cam),
                                     [float(x) for row in cam_eval.matrix_world for x in row])
        self.sink.set_camera(self._camera_params)

    def export_motion(self):
        """The transforms of what moves while the shutter is open (motion.py)."""
        moving = self.motion.sample(self.depsgraph, self.frame_set, self.scene.frame_current)
        for key, matrices in moving.items():
            if key == self.motion.camera_key:
                self._camera_params["motion"] = [normalize_frame(m)[0] for m in matrices]
                self.sink.set_camera(self._camera_params)
            else:
                for instance in self.motion.instances(key):
                    self.sink.set_instance_motion(instance, matrices)
        for mesh_id, positions, normals in self.motion.deformed:
            self.sink.set_mesh_motion(mesh_id, positions, normals)
        for text in self.motion.warnings:
            self.warn(text)
        self.stats.moving = len(moving)
        self.stats.deforming = len(self.motion.deformed)
        self.stats.motion_seconds = self.motion.seconds

    def export_world(self):
        params, warning = shaders_map.convert_world(self.scene.world, image_average=self.image_average,
                                                    view_layer_attribute=self.view_layer_attribute,
                                                    image_file=self.image_file)
        if warning:
            self.warn(warning)
        hidden = visibility.world_visibility(self.scene.world)
        if hidden:  # World > Ray Visibility
            params["visibility"] = hidden
        # (World > Settings > Max Bounces changes nothing in Cycles 3.4's image, measured: not
        # exported. A lamp's does: light_settings.)
        self.sink.set_world(params)

    def export_objects(self):
        for inst in self.depsgraph.object_instances:
            is_instance = inst.is_instance
            ob = inst.instance_object if is_instance else inst.object
            if ob is None:
                continue
            if not is_instance and not inst.show_self:
                continue
            otype = ob.type
            if otype == "LIGHT":
                self._light(ob, inst.matrix_world)
            elif otype in GEOMETRY_TYPES:
                self._geometry(ob, inst.matrix_world, inst)
            elif otype == "VOLUME":
                self._volume(ob, inst.matrix_world)
            elif otype in ("VOLUME", "CURVES", "POINTCLOUD"):
                self.warn("Object '%s': %s objects not supported yet, skipped" % (ob.name, otype.lower()))

    # ---- lights -------------------------------------------------------------------
    def _light(self, ob, matrix):
        m16 = [*matrix[0], *matrix[1], *matrix[2], *matrix[3]]
        if not is_finite_matrix(m16):
            self.warn("Light '%s': non-finite transform, skipped" % ob.name)
            return
        params = self.light_settings(ob, m16)
        if params is None:
            return
        name = self._unique(ob.name, self._light_names)
        self.sink.add_light(name, params)
        self.stats.lights += 1

    def light_settings(self, ob, m16):
        """The light's engine parameters with its ray visibility and shadow-catcher flag (None:
        skipped, warned)."""
        params = light_params(ob.data, m16, ob.name, self.warn, self.view_layer_attribute, self.image_average,
                              self.image_file)
        if params is not None:
            rays = visibility.light_visibility(ob, ob.data)
            if rays:  # Object > Visibility > Ray Visibility, Light > Cast Shadow
                params["visibility"] = rays
            # Object > Visibility > Shadow Catcher on a light (on for new lights): a light of
            # the footage, which lights the Shadow Catcher pass too; turned off, the light is
            # the synthetic objects' own and lights only the image (Cycles 3.4).
            if not getattr(ob, "is_shadow_catcher", True):
                params["shadow_catcher"] = False
            # Light > Max Bounces (Cycles' light.cycles.max_bounces, default 1024: no limit
            # in practice): the light lights paths of at most that many bounces.
            cycles = getattr(ob.data, "cycles", None)
            max_bounces = int(getattr(cycles, "max_bounces", 1024)) if cycles is not None else 1024
            if max_bounces < 1024:
                params["max_bounces"] = max(0, max_bounces)
        return params

    # ---- geometry -------------------------------------------------------------------
    @staticmethod
    def object_settings(ob, inst=None, kinds=None, attributes=(), cryptomatte=False):
        """rdv_scene_set_instance_params of a mesh object: holdout, shadow catcher, ray visibility,
        pass index, what an Object Info node reads: the depsgraph instance's random_id (inst)
        and the object's colour ({}: defaults), and the values of `attributes`, the (type, name)
        pairs of its materials' Attribute nodes of type Object / Instancer (object_attributes.py).
        kinds: the ray kinds one copy of it is seen by (ray_kind_cells), None for all.
        cryptomatte: with the names its Cryptomatte passes show, as Cycles': the object's, and
        its asset's, the topmost of its parents (an instance's within what is instanced)."""
        settings = instance_attributes(ob, inst, attributes) if attributes else {}
        if getattr(ob, "pass_index", 0):  # Object > Relations > Pass Index (the Object Index pass)
            settings["pass_index"] = int(ob.pass_index)
        # Object Info > Random, as Cycles takes it: an instance's random_id from the depsgraph
        # (Blender's signed 32-bit int, Cycles' unsigned), an object's from a hash of its name.
        if inst is not None and getattr(inst, "is_instance", False):
            random_id = int(getattr(inst, "random_id", 0)) & 0xFFFFFFFF
        else:
            random_id = name_random_id(ob.name)
        if random_id:
            settings["random_id"] = random_id
        color = tuple(float(c) for c in getattr(ob, "color", (1.0, 1.0, 1.0, 1.0)))
        if color != (1.0, 1.0, 1.0, 1.0) and len(color) == 4:  # Object > Viewport Display > Color
            settings["color"] = list(color)
        if getattr(ob, "is_holdout", False):  # Object > Visibility > Holdout
            settings["holdout"] = True
        if getattr(ob, "is_shadow_catcher", False):  # Object > Visibility > Shadow Catcher
            settings["shadow_catcher"] = True
        rays = visibility.object_visibility(ob, kinds)
        if rays:  # Object > Visibility > Ray Visibility
            settings["visibility"] = rays
        if kinds is not None:  # one of the object's copies on one spot, a look per ray kind
            settings["look_copy"] = True
        if cryptomatte:
            top = ob
            while top.parent is not None:
                top = top.parent
            settings["cryptomatte"] = {"object": ob.name, "asset": top.name}
        return settings

    @staticmethod
    def _scanned(cache, mats, scan):
        """scan(node_tree) of each node material of mats, cached by the material's name."""
        for m in mats:
            if m is None or not m.use_nodes:
                continue
            if m.name_full not in cache:
                cache[m.name_full] = scan(m.node_tree)
            yield cache[m.name_full]

    def object_attribute_names(self, mats):
        """The (type, name) pairs of the Object / Instancer Attribute nodes in materials mats."""
        return set().union(*self._scanned(self._object_attribute_cache, mats, tree_object_attributes))

    def _object_materials(self, ob):
        mats = [slot.material for slot in ob.material_slots]
        if not mats and ob.data is not None and hasattr(ob.data, "materials"):
            mats = list(ob.data.materials)
        return mats

    def _uv_needs(self, mats):
        uses, names = False, set()
        for u, n in self._scanned(self._uv_cache, mats, _tree_uses_uvs):
            uses = uses or u
            names |= n
        return uses, sorted(names)

    def _geometry(self, ob, matrix, inst=None):
        m16 = [*matrix[0], *matrix[1], *matrix[2], *matrix[3]]
        if not is_finite_matrix(m16):
            self.warn("Object '%s': non-finite transform, skipped" % ob.name)
            return
        if abs(determinant3(m16)) < 1e-24:
            self.warn("Object '%s': zero scale, skipped" % ob.name)
            return
        domain = gas_domain(ob)
        if domain is not None:
            self._grid_medium(ob, m16, self._fluid_source(ob, m16, domain))
            return
        mats = self._object_materials(ob)
        data = ob.data
        key = (data.as_pointer() if data is not None else ob.as_pointer(),
               tuple(m.name_full if m is not None else None for m in mats))
        # One copy of the object per group of ray kinds that see its materials alike (Light
        # Path's ray types, materials.py), each seen by its group alone; usually one.
        cells = ray_kind_cells([self.materials.looks(m) for m in mats]) if mats else [(None, None)]
        first_frame = None  # the first copy's arrays, which the other looks' copies send again
        for kinds, slot_ids in cells:
            settings = self.object_settings(ob, inst, kinds, self.object_attribute_names(mats), self.cryptomatte)
            if kinds is not None and visibility.hidden_from_all(settings.get("visibility", {})):
                continue  # a look no ray of the object's own visibility sees
            frame = None
            copy = (key, tuple(kinds) if kinds else None)
            if copy in self._meshes:
                mesh_id = self._meshes[copy]
            else:
                frame = []  # the mesh's arrays at the frame, for deformation blur
                mesh_id = self._meshes[copy] = self._add_mesh(ob, mats, frame, slot_ids, copy_of=first_frame)
                first_frame = first_frame or frame
            if mesh_id is None:
                return
            self.copy_kinds = kinds  # which copy the sink is given (the viewport keeps it)
            instance = self.sink.add_instance(mesh_id, m16)
            if settings:
                self.sink.set_instance_params(instance, settings)
            if self.motion is not None and inst is not None:
                self.motion.track(motion.instance_key(inst, ob), motion.object_steps(ob), instance, m16)
                if frame and motion.may_deform(ob):
                    self.motion.track_deform(motion.instance_key(inst, ob), motion.object_steps(ob), mesh_id,
                                             *frame[0])
            self.stats.instances += 1

    # ---- grid media: Volume objects and fluid domains ---------------------------------------
    def _volume(self, ob, matrix):
        """A Volume object: its .vdb grid as a medium inside a box around the grid (volumes.py)."""
        m16 = [*matrix[0], *matrix[1], *matrix[2], *matrix[3]]
        if not is_finite_matrix(m16) or abs(determinant3(m16)) < 1e-24:
            self.warn("Volume '%s': non-finite or zero-scale transform, skipped" % ob.name)
            return
        self._grid_medium(ob, m16, self.grid_source(ob, m16))

    def grid_source(self, ob, m16):
        """(what, lo, hi, lookup) of a Volume object or a gas simulation domain: its name for
        warnings, the box [lo, hi] (object space) its grids fill, and the grid lookup for
        attach_grids; None (warned) when it has nothing to render."""
        if ob.type == "VOLUME":
            return self._volume_source(ob, m16)
        domain = gas_domain(ob)
        return self._fluid_source(ob, m16, domain) if domain is not None else None

    def _volume_source(self, ob, m16):
        import bpy
        what = "Volume '%s'" % ob.name
        path, problem = volumes.volume_file(ob.data, self.scene.frame_current, bpy.path.abspath)
        if problem:
            self.warn("%s: %s, skipped" % (what, problem))
            return None
        corners = [tuple(c) for c in ob.bound_box]
        lo = [min(c[a] for c in corners) for a in range(3)]
        hi = [max(c[a] for c in corners) for a in range(3)]
        # A file that went missing keeps its old bounds in a window session's render
        # depsgraph: look at the file and its grids, not only at the bounds.
        reason = volumes.unreadable(path, ob.data.grids, lo, hi)
        if reason:
            self.warn("%s: %s (file '%s'), skipped" % (what, reason, path))
            return None
        grids = {g.name: (g.data_type, [list(row)[:3] for row in g.matrix_object][:3]) for g in ob.data.grids}
        # The grids' zero margin (a voxel, plus Cycles' half-voxel shift) stays inside.
        voxel = max((sum(x * x for x in col) ** 0.5 for _, m in grids.values() for col in zip(*m)), default=0.0)
        pad = [max(0.01 * (h - l), 2.0 * voxel) for l, h in zip(lo, hi)]
        lo = [l - p for l, p in zip(lo, pad)]
        hi = [h + p for h, p in zip(hi, pad)]
        return what, lo, hi, volumes.vdb_lookup(path, grids, m16)

    def _fluid_source(self, ob, m16, ds):
        """A smoke / fire domain: the simulation's grids for this frame (what Cycles reads,
        any cache format), filling the domain's box."""
        what = "Fluid domain '%s'" % ob.name
        if not all(int(x) > 0 for x in ds.domain_resolution):
            self.warn("%s: no simulation data at frame %d (bake the cache, or play the frames "
                      "with a Replay cache), skipped" % (what, self.scene.frame_current))
            return None
        # The grids fill the domain mesh's texture space (the adaptive box when adaptive).
        me = ob.data
        loc, size = list(me.texspace_location), list(me.texspace_size)
        lo = [c - abs(h) for c, h in zip(loc, size)]
        hi = [c + abs(h) for c, h in zip(loc, size)]
        if not all(h > l for l, h in zip(lo, hi)):
            self.warn("%s: empty bounds, skipped" % what)
            return None
        return what, lo, hi, volumes.fluid_lookup(ds, [lo, hi], m16, "the simulation")

    def grid_material(self, ob, what, lookup):
        """Engine material params of the object's volume material over its grids (a
        surface-less medium boundary), or None (warned) without a Volume shader."""
        mats = self._object_materials(ob)
        medium, warning = volumes.volume_material_params(mats[0] if mats else None, self.image_average,
                                                         self.image_file)
        if warning:
            self.warn(warning)
        if medium is None:
            self.warn("%s: its material has no Volume shader, nothing to render" % what)
            return None
        medium = dict(medium)
        for w in volumes.attach_grids(medium, lookup, what):
            self.warn(w)
        return {"type": "volume", "volume": medium}

    def with_grid_buffers(self, ob, params, changed=None):
        """The grid material params with its dense (simulation) grids sent to the sink as
        binary buffers named after the object, not as JSON values; changed(name, values)
        -> False skips sending an unchanged one (the viewport)."""
        medium, buffers = volumes.split_dense_grids(params["volume"], ob.name_full)
        for name, values, resolution in buffers:
            if changed is None or changed(name, values):
                self.sink.add_grid(name, values, resolution)
        return dict(params, volume=medium)

    def _grid_medium(self, ob, m16, source):
        """The object's grid medium (grid_source, grid_material) in its box placed by m16:
        (material id, mesh id) or None."""
        if source is None:
            return None
        what, lo, hi, lookup = source
        params = self.grid_material(ob, what, lookup)
        if params is None:
            return None
        name = self._unique(ob.name, self._mesh_names)
        params = self.with_grid_buffers(ob, params)
        material = self.sink.add_material(name, params)
        positions, indices = volumes.box_arrays(lo, hi)
        mesh_id = self.sink.add_mesh(name, positions, indices, default_material=material)
        self.sink.add_instance(mesh_id, m16)
        self.stats.meshes += 1
        self.stats.instances += 1
        return material, mesh_id

    def _add_mesh(self, ob, mats, frame=None, slot_ids=None, copy_of=None):
        """The object's evaluated mesh to the sink: its mesh id, or None (warned). frame: a
        list that receives (arrays, need_uvs, attribute names), the layout its deformation
        steps must repeat (motion.MotionSampler.track_deform). slot_ids: the engine material
        of each slot (one look of each, ray_kind_cells), else the materials' own. copy_of:
        the frame list of another look's copy of this mesh, whose arrays are sent again."""
        if copy_of:
            _, arrays, need_uvs, attr_names = copy_of[0]
        else:
            need_uvs, attr_names = self._uv_needs(mats)
            arrays = self._mesh_arrays(ob, need_uvs, attr_names)
            if arrays is None:
                return None
        if mats:
            import numpy as np
            slot_ids = np.array(slot_ids if slot_ids is not None else [self.materials.get(m) for m in mats],
                                dtype=np.uint32)
            idx = np.minimum(arrays.slot_indices, len(slot_ids) - 1)
            material_ids = slot_ids[idx]
            default = int(slot_ids[0])
        else:
            material_ids = None
            default = self.materials.default()
        name = self._unique(ob.name, self._mesh_names)
        kw = {"attributes": arrays.attributes} if arrays.attributes else {}
        mesh_id = self.sink.add_mesh(name, arrays.positions, arrays.indices, normals=arrays.normals,
                                     uvs=arrays.uvs, material_ids=material_ids, default_material=default, **kw)
        self.stats.meshes += 1
        self.stats.triangles += arrays.num_triangles
        if frame is not None and mesh_id is not None:
            frame.append((ob.name, arrays, need_uvs, attr_names))
        return mesh_id

    def _mesh_arrays(self, ob, need_uvs, attr_names):
        """The object's evaluated mesh as MeshArrays, or None (warned)."""
        owned = False
        me = None
        if ob.type == "MESH" and ob.mode != "EDIT":
            me = ob.data
        else:
            try:
                me = ob.to_mesh()
                owned = True
            except RuntimeError:
                me = None
        if me is None:
            self.warn("Object '%s': could not be converted to a mesh, skipped" % ob.name)
            return None
        try:
            arrays = mesh_arrays(me, need_uvs=need_uvs, attributes=attr_names)
        finally:
            if owned:
                ob.to_mesh_clear()
        if arrays is None:
            self.warn("Object '%s': no faces, nothing to render" % ob.name)
            return None
        if arrays.num_nonfinite:
            self.warn("Object '%s': %d vertices with non-finite (NaN/Inf) positions; their triangles are dropped"
                      % (ob.name, arrays.num_nonfinite))
        return arrays

    @staticmethod
    def _unique(name, used):
        out, n = name, 1
        while out in used:
            n += 1
            out = "%s#%d" % (name, n)
        used.add(out)
        return out


class ExportError(RuntimeError):
    """The scene cannot be rendered (e.g. no camera); the message is for the user."""
