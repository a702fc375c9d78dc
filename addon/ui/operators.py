"""RENDEZVOUS_OT_export_scene: write the scene as the command-line renderer's JSON."""

import bpy
from bpy.props import BoolProperty, StringProperty

from ..export.dump import write_scene_json


class RENDEZVOUS_OT_export_scene(bpy.types.Operator):
    """Write the exported scene as a Rendezvous JSON scene file (for bug reports)"""

    bl_idname = "rendezvous.export_scene"
    bl_label = "Export Rendezvous Scene (.json)"
    bl_options = {"REGISTER"}

    filepath: StringProperty(subtype="FILE_PATH", default="")
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    binary: BoolProperty(name="Mesh Data in .bin", default=True,
                         description="Write mesh arrays to a side .bin file instead of inline JSON")

    def invoke(self, context, event):
        if not self.filepath:
            blend = bpy.data.filepath
            stem = bpy.path.display_name_from_filepath(blend) if blend else "scene"
            self.filepath = bpy.path.abspath("//%s_rendezvous.json" % stem) if blend else stem + "_rendezvous.json"
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        depsgraph = context.evaluated_depsgraph_get()
        try:
            path, warnings = write_scene_json(depsgraph, bpy.path.abspath(self.filepath), binary=self.binary)
        except Exception as exc:
            self.report({"ERROR"}, "Rendezvous export failed: %s" % exc)
            return {"CANCELLED"}
        for w in warnings:
            self.report({"WARNING"}, w)
        self.report({"INFO"}, "Rendezvous scene written to %s" % path)
        return {"FINISHED"}


def menu_func(self, context):
    self.layout.operator(RENDEZVOUS_OT_export_scene.bl_idname, text="Rendezvous Scene (.json)")


def register():
    bpy.utils.register_class(RENDEZVOUS_OT_export_scene)
    bpy.types.TOPBAR_MT_file_export.append(menu_func)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_func)
    bpy.utils.unregister_class(RENDEZVOUS_OT_export_scene)
