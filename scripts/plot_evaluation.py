#!/usr/bin/env python3
"""Draws OUT_DIR/pr.png (precision-recall curve), OUT_DIR/map.png (trajectory with the detected
loops: true positives green, false positives red, missed revisits marked) and, when the evaluator
corrected the trajectory, OUT_DIR/correction.png (the truth, the drifting odometry and the trajectory
corrected by the loops, each aligned to the truth) from the evaluator's files. Given the sequence too,
map.png is the map before and after: the keyframe scans placed at the odometry's poses beside the same
scans at the corrected poses, with the loops drawn on both.

usage: plot_evaluation.py OUT_DIR [SEQUENCE_DIR]"""
import csv
import json
import os
import sys

import matplotlib
import numpy as np
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    out = sys.argv[1]
    with open(os.path.join(out, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out, "metrics.json")) as f:
        metrics = json.load(f)
    with open(os.path.join(out, "trajectory.csv")) as f:
        trajectory = {int(r["frame"]): (float(r["x"]), float(r["y"])) for r in csv.DictReader(f)}

    revisits = sum(int(r["true_revisit"]) for r in rows)
    detections = sorted((float(r["distance"]), int(r["correct"])) for r in rows if int(r["match"]) >= 0)
    precision, recall, tp, fp = [], [], 0, 0
    for _, correct in detections:
        tp += correct
        fp += 1 - correct
        precision.append(tp / (tp + fp))
        recall.append(tp / revisits if revisits else 0.0)
    fig, ax = plt.subplots(figsize=(6, 5))
    ax.plot(recall, precision, "b-")
    ax.set_xlim(0, 1.02)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.set_title("F1-max %.3f, recall@100%%P %.3f, AP %.3f" %
                 (metrics["f1_max"], metrics["recall_at_100_precision"], metrics["average_precision"]))
    ax.grid(True, alpha=0.3)
    fig.savefig(os.path.join(out, "pr.png"), dpi=100, bbox_inches="tight")
    plt.close(fig)

    threshold = metrics["threshold"]
    corrected = os.path.join(out, "trajectory_corrected.csv")
    sequence = sys.argv[2] if len(sys.argv) > 2 else ""
    if os.path.exists(corrected) and os.path.isdir(os.path.join(sequence, "velodyne")):
        plot_map_before_after(out, sequence, rows, corrected, threshold, metrics)
    else:
        plot_loops(out, rows, trajectory, threshold, metrics)
    written = [os.path.join(out, "pr.png"), os.path.join(out, "map.png")]
    if os.path.exists(corrected):
        written.append(plot_correction(out, trajectory, corrected))
    print(*written)


def plot_loops(out, rows, trajectory, threshold, metrics):
    """map.png without the scans: the true trajectory with the loops detected and the revisits missed."""
    fig, ax = plt.subplots(figsize=(10, 9))
    xs = [p[0] for p in trajectory.values()]
    ys = [p[1] for p in trajectory.values()]
    ax.plot(xs, ys, "-", color="0.6", lw=1, label="trajectory")
    shown = set()
    for r in rows:
        q, m = int(r["query"]), int(r["match"])
        detected = m >= 0 and float(r["distance"]) < threshold
        # With --prior, a match may be a frame of the prior sequence, which trajectory.csv does not hold.
        if detected and int(r.get("match_in_prior", "0")) and q in trajectory:
            label = "match in the prior map (%s)" % ("true" if int(r["correct"]) else "false")
            ax.plot(*trajectory[q], "s", color="g" if int(r["correct"]) else "r", ms=3,
                    label=None if label in shown else label)
            shown.add(label)
        elif detected and q in trajectory and m in trajectory:
            good = int(r["correct"])
            label = "true positive" if good else "false positive"
            ax.plot([trajectory[q][0], trajectory[m][0]], [trajectory[q][1], trajectory[m][1]],
                    "-", color="g" if good else "r", lw=1.5 if good else 1.0,
                    label=None if label in shown else label)
            shown.add(label)
        elif int(r["true_revisit"]) and q in trajectory:
            ax.plot(*trajectory[q], "o", color="orange", ms=3,
                    label=None if "missed revisit" in shown else "missed revisit")
            shown.add("missed revisit")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("threshold %.3f: precision %.3f, recall %.3f" % (threshold, metrics["precision"], metrics["recall"]))
    ax.legend(loc="best")
    fig.savefig(os.path.join(out, "map.png"), dpi=100, bbox_inches="tight")
    plt.close(fig)


