#!/usr/bin/env python3
"""Renders a KITTI-layout sequence (simulated or real) to PNG, to see what a sequence holds.

OUT_PREFIX_map.png   the whole map top-down: every N-th keyframe's points in the world frame, subsampled,
                     ground grey and everything above it coloured by height, with the trajectory
OUT_PREFIX_detail.png  the same over a square around one keyframe, from every keyframe and denser
OUT_PREFIX_scan.png  that keyframe's scan: top-down, from the side (height exaggerated) and as a range
                     image (elevation against azimuth), which shows the beam pattern

usage: render_sequence.py SEQUENCE_DIR OUT_PREFIX [--scan K] [--every N] [--detail METRES]
       [--mount-height M]"""
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


def read_info(seq):
    """key: value lines of sequence.txt (simulated sequences), else empty."""
    info = {}
    path = os.path.join(seq, "sequence.txt")
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                key, _, value = line.partition(":")
                info[key.strip()] = value.strip()
    return info


def scan_path(seq, k):
    return os.path.join(seq, "velodyne", "%06d.bin" % k)


def read_scan(seq, k):
    return np.fromfile(scan_path(seq, k), dtype=np.float32).reshape(-1, 4)


def world_points(seq, poses, frames, keep, mount, rng, tilted=False):
    """Points of the given keyframes in the world frame (a random fraction `keep` of each scan) and
    their heights above the ground under the sensor that saw them (ground: below 0.25 m). A level
    sensor's z is the height; a tilted one's (--tilt) is measured along the world's vertical."""
    points, heights = [], []
    for k in frames:
        pts = read_scan(seq, k)[:, :3]
        pts = pts[rng.random(len(pts)) < keep]
        rotated = pts @ poses[k][:3, :3].T
        heights.append((rotated if tilted else pts)[:, 2] + mount)
        points.append(rotated + poses[k][:3, 3])
    if not points:
        return np.zeros((0, 3)), np.zeros(0)
    return np.concatenate(points), np.concatenate(heights)


