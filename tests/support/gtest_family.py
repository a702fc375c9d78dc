"""A GoogleTest executable run as one process (or one per suite), each test's verdict a ctest test
of its own.

Every process of a test executable loads OpenImageIO's 260 shared libraries first (Debian's
build links every image format it knows): about 0.3 s of CPU before main(). The unit tests
took 46 s of test time as 149 processes and 5 s as one (2026-12-01). So the unit and
statistical executables run once (`unit_tests`, `stat_tests`) and the render executables once
per suite (`render_tests/MltVsBdpt`, ...; tests/CMakeLists.txt), writing GoogleTest's JSON
report and their output, and each test `Suite.Name` reads its verdict from the report and prints
its own lines of the output (a ctest fixture: `ctest -R Camera.SensorFit` runs its executable or
suite first).

    python3 gtest_family.py run EXE REPORT [FILTER]   the executable (its tests matching FILTER);
                                                      exit 0 once the report is written (the
                                                      failures are the tests'); REPORT.log its output
    python3 gtest_family.py show REPORT TEST          one test's lines and verdict (exit 1 if it
                                                      failed or is missing from the report)
"""

import json
import os
import shutil
import subprocess
import sys


def run(exe, report, test_filter=None):
    for stale in (report, report + ".log"):  # a stale report must not stand in for a run that stopped
        if os.path.exists(stale):
            os.remove(stale)
    os.makedirs(os.path.dirname(report), exist_ok=True)
    cmd = [exe, "--gtest_output=json:" + report] + (["--gtest_filter=" + test_filter] if test_filter else [])
    if shutil.which("stdbuf"):  # stdout by lines, so a test's messages on stderr land among its lines
        cmd = ["stdbuf", "-oL"] + cmd
    with open(report + ".log", "w") as log:
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace")
        for line in proc.stdout:
            sys.stdout.write(line)
            log.write(line)
        code = proc.wait()
    if not os.path.exists(report):
        print("%s stopped (exit %d) before writing its report: its tests have no verdict" % (exe, code))
        return 1
    return 0


def lines_of(report, test):
    """The test's part of the executable's output: from its [ RUN ] line to its verdict line."""
    try:
        with open(report + ".log", errors="replace") as f:
            text = f.read().splitlines()
    except OSError:
        return []
    out, inside = [], False
    for line in text:
        if line.startswith("[ RUN      ] ") and line[13:].strip() == test:
            inside = True
        if inside:
            out.append(line)
            if (line.startswith("[       OK ] ") or line.startswith("[  FAILED  ] ")) and line[13:].split(" (")[0] == test:
                break
    return out


def show(report, test):
    suite, name = test.split(".", 1)
    if not os.path.exists(report):
        print("%s: no report %s (the executable did not finish: see its own test)" % (test, report))
        return 1
    with open(report) as f:
        data = json.load(f)
    for s in data["testsuites"]:
        if s["name"] != suite:
            continue
        for t in s["testsuite"]:
            if t["name"] != name:
                continue
            failures = [f.get("failure", "") for f in t.get("failures", [])]
            print("\n".join(lines_of(report, test)))
            print("%s: %s, %s" % (test, t["result"].lower(), t["time"]))
            if failures:
                print("\n".join(failures))
                return 1
            return 0
    print("%s: not in %s" % (test, report))
    return 1


if __name__ == "__main__":
    if sys.argv[1] == "run":
        sys.exit(run(sys.argv[2], sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else None))
    sys.exit(show(sys.argv[2], sys.argv[3]))
