#!/usr/bin/env python3
"""Sums the JUnit XML files catkin writes under build/test_results and prints one line per test file
and the totals as `N passed, N failed` (the line CI counts). A rostest whose test node never reported (a
crash or a time-out) also gets rostest's own message, the end of the launch's output and the end of each
dead process's log, just above the totals, where a CI log's tail shows them. Exit status 1 when anything failed or no test ran at all."""
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET


def count(path):
    passed = failed = skipped = 0
    failures = []
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as error:
        return 0, 1, 0, ["unreadable result file: %s" % error]
    for case in root.iter("testcase"):
        name = "%s.%s" % (case.get("classname", ""), case.get("name", ""))
        if case.find("failure") is not None or case.find("error") is not None:
            failed += 1
            failures.append(name)
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            skipped += 1
        else:
            passed += 1
    # A test binary that died writes a file with failures but possibly no testcase entries.
    if passed + failed + skipped == 0:
        errors = int(root.get("errors", "0") or 0) + int(root.get("failures", "0") or 0)
        if errors:
            failed += errors
            failures.append(os.path.basename(path))
    return passed, failed, skipped, failures


# Lines of a failed launch's output shown above the totals.
TAIL_LINES = 25


def launch_details(path):
    """rostest's message for a test node that never reported, the end of the launch's output and the end of
    each dead process's log."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        return []
    lines = []
    for case in root.iter("testcase"):
        for problem in list(case.findall("failure")) + list(case.findall("error")):
            text = (problem.get("message") or "") + " " + (problem.text or "")
            lines += ["  " + line for line in text.strip().splitlines()[-5:]]
    out = root.find("system-out")
    if out is not None and out.text:
        text = re.sub(r"(&#x001B;|\x1b)\[[0-9;]*m", "", out.text.replace("<![CDATA[", "").replace("]]>", ""))
        lines += ["  | " + line for line in text.rstrip().splitlines()[-TAIL_LINES:]]
        # The output of a process that died or was killed, from its log file.
        for pattern in sorted(set(re.findall(r"log file: (\S+)", text)))[-2:]:
            for log in sorted(glob.glob(pattern))[-2:]:
                with open(log, errors="replace") as f:
                    lines += ["  %s:" % log] + ["  > " + line for line in f.read().rstrip().splitlines()[-TAIL_LINES:]]
    return lines


def main():
    results = sys.argv[1]
    total_passed = total_failed = total_skipped = 0
    details = []
    for path in sorted(glob.glob(os.path.join(results, "**", "*.xml"), recursive=True)):
        passed, failed, skipped, failures = count(path)
        if os.path.basename(path).startswith("rostest-"):
            # rostest's own file repeats, as one case, the test cases reported in rosunit-*.xml; it
            # only adds news when the test node never reported (a crash or a time-out).
            passed = 0
            if failed:
                details += ["%s:" % os.path.basename(path)] + launch_details(path)
        total_passed += passed
        total_failed += failed
        total_skipped += skipped
        label = os.path.relpath(path, results)
        print("%-70s %4d passed %4d failed" % (label, passed, failed))
        for name in failures:
            print("    FAILED: %s" % name)
    for detail in details:
        print(detail)
    line = "%d passed, %d failed" % (total_passed, total_failed)
    if total_skipped:
        line += ", %d skipped" % total_skipped
    print(line)
    return 1 if total_failed or total_passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
