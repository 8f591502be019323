#!/usr/bin/env python3
"""Which acceptance test refused the candidates at the right place, per evaluated sequence.

Reads each EVAL_DIR's metrics.json and verifications.csv (scripts/evaluate's output) and prints one
Markdown row per sequence: the verified precision and recall, the descriptor stage's recall at 100 %
precision, the first candidate right / kept by verification, and for every acceptance test that refused
a candidate at the right place (within the revisit radius of the query by the truth): how many, and how
many of those had a right registration all the same (within 1 m and 2 deg of the truth) with their
median translation error; then the candidates at a wrong place it refused.

Usage: scripts/measure/refusals.py EVAL_DIR...
"""
import csv
import json
import os
import statistics
import sys


def row(eval_dir):
    metrics = json.load(open(os.path.join(eval_dir, "metrics.json")))
    radius = metrics.get("revisit_radius_m", 5.0)
    verified = metrics.get("verified") or {}
    refused = {}  # test -> [right place, right registration, errors, wrong place]
    with open(os.path.join(eval_dir, "verifications.csv")) as f:
        for c in csv.DictReader(f):
            if c["accepted"] == "1" or not c["rejected_by"]:
                continue
            entry = refused.setdefault(c["rejected_by"], [0, 0, [], 0])
            if float(c["gap_m"]) <= radius:
                entry[0] += 1
                error = float(c["trans_err_m"])
                entry[2].append(error)
                entry[1] += error <= 1.0 and float(c["rot_err_deg"]) <= 2.0
            else:
                entry[3] += 1
    tests = ", ".join(
        "%s %d (%d right, median %.2f m; %d elsewhere)"
        % (name, e[0], e[1], statistics.median(e[2]) if e[2] else float("nan"), e[3])
        for name, e in sorted(refused.items(), key=lambda kv: -kv[1][0]))
    name = os.path.basename(os.path.dirname(os.path.abspath(eval_dir)))
    return "| %s | %d | %.3f / %.3f | %.3f | %d / %d | %s |" % (
        name, metrics["true_revisits"], verified.get("precision", float("nan")), verified.get("recall", float("nan")),
        metrics["recall_at_100_precision"], verified.get("first_candidate_right", 0),
        verified.get("first_candidate_right_verified", 0), tests or "none")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    print("| sequence | revisits | verified precision / recall | descriptor recall @100% P | first candidate right / "
          "verified | refused at the right place, by test |")
    print("|---|---|---|---|---|---|")
    for eval_dir in sys.argv[1:]:
        print(row(eval_dir))


if __name__ == "__main__":
    main()
