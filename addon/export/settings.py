"""Render settings JSON for rdv_session_create, and the output rectangle."""

import hashlib
import math
import os

INTEGRATORS = {"PATH": "path", "BDPT": "bdpt", "PSSMLT": "pssmlt", "MMLT": "mmlt", "MLT": "mlt", "AUTO": "auto"}
METROPOLIS = ("pssmlt", "mmlt", "mlt")
INTEGRATOR_LABELS = {"path": "Path Tracing", "bdpt": "Bidirectional", "pssmlt": "Metropolis (Kelemen)",
                     "mmlt": "Metropolis (Multiplexed)", "mlt": "Metropolis (Path Space)",
                     "auto": "Automatic"}


def auto_choice_text(stats):
    """Integrator Automatic's pick and its evidence (each pilot's estimated error and speed),
    from the session stats; "" when the stats hold no choice."""
    choice = stats.get("auto")
    if not choice:
        return ""
    if choice.get("integrator") is None:
        return "Automatic: pilots running"
    pilots = ", ".join("%s %.2g/s (relMSE %.2g, %d spp)" % (INTEGRATOR_LABELS.get(p["integrator"], p["integrator"]),
                                                            p["efficiency"], p["rel_mse"], p["spp"])
                       for p in choice["pilots"])
    text = "Automatic chose %s after %.1f s of pilots; efficiency 1/(error x time): %s" % (
        INTEGRATOR_LABELS.get(choice["integrator"], choice["integrator"]), choice["pilot_seconds"], pilots)
    if choice.get("time_limit_extended"):
        text += " (the pilots overran: the time limit grew to give the pick 5% of it)"
    for why in choice.get("left_out", []):  # "mlt: the reason" (a candidate the scene rules out)
        name, _, reason = why.partition(": ")
        text += "; %s left out: %s" % (INTEGRATOR_LABELS.get(name, name), reason)
    return text


def metropolis_settings(props):
    """The Metropolis integrators' settings of scene.rendezvous (final render and viewport)."""
    s = {"mlt_large_step": float(props.mlt_large_step), "mlt_bootstrap": int(props.mlt_bootstrap),
         "mlt_chains": int(props.mlt_chains), "mlt_step_size": float(props.mlt_step_size),
         # Path space (mlt) only: its mutations' weights (the other integrators ignore them).
         "mlt_mutations": {name: float(getattr(props, "mlt_mutation_" + name, 1.0))
                           for name in ("bidirectional", "lens", "propagation", "scattering", "caustic",
                                        "multi_chain", "lens_subpath")},
         "mlt_keep_distances": float(getattr(props, "mlt_keep_distances", 0.5)),
         "mlt_equiangular": float(getattr(props, "mlt_equiangular", 0.0)),
         "mlt_direct_samples": int(getattr(props, "mlt_direct_samples", 0))}
    target = getattr(props, "mlt_target", "DEFAULT")
    if target != "DEFAULT":  # else each integrator's own (the engine's default)
        s["mlt_target"] = target.lower()
    return s


MIS = {"POWER": "power", "BALANCE": "balance", "LAFORTUNE_WILLEMS": "lafortune_willems"}
DEFAULT_SAMPLES = 128


def resolution(render):
    pct = render.resolution_percentage / 100.0
    return max(1, int(render.resolution_x * pct)), max(1, int(render.resolution_y * pct))


def border_rect(render, width, height):
    """(x, y_top, w, h) in pixels of the full image, rows counted from the top, or None.

    Blender's border is given from the bottom-left in fractions; like Cycles, truncate."""
    if not render.use_border:
        return None
    x0 = int(render.border_min_x * width)
    x1 = int(render.border_max_x * width)
    y0 = int(render.border_min_y * height)  # from the bottom
    y1 = int(render.border_max_y * height)
    x0, x1 = max(0, min(x0, width)), max(0, min(x1, width))
    y0, y1 = max(0, min(y0, height)), max(0, min(y1, height))
    if x1 <= x0 or y1 <= y0:
        return None
    if x0 == 0 and y0 == 0 and x1 == width and y1 == height:
        return None
    return (x0, height - y1, x1 - x0, y1 - y0)


