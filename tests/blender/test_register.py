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
            print("round %d ok: %d compatible panels" % (i, len(panels)))
        addon_utils.disable("rendezvous", default_set=True, handle_error=None)
        s = registered_state()
        check(all_off(s), "state after final disable: %r" % (s,))
        print("REGISTER TEST PASSED")
    except Exception:
        traceback.print_exc()
        sys.exit(1)


main()