def draw_map(ax, points, heights, poses, size):
    ground = heights < 0.25
    ax.scatter(points[ground, 0], points[ground, 1], c="0.8", s=size, linewidths=0, rasterized=True)
    above = points[~ground]
    height = heights[~ground]
    order = np.argsort(height)
    sc = ax.scatter(above[order, 0], above[order, 1], c=np.clip(height[order], 0, 12), s=size * 1.5,
                    cmap="turbo", vmin=0, vmax=12, linewidths=0, rasterized=True)
    ax.plot(poses[:, 0, 3], poses[:, 1, 3], "k-", lw=0.7, label="trajectory")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    return sc


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("sequence")
    parser.add_argument("out_prefix")
    parser.add_argument("--scan", type=int, default=0, help="keyframe of the scan and detail views")
    parser.add_argument("--every", type=int, default=5, help="use every N-th keyframe in the map")
    parser.add_argument("--detail", type=float, default=120.0, help="side of the detail square [m]")
    parser.add_argument("--mount-height", type=float, default=None,
                        help="sensor height above the ground [m] (default: sequence.txt's, else 1.73)")
    args = parser.parse_args()

    seq = args.sequence
    info = read_info(seq)
    mount = args.mount_height or float(info.get("mount_height_m", 1.73))
    tilted = float(info.get("tilt_deg", 0)) > 0
    tr = read_tr(os.path.join(seq, "calib.txt"))
    poses = np.linalg.inv(tr) @ read_poses(os.path.join(seq, "poses.txt")) @ tr
    available = [k for k in range(len(poses)) if os.path.exists(scan_path(seq, k))]
    if not available:
        raise SystemExit("no scans in %s" % seq)
    if args.scan not in available:
        args.scan = min(available, key=lambda k: abs(k - args.scan))
    name = os.path.basename(os.path.normpath(seq))
    sensor = info.get("sensor", "")
    rng = np.random.default_rng(0)
    outputs = []

    # The whole map.
    points, heights = world_points(seq, poses, available[::args.every], 0.06, mount, rng, tilted)
    fig, ax = plt.subplots(figsize=(14, 11))
    sc = draw_map(ax, points, heights, poses, 0.2)
    ax.set_title("%s %s: %d keyframes; ground grey, other points by height above the ground" %
                 (name, sensor, len(poses)))
    fig.colorbar(sc, ax=ax, shrink=0.6, label="height above ground [m]")
    outputs.append(args.out_prefix + "_map.png")
    fig.savefig(outputs[-1], dpi=110, bbox_inches="tight")
    plt.close(fig)

    # A square around the chosen keyframe, from every keyframe near it.
    centre = poses[args.scan][:3, 3]
    half = args.detail / 2
    near = [k for k in available if np.max(np.abs(poses[k][:2, 3] - centre[:2])) < half + 60]
    points, heights = world_points(seq, poses, near, 0.25, mount, rng, tilted)
    inside = np.all(np.abs(points[:, :2] - centre[:2]) < half, axis=1)
    fig, ax = plt.subplots(figsize=(12, 11))
    sc = draw_map(ax, points[inside], heights[inside], poses, 0.6)
    ax.plot(centre[0], centre[1], "r^", ms=9, label="keyframe %d" % args.scan)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_title("%s: %.0f m around keyframe %d, from %d keyframes" % (name, args.detail, args.scan, len(near)))
    ax.legend(loc="upper right")
    fig.colorbar(sc, ax=ax, shrink=0.6, label="height above ground [m]")
    outputs.append(args.out_prefix + "_detail.png")
    fig.savefig(outputs[-1], dpi=110, bbox_inches="tight")
    plt.close(fig)

    # One scan: top-down, side view, range image.
    scan = read_scan(seq, args.scan)
    x, y, z, intensity = scan.T
    horizontal = np.hypot(x, y)
    fig = plt.figure(figsize=(18, 15))
    grid = fig.add_gridspec(3, 2, height_ratios=[2.2, 1, 1])
    top = fig.add_subplot(grid[0, 0])
    close = horizontal < 50
    top.scatter(x[close], y[close], c=np.clip(z[close] + mount, 0, 8), s=0.3, cmap="turbo", linewidths=0,
                rasterized=True)
    top.set_aspect("equal")
    top.set_title("keyframe %d top-down, 50 m (%d points), colour = height above ground" % (args.scan, len(scan)))
    inten = fig.add_subplot(grid[0, 1])
    lo, hi = np.percentile(intensity, [2, 98]) if len(intensity) else (0, 1)
    inten.scatter(x[close], y[close], c=intensity[close], s=0.3, cmap="gray_r", vmin=lo, vmax=hi, linewidths=0,
                  rasterized=True)
    inten.set_aspect("equal")
    inten.set_title("the same, colour = intensity")
    side = fig.add_subplot(grid[1, :])
    band = (np.abs(y) < 12) & (np.abs(x) < 70)
    side.scatter(x[band], z[band], c=np.clip(np.abs(y[band]), 0, 12), s=0.3, cmap="viridis", linewidths=0,
                 rasterized=True)
    side.set_xlabel("x [m] (forward)")
    side.set_ylabel("z [m]")
    side.set_title("side view of |y| < 12 m, height exaggerated, colour = |y|")
    # Range image: the nearest return in bins of 0.25 deg elevation by 0.5 deg azimuth.
    ranges = np.linalg.norm(scan[:, :3], axis=1)
    elevation = np.degrees(np.arctan2(z, horizontal))
    azimuth = np.degrees(np.arctan2(y, x))
    rows = np.clip(((elevation + 30.0) / 0.25).astype(int), 0, 199)
    cols = np.clip(((180.0 - azimuth) / 0.5).astype(int), 0, 719)
    picture = np.full((200, 720), np.inf)
    np.minimum.at(picture, (rows, cols), ranges)
    picture[np.isinf(picture)] = np.nan
    used = np.where(np.isfinite(picture).any(axis=1))[0]
    image = fig.add_subplot(grid[2, :])
    if len(used):
        top_row, bottom_row = used.max(), used.min()
        image.imshow(picture[bottom_row:top_row + 1][::-1], aspect="auto", cmap="turbo", vmin=0, vmax=60,
                     interpolation="nearest",
                     extent=(180, -180, bottom_row * 0.25 - 30.0, (top_row + 1) * 0.25 - 30.0))
    image.set_xlabel("azimuth [deg] (left of forward is positive)")
    image.set_ylabel("elevation [deg]")
    image.set_title("range image (nearest return per 0.25 x 0.5 deg), colour = range to 60 m, white = no return")
    outputs.append(args.out_prefix + "_scan.png")
    fig.savefig(outputs[-1], dpi=90, bbox_inches="tight")
    plt.close(fig)
    print(" ".join(outputs))


if __name__ == "__main__":
    main()