class SettingsError(ValueError):
    """A render setting the engine cannot take, named in the message."""


# Cycles' Light Paths (Render Properties > Light Paths), shared with Cycles the way Cycles
# keeps them: scene.cycles while the Cycles add-on is enabled, else our mirror properties
# on scene.rendezvous (same names, same defaults). Bounces count as Cycles counts them
# (0 = direct light only): the engine's max_bounces is scattering vertices, one more.
BOUNCE_KINDS = ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces")
ENGINE_MAX_BOUNCES = 1024


# Cycles' defaults, which scene.rendezvous mirrors (for a settings owner without a field).
LIGHT_PATH_DEFAULTS = {"max_bounces": 12, "diffuse_bounces": 4, "glossy_bounces": 4, "transmission_bounces": 12,
                       "volume_bounces": 0, "transparent_max_bounces": 8, "caustics_reflective": True, "caustics_refractive": True,
                       "sample_clamp_direct": 0.0, "sample_clamp_indirect": 10.0, "blur_glossy": 1.0}


def light_path_source(scene, props=None):
    """The settings' owner: scene.cycles (Cycles enabled), else props (scene.rendezvous)."""
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, "diffuse_bounces"):
        return cycles
    return props if props is not None else scene.rendezvous


def light_path_settings(scene, props=None):
    """The engine's light-path keys: max_bounces and transparent_max_bounces always; a per-kind limit only where it can
    bind (below the total), clamps and caustics only where they differ from off / on, so a
    scene that uses none of them renders exactly as before."""
    src = light_path_source(scene, props)

    def get(key):
        return getattr(src, key, LIGHT_PATH_DEFAULTS[key])

    total = int(get("max_bounces"))
    s = {"max_bounces": min(total + 1, ENGINE_MAX_BOUNCES)}
    for key in BOUNCE_KINDS:
        n = int(get(key))
        if n < total:
            s[key] = max(n, 0)
    # Transparent passes are not bounces (the total does not bound them): always Cycles'.
    s["transparent_max_bounces"] = min(max(int(get("transparent_max_bounces")), 0), ENGINE_MAX_BOUNCES)
    if not get("caustics_reflective"):
        s["caustics_reflective"] = False
    if not get("caustics_refractive"):
        s["caustics_refractive"] = False
    for key in ("sample_clamp_direct", "sample_clamp_indirect"):
        v = float(get(key))
        if v > 0:
            s[key.replace("sample_", "")] = v
    blur = float(get("blur_glossy"))  # Filter Glossy: every integrator (README)
    if blur > 0:
        s["filter_glossy"] = blur
    return s


# The Light Paths keys path-space MLT does not take: a clamp caps one sample's estimate,
# which a path-space chain does not have (its f is a function of the path alone).
MLT_UNSUPPORTED_LIGHT_PATHS = ("clamp_direct", "clamp_indirect")


def light_paths_for(integrator, light_paths, warn=print):
    """light_paths (light_path_settings) as `integrator` takes them. Filter Glossy: every
    integrator applies it (one image for all). Metropolis (Path Space) takes the per-kind
    bounces, the caustics switches and Filter Glossy but no clamps (a default Blender scene
    has Clamp Indirect 10, which the engine would refuse for it): they are left out, with one
    warning naming them."""
    if integrator != "mlt":
        return light_paths
    dropped = [k for k in MLT_UNSUPPORTED_LIGHT_PATHS if k in light_paths]
    if dropped:
        warn("Metropolis (Path Space) ignores the Light Paths clamps (%s): a clamp caps one sample's estimate, "
             "which a path-space chain does not have" % ", ".join(dropped))
    return {k: v for k, v in light_paths.items() if k not in dropped}


def film_settings(scene, props=None):
    """Film > Transparent (scene.render.film_transparent) and Transparent Glass (Cycles'
    scene.cycles, else our mirror on props): keys only when the film is transparent."""
    if not getattr(scene.render, "film_transparent", False):
        return {}
    src = light_path_source(scene, props)
    s = {"film_transparent": True}
    if getattr(src, "film_transparent_glass", False):
        s["film_transparent_glass"] = True
        s["film_transparent_roughness"] = min(max(float(getattr(src, "film_transparent_roughness", 0.1)), 0.0), 1.0)
    return s


