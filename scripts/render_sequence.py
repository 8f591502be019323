#!/usr/bin/env python3
"""Renders a KITTI-layout sequence to PNG: the whole map top-down (every keyframe's points in the world
frame, subsampled, coloured by height, with the trajectory) and one scan top-down and from the side.

usage: render_sequence.py SEQUENCE_DIR OUT_PREFIX [--scan K] [--every N]
writes OUT_PREFIX_map.png and OUT_PREFIX_scan.png"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_poses(path):
    rows = np.loadtxt(path, ndmin=2)
    poses = np.tile(np.eye(4), (len(rows), 1, 1))
    poses[:, :3, :4] = rows.reshape(-1, 3, 4)
    return poses


def read_tr(path):
    with open(path) as f:
        for line in f:
            if line.startswith("Tr:"):
                tr = np.eye(4)
                tr[:3, :4] = np.array(line.split()[1:13], dtype=float).reshape(3, 4)
                return tr
    return np.eye(4)


def read_scan(seq, k):
    return np.fromfile(os.path.join(seq, "velodyne", "%06d.bin" % k), dtype=np.float32).reshape(-1, 4)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("sequence")
    parser.add_argument("out_prefix")
    parser.add_argument("--scan", type=int, default=0, help="keyframe shown in the scan views")
    parser.add_argument("--every", type=int, default=5, help="use every N-th keyframe in the map")
    args = parser.parse_args()

    tr = read_tr(os.path.join(args.sequence, "calib.txt"))
    poses = np.linalg.inv(tr) @ read_poses(os.path.join(args.sequence, "poses.txt")) @ tr
    available = [k for k in range(len(poses))
                 if os.path.exists(os.path.join(args.sequence, "velodyne", "%06d.bin" % k))]

    clouds = []
    rng = np.random.default_rng(0)
    for k in available[::args.every]:
        pts = read_scan(args.sequence, k)[:, :3]
        pts = pts[rng.random(len(pts)) < 0.08]
        world = pts @ poses[k][:3, :3].T + poses[k][:3, 3]
        clouds.append(world)
    world = np.concatenate(clouds) if clouds else np.zeros((0, 3))
    ground = np.median(poses[:, 2, 3]) - 1.73
    above = world[:, 2] - ground
    order = np.argsort(above)
    fig, ax = plt.subplots(figsize=(14, 11))
    ax.scatter(world[order, 0], world[order, 1], c=np.clip(above[order], -0.5, 15), s=0.15, cmap="viridis",
               linewidths=0)
    ax.plot(poses[:, 0, 3], poses[:, 1, 3], "r-", lw=0.8, label="trajectory")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("%s: %d keyframes, points coloured by height above the ground" %
                 (os.path.basename(os.path.normpath(args.sequence)), len(poses)))
    ax.legend(loc="upper right")
    fig.savefig(args.out_prefix + "_map.png", dpi=110, bbox_inches="tight")
    plt.close(fig)

    scan = read_scan(args.sequence, args.scan)
    fig, (top, side) = plt.subplots(1, 2, figsize=(18, 8), gridspec_kw={"width_ratios": [1, 1.4]})
    near = np.hypot(scan[:, 0], scan[:, 1]) < 60
    top.scatter(scan[near, 0], scan[near, 1], c=np.clip(scan[near, 2], -2, 8), s=0.2, cmap="viridis",
                linewidths=0)
    top.set_aspect("equal")
    top.set_title("keyframe %d top-down (%d points), colour = z" % (args.scan, len(scan)))
    band = near & (np.abs(scan[:, 1]) < 30)
    side.scatter(scan[band, 0], scan[band, 2], c=scan[band, 3], s=0.2, cmap="gray_r", linewidths=0)
    side.set_aspect("equal")
    side.set_title("side view (x, z), colour = intensity")
    fig.savefig(args.out_prefix + "_scan.png", dpi=100, bbox_inches="tight")
    plt.close(fig)
    print(args.out_prefix + "_map.png", args.out_prefix + "_scan.png")


if __name__ == "__main__":
    main()
