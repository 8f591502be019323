#!/usr/bin/env python3
"""Feeds the loop-closure node a long multi-lap drive for scripts/measure/soak: KEYFRAMES keyframes
(sensor_msgs/PointCloud2 in the sensor frame and nav_msgs/Odometry with the same stamp, the node's normal
inputs) at RATE Hz, from a pool of simulated laps.

The pool is a list of sequence folders written by scan_context_simulate (KITTI layout: velodyne/*.bin,
poses.txt, odom_poses.txt). Lap i replays pool folder i % len(pool); the folders alternate between a
drive and the same streets driven back the other way (a second session), so each lap starts where the
last one ended. Every lap's clouds differ from the pool's and from every other lap's: a fresh random
tenth of the points is dropped and every point moves by 2 cm Gaussian noise. The odometry is one
continuous run: each step is the pool lap's own drifting odometry step (the lap junctions take the true
step), composed onto the last pose, so its drift accumulates over the whole drive.

Writes PROGRESS (keyframes fed, wall seconds since the first) every 100 keyframes and at the end, from a
thread of its own so that a slow disk never holds up the publishing. Reports at the end how late its own
publishing ever ran behind the schedule: a feeder that stalls (its process descheduled, its memory paged)
then catches up in a burst, and a burst longer than the node's queue is dropped by the node, rightly.

usage: soak_feed.py PROGRESS KEYFRAMES RATE POOL_DIR [POOL_DIR ...]"""
import math
import os
import queue
import sys
import threading
import time

import numpy as np
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import PointCloud2, PointField

STEP_SECONDS = 0.2  # keyframe stamps: 2 m at 10 m/s
DROP_FRACTION = 0.1
NOISE_SIGMA = 0.02
LATE_SECONDS = 0.1  # the feeder's own lateness worth counting (4 keyframes at 40 Hz)


def read_poses(path):
    rows = np.loadtxt(path, dtype=np.float64).reshape(-1, 12)
    poses = np.tile(np.eye(4), (len(rows), 1, 1))
    poses[:, :3, :] = rows.reshape(-1, 3, 4)
    return poses


def read_lap(folder):
    truth = read_poses(os.path.join(folder, "poses.txt"))
    odom = read_poses(os.path.join(folder, "odom_poses.txt"))
    clouds = []
    for k in range(len(truth)):
        clouds.append(np.fromfile(os.path.join(folder, "velodyne", "%06d.bin" % k), dtype=np.float32).reshape(-1, 4))
    return {"truth": truth, "odom": odom, "clouds": clouds}


