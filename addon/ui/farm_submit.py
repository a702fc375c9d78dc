"""RENDEZVOUS_OT_farm_submit: submit the saved .blend to Slurm as sample-range tasks plus a merge
(addon/farm/submit.py, docs/farm.md)."""

import os
import shutil

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty

from ..farm import submit


class RENDEZVOUS_OT_farm_submit(bpy.types.Operator):
    """Render the saved .blend on a Slurm cluster: each frame split into sample ranges (one array
    task each, headless Blender), merged into final_FRAME.exr when the tasks are done"""

    bl_idname = "rendezvous.farm_submit"
    bl_label = "Submit to Slurm"
    bl_options = {"REGISTER"}

    split: IntProperty(name="Tasks per Frame", default=8, min=1, max=100000,
                       description="Sample ranges each frame is split into (one Slurm array task each)")
    samples: IntProperty(name="Samples per Task", default=0, min=0,
                         description="Samples each task renders (0: the scene's samples / tasks per frame)")
    frames: StringProperty(name="Frames", default="",
                           description="e.g. 1-24 or 1,5,9-12 (empty: the scene's frame range)")
    out_dir: StringProperty(name="Output Folder", subtype="DIR_PATH", default="//farm/",
                            description="A folder every node sees: scripts, parts, logs and the merged frames")
    renderer: StringProperty(name="Renderer", subtype="FILE_PATH", default="",
                             description="Rendezvous' command-line renderer on the nodes (merges the parts); "
                                         "empty: `rendezvous` on PATH")
    cpus: IntProperty(name="CPUs per Task", default=1, min=1, description="sbatch --cpus-per-task")
    sbatch_args: StringProperty(name="sbatch Options", default="", description="e.g. --partition render")
    dry_run: BoolProperty(name="Dry Run", default=False, description="Write the scripts, do not submit")

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        scene = context.scene
        if not bpy.data.is_saved:
            self.report({"ERROR"}, "Rendezvous farm: save the .blend first (the nodes render the saved file)")
            return {"CANCELLED"}
        if bpy.data.is_dirty:
            self.report({"WARNING"}, "Rendezvous farm: unsaved changes are not in the farm render")
        samples = self.samples or max(1, scene.rendezvous.samples // self.split)
        frames = self.frames or "%d-%d" % (scene.frame_start, scene.frame_end)
        renderer = bpy.path.abspath(self.renderer) if self.renderer else (shutil.which("rendezvous") or "rendezvous")
        argv = [bpy.data.filepath, "--scheduler", "slurm", "--split", str(self.split), "--samples", str(samples),
                "--frames", frames, "--out", bpy.path.abspath(self.out_dir), "--renderer", renderer,
                "--blender", bpy.app.binary_path, "--cpus", str(self.cpus), "--sbatch-args", self.sbatch_args]
        if self.dry_run:
            argv.append("--dry-run")
        try:
            args = submit.parse_args(argv)
            array, merge = submit.submit(args)
        except (ValueError, RuntimeError, OSError) as exc:
            self.report({"ERROR"}, "Rendezvous farm: %s" % exc)
            return {"CANCELLED"}
        self.report({"INFO"}, "Rendezvous farm: render array %s, merge %s; output %s"
                    % (array, merge, os.path.abspath(args.out)))
        return {"FINISHED"}


def register():
    bpy.utils.register_class(RENDEZVOUS_OT_farm_submit)


def unregister():
    bpy.utils.unregister_class(RENDEZVOUS_OT_farm_submit)
