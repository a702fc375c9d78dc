"""Cycles 3.4's ray visibility -> the engine's "visibility" parameter (docs/scene-format.md).

Objects: Object > Visibility > Ray Visibility (`visible_camera`, `visible_diffuse`,
`visible_glossy`, `visible_transmission`, `visible_volume_scatter`, `visible_shadow`).
Lights are objects with the same checkboxes, except that a light's shadows are its
`light.cycles.cast_shadow` (Cycles 3.4 reads that, not the object's `visible_shadow`), and
camera rays see a lamp only with `visible_camera` on (off for new lights in 3.4).
The world: `world.cycles_visibility` (`camera`, `diffuse`, `glossy`, `transmission`,
`scatter`; its `shadow` is not used by Cycles). Only what differs from the engine's
defaults is passed, so an all-visible scene exports exactly what it did before.
"""

_OBJECT = (("camera", "visible_camera"), ("diffuse", "visible_diffuse"), ("glossy", "visible_glossy"),
           ("transmission", "visible_transmission"), ("volume_scatter", "visible_volume_scatter"))
_WORLD = (("camera", "camera"), ("diffuse", "diffuse"), ("glossy", "glossy"), ("transmission", "transmission"),
          ("volume_scatter", "scatter"))


def _hidden(owner, keys):
    return {key: False for key, prop in keys if not bool(getattr(owner, prop, True))}


KINDS = ("camera", "diffuse", "glossy", "transmission", "shadow", "volume_scatter")


def object_visibility(ob, kinds=None):
    """{"diffuse": False, ...}: the kinds of ray a mesh object is hidden from ({} if none);
    kinds: of one copy of it, seen by those kinds only (a look of its materials, materials.py)."""
    v = _hidden(ob, _OBJECT)
    if not bool(getattr(ob, "visible_shadow", True)):
        v["shadow"] = False
    if kinds is not None:
        v.update({k: False for k in KINDS if k not in kinds})
        v = {k: False for k in KINDS if k in v}  # one order, whatever the object hides
    return v


def hidden_from_all(v):
    """True when a visibility dict (object_visibility) hides every kind of ray."""
    return all(v.get(k, True) is False for k in KINDS)


def light_visibility(ob, light):
    """A light object's visibility: the engine hides lamps from the camera unless asked."""
    v = _hidden(ob, _OBJECT[1:])
    if bool(getattr(ob, "visible_camera", False)):
        v["camera"] = True
    cycles = getattr(light, "cycles", None)
    if cycles is not None and not bool(getattr(cycles, "cast_shadow", True)):
        v["shadow"] = False
    return v


def world_visibility(world):
    """The world's ray visibility ({} when seen by every kind of ray)."""
    settings = getattr(world, "cycles_visibility", None) if world is not None else None
    return _hidden(settings, _WORLD) if settings is not None else {}
