"""Render-properties panels, the bug-report operator, and Cycles' panels for our engine."""

import bpy

from .. import binding
from ..export.settings import light_path_source
from . import compat, farm_submit, operators

ENGINE_ID = "RENDEZVOUS"
METROPOLIS = {"PSSMLT", "MMLT", "MLT"}


class RendezvousPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE_ID}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RENDEZVOUS_PT_sampling(RendezvousPanel, bpy.types.Panel):
    """Parent of the Render and Viewport subpanels (as Cycles' Sampling); shows why the
    engine cannot render, if it cannot."""
    bl_label = "Sampling"

    def draw(self, context):
        problem = binding.status_message()
        if problem:
            box = self.layout.box()
            box.alert = True
            lines = _wrap(problem, 60)
            for i, line in enumerate(lines):
                box.label(text=line, icon="ERROR" if i == 0 else "BLANK1")


class RendezvousSubpanel(RendezvousPanel):
    pass


def _split(layout):
    """Labels left, values right, as Cycles' panels."""
    layout.use_property_split = True
    layout.use_property_decorate = False
    return layout


class RENDEZVOUS_PT_sampling_viewport(RendezvousSubpanel, bpy.types.Panel):
    bl_label = "Viewport"
    bl_parent_id = "RENDEZVOUS_PT_sampling"

    def draw(self, context):
        layout = _split(self.layout)
        props = context.scene.rendezvous
        layout.prop(props, "viewport_integrator", text="Integrator")
        col = layout.column(align=True)
        col.prop(props, "viewport_samples", text="Max Samples")
        col.prop(props, "viewport_pause", text="Pause")


class RENDEZVOUS_PT_sampling_render(RendezvousSubpanel, bpy.types.Panel):
    bl_label = "Render"
    bl_parent_id = "RENDEZVOUS_PT_sampling"

    def draw(self, context):
        layout = _split(self.layout)
        props = context.scene.rendezvous
        layout.prop(props, "integrator")
        if props.integrator == "BDPT":
            layout.prop(props, "bdpt_mis")
        col = layout.column(align=True)
        col.prop(props, "samples", text="Max Samples")
        col.prop(props, "time_limit")
        if props.integrator == "AUTO" and props.time_limit <= 0.0:
            layout.label(text="Automatic needs a Time Limit", icon="ERROR")
        layout.prop(props, "noise_target")
        if props.integrator in ("PATH", "BDPT"):
            layout.prop(props, "use_adaptive_sampling")
            col = layout.column(align=True)
            col.active = props.use_adaptive_sampling
            col.prop(props, "adaptive_threshold")
            col.prop(props, "adaptive_min_samples")


class RENDEZVOUS_PT_sampling_metropolis(RendezvousSubpanel, bpy.types.Panel):
    """Shown when the render or the viewport uses a Metropolis integrator."""
    bl_label = "Metropolis"
    bl_parent_id = "RENDEZVOUS_PT_sampling"

    @classmethod
    def poll(cls, context):
        if not super().poll(context):
            return False
        props = context.scene.rendezvous
        return props.integrator in METROPOLIS or props.viewport_integrator in METROPOLIS

    def draw(self, context):
        layout = _split(self.layout)
        props = context.scene.rendezvous
        layout.prop(props, "mlt_target")
        col = layout.column(align=True)
        col.prop(props, "mlt_large_step")
        col.prop(props, "mlt_step_size")
        col.prop(props, "mlt_chains")
        col.prop(props, "mlt_bootstrap")
        if "MLT" in (props.integrator, props.viewport_integrator):
            col = layout.column(align=True, heading="Mutations")
            col.prop(props, "mlt_mutation_bidirectional")
            col.prop(props, "mlt_mutation_lens")
            col.prop(props, "mlt_mutation_propagation")
            col.prop(props, "mlt_mutation_scattering")
            col.prop(props, "mlt_mutation_caustic")
            col.prop(props, "mlt_mutation_multi_chain")
            col.prop(props, "mlt_mutation_lens_subpath")
            layout.prop(props, "mlt_keep_distances")
            layout.prop(props, "mlt_equiangular")
            layout.prop(props, "mlt_direct_samples")


class RENDEZVOUS_PT_sampling_advanced(RendezvousSubpanel, bpy.types.Panel):
    bl_label = "Advanced"
    bl_parent_id = "RENDEZVOUS_PT_sampling"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = _split(self.layout)
        props = context.scene.rendezvous
        col = layout.column(align=True)
        col.prop(props, "seed")
        col.prop(props, "use_animated_seed")


class RENDEZVOUS_PT_sampling_farm(RendezvousSubpanel, bpy.types.Panel):
    bl_label = "Farm"
    bl_parent_id = "RENDEZVOUS_PT_sampling"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = _split(self.layout)
        props = context.scene.rendezvous
        col = layout.column(align=True)
        col.prop(props, "sample_offset")
        col.prop(props, "part_output")
        col.operator(farm_submit.RENDEZVOUS_OT_farm_submit.bl_idname, icon="NETWORK_DRIVE")