def scan_points(sequence, frame, rng, share=0.03, max_range=40.0):
    """A random share of a keyframe scan's points (sensor frame, x y), within max_range and above the
    ground near the sensor's height band, so walls, poles and trees show and the road does not."""
    path = os.path.join(sequence, "velodyne", "%06d.bin" % frame)
    if not os.path.exists(path):
        return np.zeros((0, 2))
    points = np.fromfile(path, dtype=np.float32).reshape(-1, 4)
    r = np.hypot(points[:, 0], points[:, 1])
    keep = (r > 3.0) & (r < max_range) & (points[:, 2] > -1.0) & (points[:, 2] < 3.0)
    points = points[keep]
    if len(points):
        points = points[rng.random(len(points)) < share]
    return points[:, :2].astype(np.float64)


def plot_map_before_after(out, sequence, rows, corrected_csv, threshold, metrics):
    """map.png: the scans at the odometry's poses (left) and at the corrected poses (right), both aligned
    to the truth, with the loops the detector reported (true green, false red) between the keyframes;
    above, the whole drive; below, 120 m around the loop whose two ends the odometry put farthest apart
    (where its map shows the same walls twice)."""
    with open(corrected_csv) as f:
        poses = {int(r["frame"]): r for r in csv.DictReader(f)}
    with open(os.path.join(out, "trajectory_error.json")) as f:
        errors = json.load(f)
    rng = np.random.default_rng(1)
    local = {frame: scan_points(sequence, frame, rng) for frame in poses}
    at = {key: {f: (float(r[key + "_x"]), float(r[key + "_y"])) for f, r in poses.items()} for key in ("odom", "corrected")}
    world = {}
    for key in ("odom", "corrected"):
        parts = []
        for frame, r in poses.items():
            x, y, yaw = float(r[key + "_x"]), float(r[key + "_y"]), float(r[key + "_yaw"])
            c, s_ = np.cos(yaw), np.sin(yaw)
            p = local[frame]
            if len(p):
                parts.append(np.column_stack((x + c * p[:, 0] - s_ * p[:, 1], y + s_ * p[:, 0] + c * p[:, 1])))
        world[key] = np.vstack(parts) if parts else np.zeros((0, 2))
    # With --prior a match may be a prior frame, whose number may also be one of this sequence's.
    loops = [(int(r["query"]), int(r["match"]), int(r["correct"])) for r in rows
             if int(r["match"]) >= 0 and float(r["distance"]) < threshold and not int(r.get("match_in_prior", "0"))
             and int(r["query"]) in poses and int(r["match"]) in poses]
    # The detail: where the odometry disagrees most with itself across a true loop.
    centre, gap = None, -1.0
    for q, m, good in loops:
        d = np.hypot(at["odom"][q][0] - at["odom"][m][0], at["odom"][q][1] - at["odom"][m][1])
        if good and d > gap:
            gap, centre = d, at["corrected"][q]
    titles = {"odom": "%s: %s" % (odometry_name(errors), ate_text(errors, "odometry")),
              "corrected": "corrected with %s: %s" % (loops_name(errors), ate_text(errors, "corrected"))}
    detail = centre is not None
    fig, axes = plt.subplots(2 if detail else 1, 2, figsize=(14, 20 if detail else 10), squeeze=False)
    for row in range(axes.shape[0]):
        for col, key in enumerate(("odom", "corrected")):
            ax = axes[row][col]
            pts = world[key]
            size = 0.05 if row == 0 else 1.0
            ax.scatter(pts[:, 0], pts[:, 1], s=size, c="0.25", alpha=0.35, linewidths=0, rasterized=True)
            frames = sorted(at[key])
            ax.plot([at[key][f][0] for f in frames], [at[key][f][1] for f in frames], "-", color="tab:blue", lw=0.8,
                    label="keyframe path")
            shown = set()
            for q, m, good in loops:
                label = "loop (true)" if good else "loop (false)"
                ax.plot([at[key][q][0], at[key][m][0]], [at[key][q][1], at[key][m][1]], "-",
                        color="g" if good else "r", lw=1.5, label=None if label in shown else label)
                shown.add(label)
            ax.set_aspect("equal")
            ax.set_xlabel("x [m]")
            if row == 0:
                ax.set_title(titles[key])
                if detail:
                    ax.add_patch(plt.Rectangle((centre[0] - 60, centre[1] - 60), 120, 120, fill=False, color="tab:orange"))
            else:
                ax.set_xlim(centre[0] - 60, centre[0] + 60)
                ax.set_ylim(centre[1] - 60, centre[1] + 60)
                ax.set_title("the orange box: %s" % ("odometry (the loop's ends %.1f m apart)" % gap if key == "odom"
                                                    else "corrected"))
            ax.legend(loc="best")
        axes[row][0].set_ylabel("y [m]")
    fig.suptitle("the scans placed at the keyframe poses, before and after the pose graph\n(threshold %.3f: "
                 "precision %.3f, recall %.3f)" % (threshold, metrics["precision"], metrics["recall"]))
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(os.path.join(out, "map.png"), dpi=70, bbox_inches="tight")
    plt.close(fig)


