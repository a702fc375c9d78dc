"""The RenderEngine: final renders (final.py), the interactive viewport (viewport.py),
material previews (preview.py)."""

import bpy

from . import final, passes, preview, viewport

ENGINE_ID = "RENDEZVOUS"


class RendezvousRenderEngine(bpy.types.RenderEngine):
    bl_idname = ENGINE_ID
    bl_label = "Rendezvous"
    bl_use_preview = True             # material previews (preview.py)
    bl_use_shading_nodes_custom = False  # keep Cycles' shader node editor
    bl_use_postprocess = True
    bl_use_eevee_viewport = True      # Material Preview uses EEVEE (as with Cycles); False sends it to view_draw

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)  # required in 4.x, harmless in 3.x
        self.session = None
        self.viewport = None

    def __del__(self):
        v = getattr(self, "viewport", None)
        if v is not None:
            try:
                v.free()
            except Exception:
                pass
            self.viewport = None
        s = getattr(self, "session", None)
        if s is not None:
            try:
                s.cancel()
            except Exception:
                pass

    def render(self, depsgraph):
        if self.is_preview:
            preview.render(self, depsgraph)
        else:
            final.render(self, depsgraph)

    def view_update(self, context, depsgraph):
        viewport.view_update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        viewport.view_draw(self, context, depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        passes.register_passes(self, scene, renderlayer)


def register():
    bpy.utils.register_class(RendezvousRenderEngine)


def unregister():
    viewport.stop_all()
    bpy.utils.unregister_class(RendezvousRenderEngine)
