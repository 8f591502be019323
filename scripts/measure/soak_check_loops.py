#!/usr/bin/env python3
"""Scores the loops a soak published against the truth of the pool laps it replayed.

LOOPS_CSV has one row per loop (query_id, match_id, verified, distance, x, y, z, qx, qy, qz, qw: the
published relative_pose T_query<-match). Keyframe ids map to the laps as soak_feed.py plays them: lap i is
POOL_DIR i % len(POOL_DIRS), keyframe by keyframe; this holds when every keyframe fed entered the
database (the soak's summary: dropped, rejected and unaccounted all 0). A verified loop is true when its
pose is within 1 m and 2 degrees of the truth (as scripts/demo and the evaluator score constraints); an
unverified one when its keyframes are within 5 m.

usage: soak_check_loops.py LOOPS_CSV POOL_DIR [POOL_DIR ...]"""
import csv
import math
import os
import sys

import numpy as np


def read_poses(path):
    rows = np.loadtxt(path, dtype=np.float64).reshape(-1, 12)
    poses = np.tile(np.eye(4), (len(rows), 1, 1))
    poses[:, :3, :] = rows.reshape(-1, 3, 4)
    return poses


def rotation(qx, qy, qz, qw):
    return np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])


def main():
    argv = sys.argv[1:]
    first_id = 0
    if len(argv) >= 2 and argv[0] == "--first-id":
        first_id = int(argv[1])
        argv = argv[2:]
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    laps = [read_poses(os.path.join(folder, "poses.txt")) for folder in argv[1:]]
    cycle = sum(len(l) for l in laps)
    starts = np.cumsum([0] + [len(l) for l in laps])

    def truth(keyframe):
        offset = keyframe % cycle
        lap = int(np.searchsorted(starts, offset, side="right")) - 1
        return laps[lap][offset - starts[lap]]

    with open(argv[0]) as f:
        rows = list(csv.DictReader(f))
    true_loops, false_loops, errors, angles, apart = 0, [], [], [], []
    into_map = 0
    for r in rows:
        q, m = int(r["query_id"]) - first_id, int(r["match_id"]) - first_id
        if q < 0 or m < 0:
            into_map += 1
            false_loops.append((q + first_id, m + first_id, float("nan")))
            continue
        t = np.linalg.inv(truth(q)) @ truth(m)
        apart.append(np.linalg.norm(t[:3, 3]))
        if int(r["verified"]):
            e = np.linalg.norm(np.array([float(r["x"]), float(r["y"]), float(r["z"])]) - t[:3, 3])
            d = rotation(float(r["qx"]), float(r["qy"]), float(r["qz"]), float(r["qw"])).T @ t[:3, :3]
            a = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(d) - 1.0) / 2.0))))
            errors.append(e)
            angles.append(a)
            ok = e < 1.0 and a < 2.0
        else:
            ok = apart[-1] < 5.0
        if ok:
            true_loops += 1
        else:
            false_loops.append((q, m, apart[-1]))
    print("loops: %d" % len(rows))
    print("true: %d" % true_loops)
    print("false: %d" % len(false_loops))
    if first_id:
        print("into the map loaded at start: %d" % into_map)
    for q, m, d in false_loops[:20]:
        print("  false loop %d -> %d, %.1f m apart" % (q, m, d))
    if errors:
        print("verified pose error median / p99 / max: %.3f / %.3f / %.3f m, %.3f / %.3f / %.3f deg" % (
            np.median(errors), np.percentile(errors, 99), max(errors), np.median(angles), np.percentile(angles, 99),
            max(angles)))
    if apart:
        print("keyframes apart (truth) median / max: %.1f / %.1f m" % (np.median(apart), max(apart)))
    return 1 if false_loops else 0


if __name__ == "__main__":
    sys.exit(main())
