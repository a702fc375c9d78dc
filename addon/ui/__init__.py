"""Render-properties panels, the bug-report operator, and Cycles' panels for our engine."""

import bpy

from .. import binding
from . import compat, farm_submit, operators

ENGINE_ID = "RENDEZVOUS"


class RendezvousPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE_ID}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RENDEZVOUS_PT_sampling(RendezvousPanel, bpy.types.Panel):
    bl_label = "Sampling"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        props = context.scene.rendezvous
        problem = binding.status_message()
        if problem:
            box = layout.box()
            box.alert = True
            for line in _wrap(problem, 60):
                box.label(text=line, icon="ERROR" if line is _wrap(problem, 60)[0] else "BLANK1")
        layout.prop(props, "integrator")
        if props.integrator == "BDPT":
            layout.prop(props, "bdpt_mis")
        if props.integrator in {"PSSMLT", "MMLT"} or props.viewport_integrator in {"PSSMLT", "MMLT"}:
            col = layout.column(align=True, heading="Metropolis")
            col.prop(props, "mlt_large_step")
            col.prop(props, "mlt_step_size")
            col.prop(props, "mlt_chains")
            col.prop(props, "mlt_bootstrap")
        col = layout.column(align=True)
        col.prop(props, "samples")
        col.prop(props, "time_limit")
        col = layout.column(align=True, heading="Viewport")
        col.prop(props, "viewport_integrator", text="Integrator")
        col.prop(props, "viewport_samples", text="Samples")
        col.prop(props, "viewport_pause", text="Pause")
        col = layout.column(align=True)
        col.prop(props, "seed")
        col.prop(props, "use_animated_seed")
        col = layout.column(align=True, heading="Farm")
        col.prop(props, "sample_offset")
        col.prop(props, "part_output")
        col.operator(farm_submit.RENDEZVOUS_OT_farm_submit.bl_idname, icon="NETWORK_DRIVE")


class RENDEZVOUS_PT_light_paths(RendezvousPanel, bpy.types.Panel):
    bl_label = "Light Paths"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        props = context.scene.rendezvous
        layout.prop(props, "max_bounces")
        layout.prop(props, "clamp")


class RENDEZVOUS_PT_performance(RendezvousPanel, bpy.types.Panel):
    bl_label = "Performance"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(context.scene.rendezvous, "threads")
        layout.operator(operators.RENDEZVOUS_OT_export_scene.bl_idname, icon="EXPORT")


def _wrap(text, width):
    words, lines, cur = text.split(), [], ""
    for w in words:
        if len(cur) + len(w) + 1 > width and cur:
            lines.append(cur)
            cur = w
        else:
            cur = (cur + " " + w).strip()
    if cur:
        lines.append(cur)
    return lines


def draw_view3d_header(self, context):
    """The 3D view header's pause toggle in Rendered mode (as Cycles)."""
    view = context.space_data
    if context.engine == ENGINE_ID and view is not None and view.shading.type == "RENDERED":
        props = context.scene.rendezvous
        self.layout.prop(props, "viewport_pause", text="", icon="PLAY" if props.viewport_pause else "PAUSE")


classes = (RENDEZVOUS_PT_sampling, RENDEZVOUS_PT_light_paths, RENDEZVOUS_PT_performance)


def register():
    operators.register()
    farm_submit.register()
    for cls in classes:
        bpy.utils.register_class(cls)
    compat.register()
    bpy.types.VIEW3D_HT_header.append(draw_view3d_header)


def unregister():
    bpy.types.VIEW3D_HT_header.remove(draw_view3d_header)
    compat.unregister()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
    farm_submit.unregister()
    operators.unregister()