class RENDEZVOUS_PT_light_paths(RendezvousPanel, bpy.types.Panel):
    bl_label = "Light Paths"

    def draw(self, context):
        pass


class RENDEZVOUS_PT_light_paths_max_bounces(RendezvousSubpanel, bpy.types.Panel):
    """Cycles' settings (scene.cycles, shared with Cycles) when its add-on is enabled, else ours."""
    bl_label = "Max Bounces"
    bl_parent_id = "RENDEZVOUS_PT_light_paths"

    def draw(self, context):
        layout = _split(self.layout)
        src = light_path_source(context.scene)
        layout.prop(src, "max_bounces", text="Total")
        col = layout.column(align=True)
        col.prop(src, "diffuse_bounces", text="Diffuse")
        col.prop(src, "glossy_bounces", text="Glossy")
        col.prop(src, "transmission_bounces", text="Transmission")
        col.prop(src, "volume_bounces", text="Volume")
        layout.prop(src, "transparent_max_bounces", text="Transparent")


class RENDEZVOUS_PT_light_paths_clamping(RendezvousSubpanel, bpy.types.Panel):
    bl_label = "Clamping"
    bl_parent_id = "RENDEZVOUS_PT_light_paths"

    def draw(self, context):
        layout = _split(self.layout)
        src = light_path_source(context.scene)
        col = layout.column(align=True)
        col.prop(src, "sample_clamp_direct", text="Direct Light")
        col.prop(src, "sample_clamp_indirect", text="Indirect Light")
        layout.prop(context.scene.rendezvous, "clamp", text="Sample")


class RENDEZVOUS_PT_light_paths_caustics(RendezvousSubpanel, bpy.types.Panel):
    bl_label = "Caustics"
    bl_parent_id = "RENDEZVOUS_PT_light_paths"

    def draw(self, context):
        layout = _split(self.layout)
        src = light_path_source(context.scene)
        layout.prop(src, "blur_glossy", text="Filter Glossy")
        col = layout.column(heading="Caustics", align=True)
        col.prop(src, "caustics_reflective", text="Reflective")
        col.prop(src, "caustics_refractive", text="Refractive")


class RENDEZVOUS_PT_motion_blur(RendezvousPanel, bpy.types.Panel):
    """Cycles' Motion Blur panel: Blender's switch and shutter (scene.render), Cycles'
    Position (scene.cycles while its add-on is enabled: the shutter centred on the frame
    otherwise)."""
    bl_label = "Motion Blur"
    bl_options = {"DEFAULT_CLOSED"}

    def draw_header(self, context):
        self.layout.prop(context.scene.render, "use_motion_blur", text="")

    def draw(self, context):
        layout = _split(self.layout)
        scene = context.scene
        layout.active = scene.render.use_motion_blur
        cycles = getattr(scene, "cycles", None)
        if cycles is not None and hasattr(cycles, "motion_blur_position"):
            layout.prop(cycles, "motion_blur_position", text="Position")
        layout.prop(scene.render, "motion_blur_shutter")


class RENDEZVOUS_PT_film(RendezvousPanel, bpy.types.Panel):
    """Cycles' Film panel: Pixel Filter and Transparent (with Transparent Glass)."""
    bl_label = "Film"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = _split(self.layout)
        render = context.scene.render
        layout.prop(render, "filter_size", text="Pixel Filter")
        col = layout.column(heading="Transparent")
        col.prop(render, "film_transparent", text="")
        src = light_path_source(context.scene)
        sub = col.column()
        sub.active = render.film_transparent
        sub.prop(src, "film_transparent_glass", text="Transparent Glass")
        glass = sub.column()
        glass.active = render.film_transparent and src.film_transparent_glass
        glass.prop(src, "film_transparent_roughness", text="Roughness Threshold")


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


class RENDEZVOUS_PT_passes(RendezvousPanel, bpy.types.Panel):
    """View Layer > Passes of our own (Blender's Data panel shows Depth, Normal, Diffuse Color)."""
    bl_label = "Rendezvous Passes"
    bl_context = "view_layer"

    def draw(self, context):
        layout = _split(self.layout)
        layout.prop(context.scene.rendezvous, "use_pass_noise")
        layer = getattr(context.view_layer, "rendezvous", None)
        if layer is not None:
            layout.prop(layer, "use_pass_strategies")
            row = layout.row()
            row.active = layer.use_pass_strategies
            row.prop(layer, "strategy_max_depth")


# Parents before their subpanels (Blender needs the parent registered first).
classes = (RENDEZVOUS_PT_sampling, RENDEZVOUS_PT_sampling_viewport, RENDEZVOUS_PT_sampling_render,
           RENDEZVOUS_PT_sampling_metropolis, RENDEZVOUS_PT_sampling_advanced, RENDEZVOUS_PT_sampling_farm,
           RENDEZVOUS_PT_light_paths, RENDEZVOUS_PT_light_paths_max_bounces, RENDEZVOUS_PT_light_paths_clamping,
           RENDEZVOUS_PT_light_paths_caustics, RENDEZVOUS_PT_motion_blur, RENDEZVOUS_PT_film,
           RENDEZVOUS_PT_performance, RENDEZVOUS_PT_passes)


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
