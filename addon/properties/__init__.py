"""scene.rendezvous: the render settings (shown in Render properties)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

INTEGRATOR_ITEMS = [
    ("PATH", "Path Tracing", "Unidirectional path tracing with next-event estimation"),
    ("BDPT", "Bidirectional", "Bidirectional path tracing (caustics, hard-to-reach lights)"),
    ("PSSMLT", "Metropolis (Kelemen)", "Metropolis light transport over bidirectional paths (Kelemen et al.): "
                                       "explores the neighbourhood of the paths that carry light (light through "
                                       "a gap, caustics seen indirectly); samples are mutations per pixel"),
    ("MMLT", "Metropolis (Multiplexed)", "Multiplexed Metropolis light transport (Hachisuka et al.): each "
                                         "mutation follows one bidirectional strategy, so mutations are cheaper; "
                                         "samples are mutations per pixel"),
]

MIS_ITEMS = [
    ("POWER", "Power Heuristic", "Veach's power heuristic over every strategy (the default)"),
    ("BALANCE", "Balance Heuristic", "Veach's balance heuristic"),
    ("LAFORTUNE_WILLEMS", "Lafortune-Willems", "The original BDPT paper's weights, by the specularity of "
                                               "the surfaces on the camera path (for comparison)"),
]


class RendezvousRenderSettings(bpy.types.PropertyGroup):
    integrator: EnumProperty(name="Integrator", items=INTEGRATOR_ITEMS, default="PATH",
                             description="Light transport algorithm")
    bdpt_mis: EnumProperty(name="Weights", items=MIS_ITEMS, default="POWER",
                           description="How bidirectional path tracing weights the ways it finds a path")
    mlt_large_step: FloatProperty(name="Large Steps", default=0.3, min=0.0, max=1.0, subtype="FACTOR",
                                  description="Metropolis: probability that a mutation draws a whole new path "
                                              "instead of moving the current one a little")
    mlt_bootstrap: IntProperty(name="Bootstrap Samples", default=1, min=1, max=4096,
                               description="Metropolis: independent samples per pixel that estimate the image's "
                                           "brightness and pick the chains' starting paths")
    mlt_chains: IntProperty(name="Chains", default=256, min=1, max=1048576,
                            description="Metropolis: number of Markov chains (the image depends on it, not on "
                                        "the thread count)")
    mlt_step_size: FloatProperty(name="Step Size", default=0.01, min=0.0001, max=1.0, precision=4,
                                 description="Metropolis: size of a small mutation in primary sample space")
    samples: IntProperty(name="Samples", default=128, min=1, soft_max=4096,
                         description="Samples per pixel; the render stops when they are done")
    sample_offset: IntProperty(name="Sample Offset", default=0, min=0, max=2**31 - 1,
                               description="Render samples [offset, offset + samples) of the sequence, as "
                                           "Cycles' sample offset: parts of one render on a farm, merged with "
                                           "`rendezvous merge` (Metropolis: the part's own chains)")
    part_output: StringProperty(name="Part File", default="", subtype="FILE_PATH",
                                description="After a final render, also write it as a render part (EXR with the "
                                            "sums `rendezvous merge` adds; # = frame number). Empty: off")
    time_limit: FloatProperty(name="Time Limit", default=0.0, min=0.0, subtype="TIME_ABSOLUTE", unit="TIME_ABSOLUTE",
                              description="Stop after this many seconds (0 = off); whichever halt comes first")
    max_bounces: IntProperty(name="Max Bounces", default=12, min=0, max=1024,
                             description="Maximum number of bounces of a path")
    seed: IntProperty(name="Seed", default=0, min=0, description="Seed of the random sequences")
    use_animated_seed: BoolProperty(name="Animated Seed", default=False,
                                    description="Add the frame number to the seed (noise changes per frame)")
    clamp: FloatProperty(name="Clamp", default=0.0, min=0.0,
                         description="Cap on the luminance of a sample, reduces fireflies (0 = off)")
    viewport_integrator: EnumProperty(name="Viewport Integrator", items=INTEGRATOR_ITEMS, default="PATH",
                                      description="Light transport algorithm of the 3D view's Rendered mode")
    viewport_samples: IntProperty(name="Viewport Samples", default=64, min=1, soft_max=4096,
                                  description="Samples per pixel in the viewport; rendering (and CPU use) "
                                              "stops when they are reached")
    viewport_pause: BoolProperty(name="Pause Viewport", default=False,
                                 description="Pause the viewport render (the last image stays)")
    threads: IntProperty(name="Threads", default=0, min=0, max=1024,
                         description="Render threads (0 = all cores)")


classes = (RendezvousRenderSettings,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.rendezvous = PointerProperty(type=RendezvousRenderSettings, name="Rendezvous")


def unregister():
    if hasattr(bpy.types.Scene, "rendezvous"):
        del bpy.types.Scene.rendezvous
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