def session_settings(scene, props, frame=None, warn=print):
    """props: scene.rendezvous (or a stand-in with the same fields)."""
    render = scene.render
    width, height = resolution(render)
    samples = int(props.samples)
    time_limit = float(props.time_limit)
    noise_target = float(getattr(props, "noise_target", 0.0))
    if not math.isfinite(noise_target) or noise_target < 0.0:
        raise SettingsError("Noise Target (scene.rendezvous.noise_target) must be a finite number >= 0, got %r"
                            % noise_target)
    if samples <= 0 and time_limit <= 0.0 and noise_target <= 0.0:
        samples = DEFAULT_SAMPLES  # a render always halts
    seed = int(props.seed)
    if props.use_animated_seed:
        seed += int(scene.frame_current if frame is None else frame)
    s = {
        "width": width,
        "height": height,
        "integrator": INTEGRATORS.get(props.integrator, "path"),
        "seed": seed & 0x7FFFFFFF,
        "threads": int(props.threads),
        "clamp": float(props.clamp),
    }
    s.update(light_paths_for(s["integrator"], light_path_settings(scene, props), warn))
    s.update(film_settings(scene, props))
    # Blender's pixel filter width (Film > Pixel Filter, Cycles' Blackman-Harris).
    filter_size = getattr(render, "filter_size", None)
    if filter_size is not None and abs(float(filter_size) - 1.5) > 1e-6:
        s["filter_width"] = min(max(float(filter_size), 0.01), 10.0)
    if s["integrator"] == "auto" and time_limit <= 0.0:
        raise SettingsError("Integrator Automatic splits a time budget between pilots and the render: set "
                            "Sampling > Render > Time Limit")
    if s["integrator"] in ("bdpt", "auto"):  # auto: the settings of whichever it picks
        s["mis"] = MIS.get(getattr(props, "bdpt_mis", "POWER"), "power")
    if s["integrator"] in METROPOLIS + ("auto",):
        s.update(metropolis_settings(props))
    if samples > 0:
        s["samples"] = samples
    if int(getattr(props, "sample_offset", 0)) > 0:
        s["sample_offset"] = int(props.sample_offset)
    if time_limit > 0.0:
        s["time_limit"] = time_limit
    if noise_target > 0.0:
        s["noise_target"] = noise_target
    if getattr(props, "use_pass_noise", False):
        s["noise_pass"] = True
    if getattr(props, "use_adaptive_sampling", False) and s["integrator"] in ("path", "bdpt"):
        s["adaptive_sampling"] = True
        s["adaptive_threshold"] = float(props.adaptive_threshold)
        s["adaptive_min_samples"] = int(props.adaptive_min_samples)
    rect = border_rect(render, width, height)
    if rect is not None:
        x, y, w, h = rect
        s["border"] = [x, y, x + w, y + h]
    if abs(render.pixel_aspect_x - render.pixel_aspect_y) > 1e-6:
        warn("Render: non-square pixel aspect not supported yet, using square pixels")
    return s


def scene_hash(blend_path, scene_name, frame):
    """What render parts of this scene and frame share (docs/farm.md): the saved .blend
    file's SHA-256 (so every farm task loading the same file agrees), the scene and the
    frame. An unsaved file is identified by its scene name alone."""
    h = hashlib.sha256()
    if blend_path and os.path.isfile(blend_path):
        with open(blend_path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        file_id = h.hexdigest()[:16]
    else:
        file_id = "unsaved"
    return "blend:%s:%s:frame%d" % (file_id, scene_name, frame)


def part_output_path(path, frame):
    """The part file of a frame: each run of '#' becomes the zero-padded frame number,
    as in Blender's output paths."""
    out, i = [], 0
    while i < len(path):
        if path[i] == "#":
            j = i
            while j < len(path) and path[j] == "#":
                j += 1
            out.append("%0*d" % (j - i, frame))
            i = j
        else:
            out.append(path[i])
            i += 1
    return "".join(out)