def odometry_name(errors):
    """What the odometry was: the sequence's own, or the truth (trajectory_error.json's odometry_source)."""
    return "odometry (the truth)" if errors.get("odometry_source") == "truth" else "odometry"


def ate_text(errors, key):
    """One trajectory's ATE for a label: in millimetres' precision where the truth is the odometry."""
    digits = 3 if errors.get("odometry_source") == "truth" else 2
    return "ATE %.*f m (max %.*f)" % (digits, errors[key]["rmse_m"], digits, errors[key]["max_m"])


def loops_name(errors):
    """The loops that corrected the trajectory, those into a prior map's fixed keyframes named."""
    if "prior" in errors:
        return "%d loops (%d into the prior, held fixed)" % (errors["loops"], errors.get("prior_loops", 0))
    return "%d loops" % errors["loops"]


def plot_correction(out, trajectory, corrected_csv):
    """Top-down: the truth, the odometry and the corrected trajectory, with their errors."""
    with open(corrected_csv) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out, "trajectory_error.json")) as f:
        errors = json.load(f)
    fig, ax = plt.subplots(figsize=(10, 9))
    frames = [int(r["frame"]) for r in rows if int(r["frame"]) in trajectory]
    ax.plot([trajectory[f][0] for f in frames], [trajectory[f][1] for f in frames], "-", color="k", lw=2.5,
            alpha=0.25, label="truth")
    ax.plot([float(r["odom_x"]) for r in rows], [float(r["odom_y"]) for r in rows], "--", color="tab:red", lw=1, alpha=0.8,
            label="%s: %s" % (odometry_name(errors), ate_text(errors, "odometry")))
    ax.plot([float(r["corrected_x"]) for r in rows], [float(r["corrected_y"]) for r in rows], "-", color="tab:blue",
            lw=1.2, label="corrected with %s: %s" % (loops_name(errors), ate_text(errors, "corrected")))
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("what the loops do to the trajectory (each aligned to the truth)")
    ax.legend(loc="best")
    path = os.path.join(out, "correction.png")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
    return path


if __name__ == "__main__":
    main()
