#!/usr/bin/env python3
"""Checks the demo as a user runs it: `scripts/demo` in a tree without ../shared/data (the simulator's
city instead of KITTI; without RViz, at 10x) must exit 0 with every loop true; and `scripts/demo --bag
FILE --stack STACK` on the simulated bags shaped like each stack's output (the build's stack_bags/STACK.bag): scripts/demo_bag, the part after the build, plays each
through that stack's launch file and the backend on the bag's clock without RViz; it must exit 0 and
print the keyframes it selected, loops that the bag's ground truth confirms, and the corrected map's
files, which must be there. A bag named with the wrong stack is refused before anything starts, with the
missing topic and the bag's topics listed.

Writes a JUnit file (--xunit); exits 1 when a check fails. --case runs one case (the build runs each case
as a test of its own, so that they run side by side).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from check_report import report  # noqa: E402

ROOT = os.path.realpath(os.path.join(HERE, "..", ".."))
STACKS = ["aloam", "lego_loam", "lio_sam", "fast_lio", "sc_aloam", "hdl_graph_slam"]


def run(bag, stack, out, *extra, timeout=300):
    done = subprocess.run(["bash", os.path.join(ROOT, "scripts", "demo_bag"), bag, stack, out, "--no-rviz"] + list(extra),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=timeout)
    return done.returncode, done.stdout


def case_stack(bags, stack, rate):
    with tempfile.TemporaryDirectory() as out:
        status, text = run(os.path.join(bags, stack + ".bag"), stack, out, "--rate", str(rate))
        errors = []
        tail = "\n".join(text.splitlines()[-25:])
        if status != 0:
            errors.append("exit status %d:\n%s" % (status, tail))
        m = re.search(r"^(\d+) keyframes selected, (\d+) loops published \((\d+) verified\)", text, re.M)
        if not m:
            return errors + ["no summary line:\n" + tail]
        keyframes, loops = int(m.group(1)), int(m.group(2))
        if keyframes < 50:
            errors.append("%d keyframes selected from a 400 m drive" % keyframes)
        if loops < 5:
            errors.append("%d loops published" % loops)
        truth = re.search(r"against the bag's ground truth: (\d+) of (\d+) loops", text)
        if not truth or truth.group(1) != truth.group(2):
            errors.append("loops not confirmed by the ground truth: %s" % (truth.group(0) if truth else "no line"))
        if not os.path.isfile(os.path.join(out, "map", "map.pcd")):
            errors.append("no corrected map in OUT/map")
        if "map.pcd" not in text:
            errors.append("the map's files are not listed")
        return errors


def case_wrong_stack(bags):
    with tempfile.TemporaryDirectory() as out:
        status, text = run(os.path.join(bags, "aloam.bag"), "lio_sam", out)
    errors = []
    if status != 2:
        errors.append("exit status %d, not 2" % status)
    if "the bag has no /lio_sam/mapping/cloud_registered_raw" not in text:
        errors.append("the missing topic is not named:\n" + text)
    if "/velodyne_cloud_registered" not in text:
        errors.append("the bag's own topics are not listed:\n" + text)
    return errors


def case_demo_without_data():
    with tempfile.TemporaryDirectory() as empty:
        env = dict(os.environ, SCL_SHARED_DATA=empty)
        done = subprocess.run(["bash", os.path.join(ROOT, "scripts", "demo"), "--no-rviz", "--rate", "10"], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=600)
    text = done.stdout
    errors = []
    if done.returncode != 0:
        errors.append("exit status %d:\n%s" % (done.returncode, "\n".join(text.splitlines()[-25:])))
    if "the demo drives the simulator's own city" not in text:
        errors.append("no word of the city drive in place of KITTI")
    m = re.search(r"^(\d+) loops published, (\d+) true .*?, (\d+) false", text, re.M)
    if not m:
        errors.append("no loop summary")
    elif int(m.group(1)) < 100 or m.group(3) != "0":
        errors.append(m.group(0))
    if "met)" not in text:
        errors.append("the corrected path does not meet the demo's aim: %s" % re.findall(r"the loops take.*", text))
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bags", required=True, help="the folder of the simulated stack bags (STACK.bag)")
    parser.add_argument("--rate", type=float, default=4.0, help="replay speed")
    parser.add_argument("--case", action="append", choices=["city", "wrong_stack"] + STACKS,
                        help="run only this case (repeatable; default: all), so that the cases can run side by side")
    parser.add_argument("--xunit", help="JUnit result file to write")
    args = parser.parse_args()
    cases = [("city", "demo_without_shared_data_drives_the_city", case_demo_without_data),
             ("wrong_stack", "wrong_stack_refused_with_the_bags_topics", lambda: case_wrong_stack(args.bags))]
    cases += [(s, "%s_bag_played_and_summarised" % s, lambda s=s: case_stack(args.bags, s, args.rate)) for s in STACKS]
    chosen = [(name, check()) for key, name, check in cases if not args.case or key in args.case]
    return report("demo", chosen, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
