#!/usr/bin/env python3
"""Checks scripts/measure/peers.py, which measures other loop-closure programs beside this package for the
results page: the peers file is read strictly, the placeholders reach the command quoted, the CPU of a
whole process tree is counted, a failing or hanging program is reported as failed and run no more, its
output folder is removed, and the table's ratio is this package's median over the peer's.

Writes a JUnit file (--xunit); exits 1 when a check fails.
"""
import argparse
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scripts", "measure"))
from check_report import report  # noqa: E402
import peers  # noqa: E402

PYTHON = sys.executable or "python3"


def expect_rejected(text, words):
    try:
        peers.parse_peers(text)
    except ValueError as e:
        return [] if words in str(e) else ["%r: error %r does not say %r" % (text, str(e), words)]
    return ["%r was accepted" % text]


def check_parsing():
    errors = []
    errors += expect_rejected("contour context run {sequence}", "expected NAME = COMMAND")
    errors += expect_rejected("a = ", "expected NAME = COMMAND")
    errors += expect_rejected("= run", "expected NAME = COMMAND")
    errors += expect_rejected("a = run {sequence} {velodyne}", "unknown placeholder {velodyne}")
    errors += expect_rejected("a = run\na = other", "is taken")
    errors += expect_rejected("%s = run" % peers.OURS, "is taken")
    errors += expect_rejected("# only a comment\n\n", "no peer")
    got = peers.parse_peers("# peers\n\n  sc = ./sc {scans} {keyframes}  \ncontour-context 2 = cc {sequence} {output}\n")
    if got != [("sc", "./sc {scans} {keyframes}"), ("contour-context 2", "cc {sequence} {output}")]:
        errors.append("parsed %r" % got)
    return errors


def write_sequence(root, scans):
    """A sequence folder whose name needs quoting in a shell, with `scans` empty scan files."""
    sequence = os.path.join(root, "it's a drive")
    os.makedirs(os.path.join(sequence, "velodyne"))
    for i in range(scans):
        open(os.path.join(sequence, "velodyne", "%06d.bin" % i), "wb").close()
    return sequence


def check_measuring():
    errors = []
    with tempfile.TemporaryDirectory() as root:
        sequence = write_sequence(root, 4)
        seen = os.path.join(root, "seen")
        runs_of_failing = os.path.join(root, "failing_runs")
        # This package's stand-in records what it was given; the busy peer burns CPU in a grandchild.
        ours = "printf '%%s\\n' {sequence} {scans} {keyframes} {output} > '%s'; ls -d {output} >> '%s'" % (seen, seen)
        burn = ("import time\nwhile time.process_time() < 0.3: pass")
        programs = [(peers.OURS, ours),
                    ("busy", "( %s -c '%s' ); echo x > {output}/kept" % (PYTHON, burn)),
                    ("failing", "echo run >> '%s'; exit 3" % runs_of_failing),
                    ("hanging", "sleep 60")]
        data = peers.measure([sequence], programs, 2, 2.0, os.path.join(root, "logs"))
        entry = data["sequences"][0]
        if entry["keyframes"] != 4:
            errors.append("keyframes %r, not 4" % entry["keyframes"])
        lines = open(seen).read().splitlines() if os.path.exists(seen) else []
        expected = [sequence, os.path.join(sequence, "velodyne"), "4"]
        if lines[:3] != expected or len(lines) != 5 or lines[3] != lines[4]:
            errors.append("the command got %r, expected %r, an output folder and that folder existing" % (lines, expected))
        elif os.path.exists(lines[3]):
            errors.append("the output folder %s was left behind" % lines[3])
        busy = entry["programs"]["busy"]
        if busy["status"] != 0 or len(busy["cpu_s"]) != 2 or min(busy["cpu_s"]) < 0.3:
            errors.append("the busy peer's grandchild CPU was not counted: %r" % busy)
        failing = entry["programs"]["failing"]
        if failing["status"] != 3 or failing["cpu_s"]:
            errors.append("the failing peer is %r, not failed with status 3" % failing)
        runs = open(runs_of_failing).read().split() if os.path.exists(runs_of_failing) else []
        if len(runs) != 1:
            errors.append("the failing peer ran %d times, not once" % len(runs))
        hanging = entry["programs"]["hanging"]
        if "timed out" not in str(hanging["status"]):
            errors.append("the hanging peer is %r, not timed out" % hanging)
        if not os.path.exists(os.path.join(root, "logs", "failing_it_s_a_drive.log")):
            errors.append("no log for the failing peer in %s" % os.listdir(os.path.join(root, "logs")))
        table = "\n".join(peers.table(data))
        if "failed (exit 3)" not in table or "timed out after 2 s" not in table:
            errors.append("the table does not show the failures:\n" + table)
        if peers.ratios(data, "failing") or peers.ratios(data, "hanging"):
            errors.append("a failed peer got a ratio")
    return errors


def check_table():
    data = {"runs": 3, "programs": [peers.OURS, "cc"], "sequences": [
        {"name": "drive", "keyframes": 1000, "programs": {peers.OURS: {"cpu_s": [1.0, 3.0, 2.0], "status": 0},
                                                           "cc": {"cpu_s": [8.0, 9.5, 7.0], "status": 0}}},
        {"name": "other", "keyframes": 0, "programs": {}}]}
    errors = []
    table = peers.table(data)
    if "| drive | 1000 | 2.00 | 8.00 | 0.25x |" not in table:
        errors.append("expected the medians 2.00 and 8.00 ms and 0.25x in:\n" + "\n".join(table))
    if "| other | 0 | not run | not run | n/a |" not in table:
        errors.append("a sequence without scans is not shown as not run:\n" + "\n".join(table))
    if peers.ratios(data, "cc") != [0.25]:
        errors.append("ratios %r, not [0.25]" % peers.ratios(data, "cc"))
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--xunit", help="JUnit result file to write")
    args = parser.parse_args()
    cases = [("peers_file_is_read_strictly", check_parsing()),
             ("programs_are_measured_and_failures_reported", check_measuring()),
             ("table_shows_medians_and_ratios", check_table())]
    return report("peer_measurement", cases, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
