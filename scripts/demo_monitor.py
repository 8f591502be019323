#!/usr/bin/env python3
"""Listens to the loop-closure node during the demo and scores every loop it publishes against the
ground truth in the bag: true separation, estimated and true yaw. Prints a table and a summary; exits
when the bag's last keyframe has been processed (or after --timeout seconds). With the pose-graph
backend running, also prints the absolute trajectory error (RMSE and max after the rigid alignment
that fits best) of the odometry and of the corrected path against the truth.

usage: demo_monitor.py BAG [--radius 5] [--timeout 600] [--no-pose-graph]"""
import argparse
import math
import sys
import time

import numpy as np
import rosbag
import rospy
from nav_msgs.msg import Path
from scan_context_loop.msg import LoopClosure


# What the corrected path should leave of the odometry's trajectory error on the demo drive [%].
TARGET_SHARE = 20


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def aligned_error(estimate, truth):
    """Position errors [m] of `estimate` against `truth` (N x 3 each) after the rotation and translation
    that fit them best (Umeyama's method without scale)."""
    mu_e, mu_t = estimate.mean(axis=0), truth.mean(axis=0)
    u, _, vt = np.linalg.svd((truth - mu_t).T @ (estimate - mu_e))
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    rotation = u @ d @ vt
    moved = (rotation @ (estimate - mu_e).T).T + mu_t
    return np.linalg.norm(moved - truth, axis=1)


def path_positions(path, truth):
    """The path's positions and the true ones at the same stamps (keyframes without truth left out)."""
    est, tru = [], []
    for pose in path.poses:
        t = truth.get(pose.header.stamp.to_nsec())
        if t is None:
            continue
        p = pose.pose.position
        est.append((p.x, p.y, p.z))
        tru.append(t[:3])
    return np.array(est), np.array(tru)


def report_trajectory_error(paths, truth):
    """Prints the ATE of the odometry and the corrected path; returns (odometry, corrected) RMSE or None."""
    if "corrected" not in paths or "odometry" not in paths:
        print("\nno corrected path from the pose graph: no trajectory error")
        return None
    rmse = {}
    for name in ("odometry", "corrected"):
        est, tru = path_positions(paths[name], truth)
        if len(est) < 3:
            print("\n%s path: too few keyframes with a true pose" % name)
            return None
        errors = aligned_error(est, tru)
        rmse[name] = math.sqrt(float(np.mean(errors ** 2)))
        print("%s trajectory error over %d keyframes: RMSE %.2f m, max %.2f m" % (
            "\nodometry " if name == "odometry" else "corrected", len(est), rmse[name], float(errors.max())))
    share = 100.0 * rmse["corrected"] / rmse["odometry"]
    print("the loops take the trajectory error to %.0f%% of the odometry's (the aim: at most %d%%, %s)" % (
        share, TARGET_SHARE, "met" if share <= TARGET_SHARE else "not met"))
    return rmse["odometry"], rmse["corrected"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("bag")
    parser.add_argument("--radius", type=float, default=5.0)
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--no-pose-graph", action="store_true", help="no backend runs: RViz gets an identity map -> odom")
    args = parser.parse_args(rospy.myargv()[1:])

    truth = {}
    with rosbag.Bag(args.bag) as bag:
        for _, msg, _ in bag.read_messages(topics=["ground_truth"]):
            p = msg.pose.pose
            truth[msg.header.stamp.to_nsec()] = (p.position.x, p.position.y, p.position.z, yaw_of(p.orientation))
    last_stamp = max(truth) if truth else 0

    loops = []
    done = {"last": 0}

    def on_loop(msg):
        loops.append(msg)

    rospy.init_node("demo_monitor", anonymous=True)
    if args.no_pose_graph:
        # RViz needs the markers' frame in tf: without the backend's correction, an identity map -> odom.
        import tf2_ros
        from geometry_msgs.msg import TransformStamped
        broadcaster = tf2_ros.StaticTransformBroadcaster()
        static = TransformStamped()
        static.header.stamp = rospy.Time(0)
        static.header.frame_id = "map"
        static.child_frame_id = "odom"
        static.transform.rotation.w = 1.0
        broadcaster.sendTransform(static)
    paths = {}

    def keep(name):
        return lambda msg: paths.__setitem__(name, msg)

    rospy.Subscriber("corrected_path", Path, keep("corrected"), queue_size=2)
    rospy.Subscriber("odometry_path", Path, keep("odometry"), queue_size=2)
    rospy.Subscriber("loop_closures", LoopClosure, on_loop, queue_size=1000)
    start = time.time()
    # The node's markers carry the stamp of the newest keyframe: watch them to know when it is done.
    from visualization_msgs.msg import MarkerArray

    def on_markers(msg):
        if msg.markers:
            done["last"] = max(done["last"], msg.markers[0].header.stamp.to_nsec())

    rospy.Subscriber("loop_markers", MarkerArray, on_markers, queue_size=10)
    while not rospy.is_shutdown() and time.time() - start < args.timeout:
        if done["last"] >= last_stamp and last_stamp > 0:
            time.sleep(1.0)
            break
        time.sleep(0.2)

    print("%6s %6s  %8s  %9s  %9s  %8s  %9s  %s" % ("query", "match", "distance", "yaw [deg]", "true yaw", "apart",
                                                   "pose err", ""))
    correct = 0
    for loop in loops:
        q = truth.get(loop.query_stamp.to_nsec())
        m = truth.get(loop.match_stamp.to_nsec())
        if q is None or m is None:
            print("%6d %6d  %8.4f  (stamps not in the bag)" % (loop.query_id, loop.match_id, loop.distance))
            continue
        dx, dy = m[0] - q[0], m[1] - q[1]
        apart = math.hypot(dx, dy)
        true_yaw = wrap(m[3] - q[3])
        # A verified loop carries the registered T_query<-match: its error against the truth, in the
        # query's frame. One a little beyond the radius with the right pose is still a true constraint.
        c, s_ = math.cos(q[3]), math.sin(q[3])
        tx, ty = c * dx + s_ * dy, -s_ * dx + c * dy
        r = loop.relative_pose
        pose_error = math.hypot(r.position.x - tx, r.position.y - ty)
        yaw_error = abs(wrap(yaw_of(r.orientation) - true_yaw))
        exact = loop.verified and pose_error < 1.0 and yaw_error < math.radians(2.0)
        ok = apart < args.radius or exact
        correct += ok
        label = "true revisit" if apart < args.radius else ("true constraint" if exact else "FALSE LOOP")
        print("%6d %6d  %8.4f  %9.2f  %9.2f  %6.1f m  %s  %s" % (
            loop.query_id, loop.match_id, loop.distance, math.degrees(loop.yaw), math.degrees(true_yaw), apart,
            "%7.2f m" % pose_error if loop.verified else "        -", label))
    print("\n%d loops published, %d true (within %.0f m, or verified with a pose within 1 m and 2 deg of the "
          "truth), %d false; %d keyframes in the bag" % (len(loops), correct, args.radius, len(loops) - correct,
                                                         len(truth)))
    ate = None
    if not args.no_pose_graph:
        # The backend publishes its path once it has every keyframe and the last solve is done.
        deadline = time.time() + 60.0
        while time.time() < deadline and not rospy.is_shutdown():
            if all(len(paths.get(n, Path()).poses) >= len(truth) for n in ("corrected", "odometry")):
                break
            time.sleep(0.5)
        time.sleep(1.0)  # a solve that was due may still be going out
        ate = report_trajectory_error(paths, truth)
    ok = loops and correct == len(loops) and (args.no_pose_graph or (ate is not None and ate[1] < ate[0]))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
