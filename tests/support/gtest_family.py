"""A GoogleTest executable run as one process, each test's verdict a ctest test of its own.

Every process of a test executable loads OpenImageIO's 260 shared libraries first (Debian's
build links every image format it knows): about 0.3 s of CPU before main(). The unit tests
took 46 s of test time as 149 processes and 5 s as one (2026-12-01). So the unit and
statistical executables run once (`unit_tests`, `stat_tests`: tests/CMakeLists.txt,
rdv_test_in_one_process), writing GoogleTest's JSON report, and each test `Suite.Name` reads
its verdict from the report (a ctest fixture: `ctest -R Camera.SensorFit` runs the executable
first).

    python3 gtest_family.py run EXE REPORT      the executable, all its tests; exit 0 once the
                                                report is written (failures are the tests')
    python3 gtest_family.py show REPORT TEST    one test's verdict (exit 1 if it failed or is
                                                missing from the report)
"""

import json
import os
import subprocess
import sys


def run(exe, report):
    if os.path.exists(report):
        os.remove(report)  # a stale report must not stand in for a run that stopped
    os.makedirs(os.path.dirname(report), exist_ok=True)
    code = subprocess.call([exe, "--gtest_output=json:" + report])
    if not os.path.exists(report):
        print("%s stopped (exit %d) before writing its report: its tests have no verdict" % (exe, code))
        return 1
    return 0


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
            print("%s: %s, %s (its output is in the executable's test's log)" % (test, t["result"].lower(), t["time"]))
            if failures:
                print("\n".join(failures))
                return 1
            return 0
    print("%s: not in %s" % (test, report))
    return 1


if __name__ == "__main__":
    if sys.argv[1] == "run":
        sys.exit(run(sys.argv[2], sys.argv[3]))
    sys.exit(show(sys.argv[2], sys.argv[3]))
