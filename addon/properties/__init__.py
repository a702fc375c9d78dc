"""scene.rendezvous: the render settings (shown in Render properties)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

INTEGRATOR_ITEMS = [
    ("PATH", "Path Tracing", "Unidirectional path tracing with next-event estimation: the fastest samples; "
                              "noisy where light arrives only through glass, mirrors or small gaps"),
    ("BDPT", "Bidirectional", "Bidirectional path tracing: each sample costs about 2-3x a path-tracing "
                             "sample, but caustics and light through gaps converge far faster"),
    ("PSSMLT", "Metropolis (Kelemen)", "Metropolis light transport over bidirectional paths (Kelemen et al.): "
                                       "explores the neighbourhood of the paths that carry light (light through "
                                       "a gap, caustics seen indirectly); samples are mutations per pixel; uneven "
                                       "noise and a slower start in easy scenes"),
    ("MMLT", "Metropolis (Multiplexed)", "Multiplexed Metropolis light transport (Hachisuka et al.): each "
                                         "mutation follows one bidirectional strategy, so mutations are cheaper; "
                                         "samples are mutations per pixel; uneven noise in easy scenes"),
    ("MLT", "Metropolis (Path Space)", "Veach's Metropolis light transport on explicit paths: the bidirectional "
                                       "mutation rebuilds part of a light-carrying path and keeps the rest; samples "
                                       "are mutations per pixel. Pinhole cameras, lamps of radius 0, area and mesh "
                                       "lights, homogeneous media; no sun, world light, grid or emissive volumes, "
                                       "and no light through perfectly specular surfaces yet"),
]

# The final render may also let short pilots choose (it has a time budget to split).
FINAL_INTEGRATOR_ITEMS = INTEGRATOR_ITEMS + [
    ("AUTO", "Automatic", "Short pilot renders of each integrator (10% of the Time Limit) measure its noise "
                          "per second; the most efficient one renders the rest. Needs a Time Limit; the choice "
                          "and its evidence appear in the status bar and the Info log"),
]

MIS_ITEMS = [
    ("POWER", "Power Heuristic", "Veach's power heuristic over every strategy (the default)"),
    ("BALANCE", "Balance Heuristic", "Veach's balance heuristic"),
    ("LAFORTUNE_WILLEMS", "Lafortune-Willems", "The original BDPT paper's weights, by the specularity of "
                                               "the surfaces on the camera path (for comparison)"),
]


def _mutation_weight(name, what):
    return FloatProperty(name=name, default=1.0, min=0.0, soft_max=10.0,
                         description="Metropolis (Path Space): weight of " + what)


class RendezvousRenderSettings(bpy.types.PropertyGroup):
    integrator: EnumProperty(name="Integrator", items=FINAL_INTEGRATOR_ITEMS, default="PATH",
                             description="Light transport algorithm of the final render: path tracing "
                                         "is the fastest per sample; bidirectional and Metropolis cost more "
                                         "per sample but find hard light (caustics, gaps) with less noise")
    bdpt_mis: EnumProperty(name="Weights", items=MIS_ITEMS, default="POWER",
                           description="How bidirectional path tracing weights the ways it finds a path (all unbiased; "
                                       "they differ in noise)")
    mlt_large_step: FloatProperty(name="Large Steps", default=0.3, min=0.0, max=1.0, subtype="FACTOR",
                                  description="Metropolis: probability that a mutation draws a whole new path "
                                              "instead of moving the current one a little: higher explores the "
                                              "image more evenly, lower follows hard paths longer")
    mlt_bootstrap: IntProperty(name="Bootstrap Samples", default=1, min=1, max=4096,
                               description="Metropolis: independent samples per pixel that estimate the image's "
                                           "brightness and pick the chains' starting paths: more costs start-up "
                                           "time, fewer risks a wrong overall brightness in a noisy scene")
    mlt_chains: IntProperty(name="Chains", default=256, min=1, max=1048576,
                            description="Metropolis: number of Markov chains (the image depends on it, not on "
                                        "the thread count): more chains spread the noise more evenly, each "
                                        "starts with a burn-in")
    mlt_step_size: FloatProperty(name="Step Size", default=0.01, min=0.0001, max=1.0, precision=4,
                                 description="Metropolis: size of a small mutation in primary sample space: larger "
                                             "moves explore faster but are rejected more often")
    mlt_mutation_bidirectional: _mutation_weight(
        "Bidirectional", "Veach's bidirectional mutation, which rebuilds a part of the path from both ends "
                         "(large steps aside)")
    mlt_mutation_lens: _mutation_weight(
        "Lens", "the lens perturbation (Veach), which moves the path's image position a little and traces its "
                "first vertex afresh: spreads the chains over the image")
    mlt_mutation_propagation: _mutation_weight(
        "Propagation", "the propagation perturbation (Pauly et al.), which moves a scattering point in a volume "
                       "along the light's direction: light through fog, shafts")
    mlt_mutation_scattering: _mutation_weight(
        "Scattering", "the scattering perturbation, which turns a scattering point in a volume a little about "
                      "the vertex the light came from")
    mlt_mutation_caustic: _mutation_weight(
        "Caustic", "the caustic perturbation (Veach), which turns the light's direction into a chain of mirrors "
                   "or smooth glass a little and retraces it to the surface or fog the camera sees: caustics")
    mlt_mutation_multi_chain: _mutation_weight(
        "Multi-Chain", "the multi-chain perturbation (Veach), which moves the image position a little and, past each "
                       "rough surface seen through mirrors or smooth glass, turns the path a little through the next "
                       "chain of them: caustics seen in a mirror or through glass")
    mlt_mutation_lens_subpath: _mutation_weight(
        "Lens Subpath", "the lens subpath mutation (Veach), which traces the path's first vertices afresh through "
                        "the chain's next pixel in a shuffled sweep of the image: every pixel gets visited")
    mlt_keep_distances: FloatProperty(
        name="Keep Distances", default=0.5, min=0.0, max=1.0, subtype="FACTOR",
        description="Metropolis (Path Space), scenes with volumes: how often the lens, caustic and multi-chain "
                    "perturbations keep a scattering point's distance along the ray they retrace (Pauly et al.), "
                    "so it moves a little with the caustic or the image position instead of jumping along the "
                    "ray: higher follows volume caustics and shafts longer, lower explores depth more")
    mlt_equiangular: FloatProperty(
        name="Toward Lamps", default=0.0, min=0.0, max=1.0, subtype="FACTOR",
        description="Metropolis (Path Space), scenes with volumes lit by point or spot lamps: how often a "
                    "distance in the volume seen from the camera side is drawn toward a lamp (equiangular "
                    "sampling) instead of by the volume's density. Fog close to a small lamp converges instead "
                    "of leaving fireflies and brightness flicker; 0 spends every draw on the fog's depth")
    mlt_direct_samples: IntProperty(
        name="Direct Samples", default=0, min=0, max=65536,
        description="Metropolis (Path Space): path-traced samples per pixel for direct light (lamps and the world "
                    "seen directly or lighting a surface or volume at one bounce), which the chains then leave "
                    "out (Veach): the chains spend every mutation on indirect light. 0: the chains take all light")
    mlt_target: EnumProperty(
        name="Target", default="DEFAULT",
        items=[("DEFAULT", "Automatic", "Even Error for Metropolis (Kelemen) and (Multiplexed), Brightness for "
                "Metropolis (Path Space), whose chains spread wider between renders with Even Error"),
               ("RELATIVE", "Even Error", "Mutations spread by relative error: regions brighter than the image's "
                "mean get no more than their share (a short pilot of independent samples maps them)"),
               ("LUMINANCE", "Brightness", "Mutations in proportion to brightness (Kelemen's, Hachisuka's and Veach's "
                "target): a small bright region takes most of them")],
        description="Metropolis: where the chains spend their mutations: Even Error suits images with small bright regions, Brightness spends nothing on the pilot")
    samples: IntProperty(name="Samples", default=128, min=1, soft_max=4096,
                         description="Samples per pixel; the render stops when they are done. Noise falls "
                                     "as 1 / sqrt(samples): 4x the samples (and time) halves it")
    sample_offset: IntProperty(name="Sample Offset", default=0, min=0, max=2**31 - 1,
                               description="Render samples [offset, offset + samples) of the sequence, as "
                                           "Cycles' sample offset: parts of one render on a farm, merged with "
                                           "`rendezvous merge` (Metropolis: the part's own chains)")
    part_output: StringProperty(name="Part File", default="", subtype="FILE_PATH",
                                description="After a final render, also write it as a render part (EXR with the "
                                            "sums `rendezvous merge` adds; # = frame number). Empty: off")
    time_limit: FloatProperty(name="Time Limit", default=0.0, min=0.0, subtype="TIME_ABSOLUTE", unit="TIME_ABSOLUTE",
                              description="Stop after this many seconds (0 = off), whichever halt comes first: a "
                                          "fixed render time, at the cost of a noise level that depends on the scene")
    noise_target: FloatProperty(name="Noise Target", default=0.0, min=0.0, soft_max=0.1, precision=4, step=0.01,
                                description="Stop once the estimated relative MSE of the image (the error measure "
                                            "of docs/trade.md: mean of (error / value)^2, 1e-3 is about 3% noise) "
                                            "falls below this (0 = off), whichever halt comes first. A render "
                                            "that estimates its noise draws its samples from two independent "
                                            "sequences (path, bidirectional): up to ~1.4x the noise of one in "
                                            "smooth regions at equal samples")
    use_adaptive_sampling: BoolProperty(name="Adaptive Sampling", default=False,
                                        description="Path tracing and bidirectional: a pixel whose estimated relative "
                                                    "error (over its 3 x 3 neighbourhood) is below the Noise "
                                                    "Threshold stops receiving samples, so the time goes where the "
                                                    "noise is (Cycles' Noise Threshold)")
    adaptive_threshold: FloatProperty(name="Noise Threshold", default=0.01, min=0.0001, max=1.0, precision=4,
                                      step=0.1, description="Relative error (standard deviation over value) at which "
                                                            "a pixel stops: 0.01 = 1% noise; lower renders cleaner "
                                                            "and longer")
    adaptive_min_samples: IntProperty(name="Min Samples", default=0, min=0, max=4096,
                                      description="Samples every pixel gets before it may stop (0 = automatic, 16): "
                                                  "more keeps rare light (caustics, small lamps) from being missed "
                                                  "by pixels that look converged")
    use_pass_noise: BoolProperty(name="Noise", default=False,
                                 description="Render pass: the estimated relative error of each pixel (the root of "
                                             "its relative MSE), from two independent half images; draws the "
                                             "samples as the Noise Target does")
    # Light Paths, mirroring Cycles' (names, defaults, meaning): used when the Cycles add-on
    # is disabled; with it enabled the settings are scene.cycles', shared with Cycles.
    max_bounces: IntProperty(name="Max Bounces", default=12, min=0, max=1024,
                             description="Total bounces of a path, as Cycles counts them (0 = direct light "
                                         "only): fewer render faster but lose indirect light (darker "
                                         "interiors, glass and mirrors go black)")
    diffuse_bounces: IntProperty(name="Diffuse Bounces", default=4, min=0, max=1024,
                                 description="Diffuse reflections a path may make before it meets a light: "
                                             "fewer are faster, indirect light between matte walls is lost")
    glossy_bounces: IntProperty(name="Glossy Bounces", default=4, min=0, max=1024,
                                description="Glossy and mirror reflections a path may make: fewer are faster, "
                                            "mirrors facing each other go black sooner")
    transmission_bounces: IntProperty(name="Transmission Bounces", default=12, min=0, max=1024,
                                      description="Passages through glass a path may make: fewer are faster, "
                                                  "thick or stacked glass turns black")
    volume_bounces: IntProperty(name="Volume Bounces", default=0, min=0, max=1024,
                                description="Scatterings in a volume a path may make (0 = single scattering): "
                                            "more give denser, brighter fog and smoke at a higher cost")
    transparent_max_bounces: IntProperty(name="Transparent Max Bounces", default=8, min=0, max=1024,
                                         description="Transparent surfaces (alpha, Transparent BSDF) a path may "
                                                     "pass straight through: more are slower, fewer turn what "
                                                     "lies behind stacked leaves or cards black")
    caustics_reflective: BoolProperty(name="Reflective Caustics", default=True,
                                      description="Light reflected by glossy surfaces onto diffuse ones: off "
                                                  "removes that noise, and the light (biased)")
    caustics_refractive: BoolProperty(name="Refractive Caustics", default=True,
                                      description="Light refracted by glass onto diffuse surfaces: off removes "
                                                  "that noise, and the light (shadows of glass stay dark)")
    blur_glossy: FloatProperty(name="Filter Glossy", default=1.0, min=0.0, soft_max=10.0,
                               description="Roughens glossy and glass surfaces seen after unlikely bounces "
                                           "(0 = off): less noise in caustics and glossy reflections of "
                                           "diffuse light, which blur (biased)")
    sample_clamp_direct: FloatProperty(name="Clamp Direct", default=0.0, min=0.0,
                                       description="Cap on the brightness of light arriving after at most one "
                                                   "bounce (0 = off): fewer fireflies, darker highlights")
    sample_clamp_indirect: FloatProperty(name="Clamp Indirect", default=10.0, min=0.0,
                                         description="Cap on the brightness of light arriving after more "
                                                     "bounces (0 = off): fewer fireflies, less indirect light")
    # Cycles' Film > Transparent Glass (scene.cycles while its add-on is enabled); the
    # Transparent switch itself is Blender's scene.render.film_transparent.
    film_transparent_glass: BoolProperty(name="Transparent Glass", default=False,
                                         description="With Film > Transparent: the world seen through smooth "
                                                     "glass is transparent too (for compositing over a plate)")
    film_transparent_roughness: FloatProperty(name="Roughness Threshold", default=0.1, min=0.0, max=1.0,
                                              description="With Transparent Glass: refractions up to this "
                                                          "roughness keep the world behind them transparent")
    seed: IntProperty(name="Seed", default=0, min=0, description="Seed of the random sequences: another seed gives another "
                                                              "noise pattern of the same image")
    use_animated_seed: BoolProperty(name="Animated Seed", default=False,
                                    description="Add the frame number to the seed: the noise changes per frame (a "
                                                "moving grain instead of a fixed pattern in animations)")
    clamp: FloatProperty(name="Clamp", default=0.0, min=0.0,
                         description="Cap on the luminance of a sample (0 = off): removes fireflies at the cost "
                                     "of energy (highlights and caustics get darker, the image is biased)")
    viewport_integrator: EnumProperty(name="Viewport Integrator", items=INTEGRATOR_ITEMS, default="PATH",
                                      description="Light transport algorithm of the 3D view's Rendered mode (path "
                                                  "tracing gives the quickest first image)")
    viewport_samples: IntProperty(name="Viewport Samples", default=64, min=1, soft_max=4096,
                                  description="Samples per pixel in the viewport; rendering (and CPU use) "
                                              "stops when they are reached: more samples, less noise, longer CPU use")
    viewport_pause: BoolProperty(name="Pause Viewport", default=False,
                                 description="Pause the viewport render (the last image stays): frees the CPU "
                                             "while you edit")
    threads: IntProperty(name="Threads", default=0, min=0, max=1024,
                         description="Render threads (0 = all cores); fewer leave cores "
                                     "free for other work at the cost of render speed")


def _update_render_passes(self, context):
    """The compositor's Render Layers node shows the passes at once (as Cycles' pass toggles)."""
    view_layer = getattr(context, "view_layer", None)
    if view_layer is not None:
        view_layer.update_render_passes()


class RendezvousViewLayerSettings(bpy.types.PropertyGroup):
    """view_layer.rendezvous: passes of our own (View Layer > Passes > Rendezvous Passes)."""
    use_pass_strategies: BoolProperty(
        name="BDPT Strategies", default=False, update=_update_render_passes,
        description="Bidirectional only: one pass per strategy (s light vertices, t camera vertices) of the "
                    "paths up to Strategy Depth bounces, its MIS-weighted share of Combined "
                    "(Strategy_s1t2: next-event estimation at the first hit, Strategy_s2t1: light tracing, ...), "
                    "and Strategy_rest for longer paths; they sum to Combined. Shows which way of sampling "
                    "found each part of the image. Other integrators leave them black")
    strategy_max_depth: IntProperty(
        name="Strategy Depth", default=3, min=0, max=6, update=_update_render_passes,
        description="Bounces of the longest paths split by strategy (3: paths of 1 to 4 segments, 13 passes); "
                    "each more bounce adds its strategies' passes and their memory")


classes = (RendezvousRenderSettings, RendezvousViewLayerSettings)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.rendezvous = PointerProperty(type=RendezvousRenderSettings, name="Rendezvous")
    bpy.types.ViewLayer.rendezvous = PointerProperty(type=RendezvousViewLayerSettings, name="Rendezvous")


def unregister():
    if hasattr(bpy.types.ViewLayer, "rendezvous"):
        del bpy.types.ViewLayer.rendezvous
    if hasattr(bpy.types.Scene, "rendezvous"):
        del bpy.types.Scene.rendezvous
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
