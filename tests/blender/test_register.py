"""Register/unregister the add-on twice without errors; the engine, settings and Cycles'
panels appear and disappear."""

import sys
import traceback

import addon_utils
import bpy


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def engine_available():
    render = bpy.context.scene.render
    old = render.engine
    try:
        render.engine = "RENDEZVOUS"
        return True
    except TypeError:
        return False
    finally:
        render.engine = old if old != "RENDEZVOUS" else "CYCLES"


def registered_state():
    panels = [p for p in bpy.types.Panel.__subclasses__()
              if "RENDEZVOUS" in getattr(p, "COMPAT_ENGINES", ()) and not p.__name__.startswith("RENDEZVOUS_")]
    return {
        "engine": engine_available(),
        "props": hasattr(bpy.types.Scene, "rendezvous"),
        "compat_panels": len(panels),
        "operator": hasattr(bpy.types, "RENDEZVOUS_OT_export_scene"),
        "panel": hasattr(bpy.types, "RENDEZVOUS_PT_sampling"),
    }


def all_off(s):
    return not (s["engine"] or s["props"] or s["compat_panels"] or s["operator"] or s["panel"])


class RecordingLayout:
    """Enough of bpy.types.UILayout for our panels' draw(): checks that every property
    drawn exists and records (owner, name)."""

    def __init__(self, shown):
        self.shown = shown
        self.use_property_split = self.use_property_decorate = self.alert = False

    def prop(self, data, name, **kwargs):
        check(hasattr(data, name), "a panel draws %r, which %r does not have" % (name, data))
        owner = "rendezvous" if isinstance(data, type(bpy.context.scene.rendezvous)) else type(data).__name__
        self.shown.add((owner, name))

    def column(self, **kwargs):
        return self

    row = box = column

    def label(self, **kwargs):
        pass

    def operator(self, idname, **kwargs):
        pass

    def separator(self, **kwargs):
        pass


# Render properties laid out as Cycles': (panel, label, parent).
LAYOUT = [
    ("RENDEZVOUS_PT_sampling", "Sampling", None),
    ("RENDEZVOUS_PT_sampling_viewport", "Viewport", "RENDEZVOUS_PT_sampling"),
    ("RENDEZVOUS_PT_sampling_render", "Render", "RENDEZVOUS_PT_sampling"),
    ("RENDEZVOUS_PT_sampling_advanced", "Advanced", "RENDEZVOUS_PT_sampling"),
    ("RENDEZVOUS_PT_light_paths", "Light Paths", None),
    ("RENDEZVOUS_PT_light_paths_max_bounces", "Max Bounces", "RENDEZVOUS_PT_light_paths"),
    ("RENDEZVOUS_PT_light_paths_clamping", "Clamping", "RENDEZVOUS_PT_light_paths"),
    ("RENDEZVOUS_PT_light_paths_caustics", "Caustics", "RENDEZVOUS_PT_light_paths"),
    ("RENDEZVOUS_PT_motion_blur", "Motion Blur", None),
]


def check_render_properties_layout():
    for name, label, parent in LAYOUT:
        panel = getattr(bpy.types, name, None)
        check(panel is not None, "panel %s is not registered" % name)
        check(panel.bl_label == label, "%s is labelled %r, not %r" % (name, panel.bl_label, label))
        check(getattr(panel, "bl_parent_id", None) == parent or (parent is None and not getattr(panel, "bl_parent_id", "")),
              "%s's parent is %r, not %r" % (name, getattr(panel, "bl_parent_id", None), parent))
    # Each panel draws (a layout stand-in records and checks every property it shows).
    shown = set()
    for name, _, _ in LAYOUT:
        panel = getattr(bpy.types, name)
        fake = type("FakePanel", (), {"layout": RecordingLayout(shown)})()
        panel.draw(fake, bpy.context)
    for want in ("integrator", "samples", "viewport_integrator", "viewport_samples", "seed"):
        check(("rendezvous", want) in shown, "no panel shows scene.rendezvous.%s" % want)
    # Light Paths: Cycles' own settings while Cycles is enabled (shared, as Cycles shares them).
    for want in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces",
                 "caustics_reflective", "caustics_refractive", "sample_clamp_direct", "sample_clamp_indirect",
                 "blur_glossy", "motion_blur_position"):
        check(("CyclesRenderSettings", want) in shown, "the render panels do not show scene.cycles.%s" % want)
    check(("RenderSettings", "motion_blur_shutter") in shown, "the Motion Blur panel does not show the shutter")
    # Every setting says what it trades: a tooltip of a sentence at least.
    props = bpy.context.scene.rendezvous
    for prop in props.bl_rna.properties:
        if prop.identifier in ("rna_type", "name"):
            continue
        check(len(prop.description) >= 40, "scene.rendezvous.%s's tooltip is too short: %r"
              % (prop.identifier, prop.description))


