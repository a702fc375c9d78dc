"""The RenderEngine: final renders (final.py); the viewport (viewport.py) comes later."""

import bpy

from . import final

ENGINE_ID = "RENDEZVOUS"


class RendezvousRenderEngine(bpy.types.RenderEngine):
    bl_idname = ENGINE_ID
    bl_label = "Rendezvous"
    bl_use_preview = False            # material previews: later, with the viewport
    bl_use_shading_nodes_custom = False  # keep Cycles' shader node editor
    bl_use_postprocess = True
    bl_use_eevee_viewport = True      # Material Preview shading uses EEVEE until viewport.py exists

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)  # required in 4.x, harmless in 3.x
        self.session = None

    def __del__(self):
        s = getattr(self, "session", None)
        if s is not None:
            try:
                s.cancel()
            except Exception:
                pass

    def render(self, depsgraph):
        final.render(self, depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        final.register_passes(self, scene, renderlayer)


def register():
    bpy.utils.register_class(RendezvousRenderEngine)


def unregister():
    bpy.utils.unregister_class(RendezvousRenderEngine)