def quaternion(r):
    """Unit quaternion (x, y, z, w) of a rotation matrix."""
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s)
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = (0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s)
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = ((r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = ((r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s, (r[1, 0] - r[0, 1]) / s)
    n = math.sqrt(sum(c * c for c in q))
    return tuple(c / n for c in q)


def orthonormalised(pose):
    u, _, vt = np.linalg.svd(pose[:3, :3])
    out = pose.copy()
    out[:3, :3] = u @ vt
    return out


def cloud_message(points, stamp):
    msg = PointCloud2()
    msg.header.stamp = stamp
    msg.header.frame_id = "velodyne"
    msg.height = 1
    msg.width = len(points)
    msg.fields = [PointField(name, 4 * i, PointField.FLOAT32, 1) for i, name in enumerate(("x", "y", "z", "intensity"))]
    msg.is_bigendian = False
    msg.point_step = 16
    msg.row_step = 16 * len(points)
    msg.is_dense = True
    msg.data = points.astype(np.float32, copy=False).tobytes()
    return msg


def odom_message(pose, stamp):
    msg = Odometry()
    msg.header.stamp = stamp
    msg.header.frame_id = "odom"
    msg.child_frame_id = "velodyne"
    p = msg.pose.pose
    p.position.x, p.position.y, p.position.z = pose[0, 3], pose[1, 3], pose[2, 3]
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = quaternion(pose[:3, :3])
    return msg


def main():
    args = rospy.myargv()[1:]
    if len(args) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    progress_path, total, rate, folders = args[0], int(args[1]), float(args[2]), args[3:]
    laps = [read_lap(f) for f in folders]
    sys.stderr.write("soak_feed: %d pool laps, %s keyframes each, %.0f MB of clouds\n" % (
        len(laps), "/".join(str(len(l["truth"])) for l in laps),
        sum(c.nbytes for l in laps for c in l["clouds"]) / 1e6))

    rospy.init_node("soak_feed")
    cloud_pub = rospy.Publisher("keyframe_cloud", PointCloud2, queue_size=200, tcp_nodelay=True)
    odom_pub = rospy.Publisher("keyframe_odom", Odometry, queue_size=200, tcp_nodelay=True)
    while not rospy.is_shutdown() and (cloud_pub.get_num_connections() == 0 or odom_pub.get_num_connections() == 0):
        time.sleep(0.1)
    time.sleep(1.0)

    rng = np.random.default_rng(7)
    base = rospy.Time(1000000000)
    pose = laps[0]["truth"][0].copy()  # the odometry starts at the first true pose
    lap_index, k, previous = 0, 0, None
    start = time.time()
    fed = 0

    progress = queue.Queue()

    def progress_writer():  # writes the newest line queued; None, after the last line, ends it
        done = False
        while not done:
            items = [progress.get()]
            while not progress.empty():
                items.append(progress.get_nowait())
            done = items[-1] is None
            lines = [item for item in items if item is not None]
            if lines:
                with open(progress_path + ".tmp", "w") as f:
                    f.write(lines[-1])
                os.replace(progress_path + ".tmp", progress_path)

    writer = threading.Thread(target=progress_writer, daemon=True)
    writer.start()

    def write_progress():
        progress.put("%d %.3f\n" % (fed, time.time() - start))

    late_max, late_count, late_at = 0.0, 0, 0

    while fed < total and not rospy.is_shutdown():
        lap = laps[lap_index % len(laps)]
        if previous is not None:
            if k == 0:  # lap junction: the true step from the last lap's end to this one's start
                prev_lap, prev_k = previous
                step = np.linalg.inv(prev_lap["truth"][prev_k]) @ lap["truth"][0]
            else:
                step = np.linalg.inv(lap["odom"][k - 1]) @ lap["odom"][k]
            pose = pose @ step
            if fed % 100 == 0:
                pose = orthonormalised(pose)
        points = lap["clouds"][k]
        keep = rng.random(len(points)) >= DROP_FRACTION
        points = points[keep].copy()
        points[:, :3] += rng.normal(0.0, NOISE_SIGMA, (len(points), 3)).astype(np.float32)
        stamp = base + rospy.Duration.from_sec(fed * STEP_SECONDS)

        due = start + fed / rate
        wait = due - time.time()
        if wait > 0:
            time.sleep(wait)
        late = time.time() - due
        if late > LATE_SECONDS:
            late_count += 1
        if late > late_max:
            late_max, late_at = late, fed
        cloud_pub.publish(cloud_message(points, stamp))
        odom_pub.publish(odom_message(pose, stamp))
        fed += 1
        if fed % 100 == 0:
            write_progress()
        previous = (lap, k)
        k += 1
        if k == len(lap["truth"]):
            lap_index, k = lap_index + 1, 0
    elapsed = time.time() - start
    write_progress()
    progress.put(None)
    writer.join()
    sys.stderr.write("soak_feed: %d keyframes in %.1f s (%.2f Hz), %d laps begun\n" % (
        fed, elapsed, fed / max(elapsed, 1e-9), lap_index + (k > 0)))
    sys.stderr.write("soak_feed: publishing ran late by more than %.0f ms %d times, at most %.0f ms "
                     "(keyframe %d)\n" % (1000 * LATE_SECONDS, late_count, 1000 * late_max, late_at))
    time.sleep(2.0)  # let the last messages go out
    return 0


if __name__ == "__main__":
    sys.exit(main())
