#!/usr/bin/env python3
"""Listens to the loop-closure node during the demo and scores every loop it publishes against the
ground truth in the bag: true separation, estimated and true yaw. Prints a table and a summary; exits
when the bag's last keyframe has been processed (or after --timeout seconds).

usage: demo_monitor.py BAG [--radius 5] [--timeout 600]"""
import argparse
import math
import sys
import time

import rosbag
import rospy
from scan_context_loop.msg import LoopClosure


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("bag")
    parser.add_argument("--radius", type=float, default=5.0)
    parser.add_argument("--timeout", type=float, default=600.0)
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
    # RViz needs the markers' frame in tf: a static identity map -> odom puts it there.
    import tf2_ros
    from geometry_msgs.msg import TransformStamped
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    static = TransformStamped()
    static.header.stamp = rospy.Time(0)
    static.header.frame_id = "map"
    static.child_frame_id = "odom"
    static.transform.rotation.w = 1.0
    broadcaster.sendTransform(static)
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
    return 0 if loops and correct == len(loops) else 1


if __name__ == "__main__":
    sys.exit(main())