# Cycles' panels a Rendezvous user needs (their poll, not only their engine set: most call
# CyclesButtonsPanel.poll(context) by name, which reads the base class's set), and Cycles'
# own render settings, which stay hidden.
SHOWN_PANELS = ("CYCLES_PT_context_material", "CYCLES_MATERIAL_PT_surface", "CYCLES_LIGHT_PT_light",
                "CYCLES_WORLD_PT_surface", "CYCLES_WORLD_PT_ray_visibility", "CYCLES_OBJECT_PT_visibility",
                "CYCLES_OBJECT_PT_visibility_ray_visibility", "CYCLES_OBJECT_PT_motion_blur", "CYCLES_CAMERA_PT_dof",
                "CYCLES_RENDER_PT_passes_light")
HIDDEN_PANELS = ("CYCLES_RENDER_PT_sampling", "CYCLES_RENDER_PT_light_paths", "CYCLES_RENDER_PT_motion_blur",
                 "CYCLES_RENDER_PT_film")


def panel_polls(engine):
    """Each listed panel's poll with the default scene's cube, lamp, camera and world in context."""
    scene = bpy.context.scene
    scene.render.engine = engine
    cube, lamp, camera = (bpy.data.objects[n] for n in ("Cube", "Light", "Camera"))
    with bpy.context.temp_override(object=cube, active_object=cube, material=cube.active_material, world=scene.world,
                                   light=lamp.data, camera=camera.data):
        return {name: bool(getattr(bpy.types, name).poll(bpy.context)) for name in SHOWN_PANELS + HIDDEN_PANELS}


def check_panel_polls():
    polls = panel_polls("RENDEZVOUS")
    for name in SHOWN_PANELS:
        check(polls[name], "%s is hidden under Rendezvous" % name)
    for name in HIDDEN_PANELS:
        check(not polls[name], "%s (Cycles' own setting) shows under Rendezvous" % name)
    cycles = panel_polls("CYCLES")
    check(all(cycles.values()), "Cycles' panels under Cycles: %r" % cycles)


def main():
    try:
        addon_utils.enable("cycles", default_set=True)
        for i in range(2):
            if addon_utils.check("rendezvous")[1]:
                addon_utils.disable("rendezvous", default_set=True, handle_error=None)
            s = registered_state()
            check(all_off(s), "round %d: state after disable: %r" % (i, s))
            mod = addon_utils.enable("rendezvous", default_set=True, handle_error=None)
            check(mod is not None, "enable failed")
            s = registered_state()
            check(s["props"] and s["engine"] and s["operator"] and s["panel"] and s["compat_panels"] > 20,
                  "round %d: state after enable: %r" % (i, s))
            bpy.context.scene.render.engine = "RENDEZVOUS"
            check(bpy.context.scene.render.engine == "RENDEZVOUS", "cannot select the engine")
            props = bpy.context.scene.rendezvous
            for name in ("integrator", "samples", "time_limit", "max_bounces", "seed", "use_animated_seed",
                         "clamp", "threads"):
                check(hasattr(props, name), "scene.rendezvous.%s missing" % name)
            panels = {p.__name__ for p in bpy.types.Panel.__subclasses__()
                      if not p.__name__.startswith("RENDEZVOUS_")
                      and "RENDEZVOUS" in getattr(p, "COMPAT_ENGINES", ())}
            for want in ("CYCLES_PT_context_material", "CYCLES_MATERIAL_PT_surface", "CYCLES_LIGHT_PT_light",
                         "CYCLES_WORLD_PT_surface"):
                check(want in panels, "%s does not list RENDEZVOUS" % want)
            check("CYCLES_RENDER_PT_sampling" not in panels, "Cycles' sampling panel must stay Cycles'")
            check_panel_polls()
            bpy.context.scene.render.engine = "RENDEZVOUS"
            check_render_properties_layout()
            print("round %d ok: %d compatible panels" % (i, len(panels)))
        addon_utils.disable("rendezvous", default_set=True, handle_error=None)
        s = registered_state()
        check(all_off(s), "state after final disable: %r" % (s,))
        base = sys.modules["cycles.ui"].CyclesButtonsPanel
        check(base.COMPAT_ENGINES == {"CYCLES"}, "Cycles' base panel set after disable: %r" % base.COMPAT_ENGINES)
        check(all(panel_polls("CYCLES").values()), "Cycles' panels after disable")
        check(not any(panel_polls("BLENDER_EEVEE")[n] for n in HIDDEN_PANELS),
              "Cycles' render panels under Eevee after disable")
        print("REGISTER TEST PASSED")
    except Exception:
        traceback.print_exc()
        sys.exit(1)


main()
