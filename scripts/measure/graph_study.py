#!/usr/bin/env python3
"""Prints the graph study's tables (scripts/measure/graph_study) from each sequence's graph_study.csv.

Arguments: NAME=PATH, one per sequence. First a table per sequence (odometry; the reported loops with the
default weights ("reported"), with one false loop, at their true poses, the oracle; the same with the
candidate weights; where the error lies), then one row per variant: its ATE RMSE against the reported
loops' with the default weights, over the sequences."""
import csv
import math
import os
import sys


def read(path):
    with open(path) as f:
        return {row["variant"]: row for row in csv.DictReader(f)}


def num(row, key):
    return float(row[key])


def main():
    studies = []
    for arg in sys.argv[1:]:
        name, path = arg.split("=", 1)
        if os.path.exists(path):
            studies.append((name, read(path)))
        else:
            print("%s: no %s" % (name, path), file=sys.stderr)
    if not studies:
        return 1
    print("| sequence | odometry | reported loops | + one false loop | same pairs, true poses | oracle (loops) | "
          "candidate weights | candidate: + one false loop | candidate: oracle | revisited / rest (keyframes) | "
          "candidate: revisited / rest | after similarity (scale) | no alignment |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, s in studies:
        o, r, t, k = s["odometry"], s["reported"], s["reported_true"], s["oracle"]
        d, df, dk, bf = s["candidate"], s["candidate_false"], s["candidate_oracle"], s["reported_false"]
        print("| %s | %.2f | **%.2f** (%s) | %.2f | %.2f | %.2f (%s) | %.2f | %.2f | %.2f | %.2f / %.2f (%s / %s) | "
              "%.2f / %.2f | %.2f (%.4f) | %.2f |" % (
                  name, num(o, "ate_rmse_m"), num(r, "ate_rmse_m"), r["loops"], num(bf, "ate_rmse_m"),
                  num(t, "ate_rmse_m"), num(k, "ate_rmse_m"), k["loops"], num(d, "ate_rmse_m"), num(df, "ate_rmse_m"),
                  num(dk, "ate_rmse_m"), num(r, "revisited_rmse_m"), num(r, "rest_rmse_m"), r["revisited_keyframes"],
                  r["rest_keyframes"], num(d, "revisited_rmse_m"), num(d, "rest_rmse_m"), num(r, "similarity_rmse_m"),
                  num(r, "similarity_scale"), num(r, "anchored_rmse_m")))
    print()
    variants = [v for v in studies[0][1] if v != "odometry"]
    print("| variant | settings | ATE RMSE / reported's: geometric mean | lower by > 2 % | higher by > 2 % | "
          "highest ratio (sequence) | mean ATE RMSE [m] | mean revisited / rest [m] |")
    print("|---|---|---|---|---|---|---|---|")
    for v in variants:
        ratios = []
        for name, s in studies:
            if v in s and num(s["reported"], "ate_rmse_m") > 0:
                ratios.append((num(s[v], "ate_rmse_m") / num(s["reported"], "ate_rmse_m"), name))
        if not ratios:
            continue
        mean_log = sum(math.log(max(x, 1e-9)) for x, _ in ratios) / len(ratios)
        worst = max(ratios)
        rows = [s[v] for _, s in studies if v in s]
        print("| %s | `%s` | %.3f | %d | %d | %.3f (%s) | %.3f | %.3f / %.3f |" % (
            v, rows[0]["settings"], math.exp(mean_log), sum(x < 0.98 for x, _ in ratios),
            sum(x > 1.02 for x, _ in ratios), worst[0], worst[1],
            sum(num(r, "ate_rmse_m") for r in rows) / len(rows),
            sum(num(r, "revisited_rmse_m") for r in rows) / len(rows), sum(num(r, "rest_rmse_m") for r in rows) / len(rows)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
