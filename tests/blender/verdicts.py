"""A family of Blender tests in one Blender process, each member's verdict a ctest test of its own.

Starting Blender, installing the add-on and rendering the first image cost about 2 s of CPU per
process; the brightness scenes alone took 208 s as 42 processes and 110 s in one (2026-12-01).
So a family (the brightness scenes, the light paths scenes, the ray visibility variants, ...)
renders and checks every member in one process, `blender.FAMILY` (tests/blender/CMakeLists.txt,
rdv_blender_family), which writes one verdict file per member: its failures and the lines it
printed. `blender.FAMILY.MEMBER` (this file run by python3, no Blender) prints that member's
lines and fails if it failed, so a failure still names its scene, and
`ctest -R blender.brightness.hdri` runs the family first (a ctest fixture). To render one member
alone, run its script: `run_blender.py --script test_brightness.py -- hdri`.

    python3 verdicts.py DIR MEMBER
"""

import io
import json
import os
import shutil
import sys
import traceback


class _Tee(io.TextIOBase):
    """stdout that is also kept: a member's lines go to the log and into its verdict."""

    def __init__(self, out):
        self.out, self.kept = out, io.StringIO()

    def write(self, s):
        self.kept.write(s)
        return self.out.write(s)

    def flush(self):
        self.out.flush()


def run_members(members, check_member, verdict_dir=None, fresh=None):
    """check_member(member, failures) for each member, in order, each with its own failure list
    (an exception is one failure, its traceback printed), after fresh() (Blender's factory state
    back: a member sees no setting an earlier one left, as in a process of its own). Returns
    every failure, each naming its member. With verdict_dir, each member's verdict is written
    there (the directory is emptied at the start: a member not reached has no verdict, which
    its test reports)."""
    if verdict_dir:
        shutil.rmtree(verdict_dir, ignore_errors=True)
        os.makedirs(verdict_dir)
    everything = []
    for member in members:
        failures = []
        tee = _Tee(sys.stdout)
        sys.stdout = tee
        try:
            if fresh:
                fresh()
            check_member(member, failures)
        except Exception as exc:
            traceback.print_exc(file=sys.stdout)
            failures.append("%s: %s (traceback above)" % (member, exc))
        finally:
            sys.stdout = tee.out
        failures = [f if f.startswith(member) else "%s: %s" % (member, f) for f in failures]
        everything += failures
        if verdict_dir:
            with open(os.path.join(verdict_dir, member + ".json"), "w") as f:
                json.dump({"member": member, "failures": failures, "log": tee.kept.getvalue()}, f)
    return everything


def show(verdict_dir, member):
    """A member's test: its lines, then its verdict (exit 1 if it failed or has none)."""
    path = os.path.join(verdict_dir, member + ".json")
    if not os.path.exists(path):
        print("%s: no verdict in %s (the family's Blender process stopped before it: see its test's log)"
              % (member, verdict_dir))
        return 1
    with open(path) as f:
        v = json.load(f)
    sys.stdout.write(v["log"])
    if v["failures"]:
        print("%s FAILED:\n  %s" % (member, "\n  ".join(v["failures"])))
        return 1
    print("%s PASSED" % member)
    return 0


if __name__ == "__main__":
    sys.exit(show(sys.argv[1], sys.argv[2]))
