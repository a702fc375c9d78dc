"""Interactive viewport rendering (view_update / view_draw) - not implemented yet.

Plan (see shared/guides/blender-integration.md, "Viewport"): keep one engine scene alive,
apply depsgraph.updates (transforms via rdv_scene_set_instance_transform, geometry and
shading edits by re-export), restart the session on change, and in view_draw upload the
newest film as a GPU texture through the display-space shader.  The exporter already
takes a sink and an `is_viewport` flag so the same export code serves both.
"""
