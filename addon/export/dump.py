"""Bug-report dump: the exported scene as the command-line renderer's JSON scene file
(docs/scene-format.md), mesh arrays inline or in a side .bin file.

    write_scene_json(depsgraph, "/tmp/scene.json", binary=True)

works under `blender -b` (see also the RENDEZVOUS_OT_export_scene operator)."""

import json
import math
import os

import numpy as np

from ..utils import Messages


def _num(x):
    x = float(x)
    if not math.isfinite(x):
        return None  # JSON has no NaN: the CLI reports the null as a malformed value
    return x


def _floats(arr):
    return [_num(x) for x in np.asarray(arr, dtype=np.float64).reshape(-1)]


class JsonSink:
    """Collects the engine scene calls as the JSON scene format."""

    def __init__(self, bin_file=None, bin_name=None):
        self.materials = []
        self._material_names = []
        self._grids = {}
        self.meshes = []
        self.instances = []
        self.lights = []
        self.world = None
        self.camera = None
        self._bin = bin_file
        self._bin_name = bin_name

    def add_grid(self, name, values, resolution):
        """A grid buffer: scene files have none, so materials get its values inline."""
        self._grids[name] = {"resolution": [int(x) for x in resolution], "values": _floats(values)}

    def _inline_grids(self, params):
        volume = params.get("volume")
        if not isinstance(volume, dict):
            return params
        volume = dict(volume)
        for key, grid in volume.items():
            if isinstance(grid, dict) and "buffer" in grid:
                inline = {k: v for k, v in grid.items() if k != "buffer"}
                inline.update(self._grids[grid["buffer"]])
                volume[key] = inline
        return dict(params, volume=volume)

    def add_material(self, name, params):
        d = {"name": name}
        d.update(self._inline_grids(params))
        self.materials.append(d)
        self._material_names.append(name)
        return len(self.materials) - 1

    def _write_bin(self, arr, dtype):
        arr = np.ascontiguousarray(arr, dtype=dtype)
        offset = self._bin.tell()
        self._bin.write(arr.astype(arr.dtype.newbyteorder("<"), copy=False).tobytes())
        pad = (-self._bin.tell()) % 4
        if pad:
            self._bin.write(b"\0" * pad)
        return offset

    def add_mesh(self, name, positions, indices, normals=None, uvs=None, material_ids=None, default_material=0,
                 attributes=None):
        positions = np.asarray(positions, dtype=np.float32).reshape(-1)
        indices = np.asarray(indices, dtype=np.uint32).reshape(-1)
        d = {"name": name}
        if material_ids is not None:
            ids = np.asarray(material_ids, dtype=np.uint32)
            used, local = np.unique(ids, return_inverse=True)
            d["materials"] = [self._material_names[int(i)] for i in used]
            if len(used) > 1:
                d["material_indices"] = local.astype(np.uint32).tolist()
        else:
            d["materials"] = [self._material_names[int(default_material)]]
        if self._bin is not None:
            b = {"file": self._bin_name, "positions": self._write_bin(positions, np.float32),
                 "num_vertices": int(positions.size // 3),
                 "indices": self._write_bin(indices, np.uint32), "num_triangles": int(indices.size // 3)}
            if normals is not None:
                b["normals"] = self._write_bin(normals, np.float32)
            if uvs is not None:
                b["uvs"] = self._write_bin(uvs, np.float32)
            d["binary"] = b
        else:
            d["positions"] = _floats(positions)
            d["indices"] = indices.tolist()
            if normals is not None:
                d["normals"] = _floats(normals)
            if uvs is not None:
                d["uvs"] = _floats(uvs)
        if attributes:
            d["attributes"] = [{"name": n, "kind": k, "components": int(c), "data": _floats(a)}
                               for n, k, a, c in attributes]
        self.meshes.append(d)
        return len(self.meshes) - 1

    def add_instance(self, mesh, transform):
        self.instances.append({"mesh": self.meshes[mesh]["name"], "transform": [_num(x) for x in transform]})
        return len(self.instances) - 1

    def set_instance_params(self, instance, params):
        self.instances[instance].update(params)

    def set_instance_motion(self, instance, matrices):
        self.instances[instance]["motion"] = [[_num(x) for x in m] for m in matrices]

    def set_mesh_motion(self, mesh, positions, normals=None):
        self.meshes[mesh]["motion_positions"] = [_floats(p) for p in positions]
        if normals is not None:
            self.meshes[mesh]["motion_normals"] = [_floats(n) for n in normals]

    def add_light(self, name, params):
        d = {"name": name}
        d.update(params)
        self.lights.append(d)
        return len(self.lights) - 1

    def set_world(self, params):
        self.world = dict(params)

    def set_camera(self, params):
        self.camera = dict(params)

    def document(self, settings):
        doc = {"settings": settings}
        if self.camera is not None:
            doc["camera"] = self.camera
        if self.world is not None:
            doc["world"] = self.world
        doc["materials"] = self.materials
        doc["meshes"] = self.meshes
        doc["instances"] = self.instances
        doc["lights"] = self.lights
        return doc


def write_scene_json(depsgraph, filepath, binary=False, props=None, image_average=None):
    """Exports the evaluated scene to `filepath` (and `<stem>.bin` when binary).

    Returns (filepath, warnings).  Usable under `blender -b --python-expr`."""
    from . import SceneExporter, session_settings
    if image_average is None:
        from ..utils.images import image_average as _avg
        image_average = _avg
    scene = depsgraph.scene
    props = props if props is not None else scene.rendezvous
    messages = Messages()
    filepath = os.path.abspath(filepath)
    os.makedirs(os.path.dirname(filepath), exist_ok=True)
    bin_file = None
    try:
        if binary:
            bin_path = os.path.splitext(filepath)[0] + ".bin"
            bin_file = open(bin_path, "wb")
            sink = JsonSink(bin_file, os.path.basename(bin_path))
        else:
            sink = JsonSink()
        # Motion steps at other times: the depsgraph follows the scene's frame (motion.py).
        exporter = SceneExporter(depsgraph, sink, image_average=image_average, messages=messages,
                                 frame_set=lambda frame, subframe: scene.frame_set(frame, subframe=subframe))
        exporter.export()
        settings = session_settings(scene, props, warn=messages.warn)
    finally:
        if bin_file is not None:
            bin_file.close()
    doc = sink.document(settings)  # only keys the CLI knows: warnings are returned, not stored
    with open(filepath, "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1, allow_nan=False)
    return filepath, messages.lines
