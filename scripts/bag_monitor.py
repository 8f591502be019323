#!/usr/bin/env python3
"""What the node and the backend made of a user's bag (scripts/demo --bag): the keyframes the node
selected, the loops it published, the corrected path. Listens from before the replay starts; once the
file --played exists (the replay ended) and nothing new came for --idle seconds, waits for the backend's
path to hold every selected keyframe, prints the summary and exits: 0 when the node selected keyframes, 1
when it selected none (the topics or frames do not fit; the launch log says why), or when the bag carries
a ground truth (the simulator's `ground_truth`) and a loop joins places it puts more than --radius apart.

    bag_monitor.py --check-topics BAG TOPIC...   exits 2, naming them, if the bag lacks one of the topics
    bag_monitor.py BAG --played FILE [--radius 10] [--idle 3] [--timeout 3600]
"""
import argparse
import math
import os
import sys
import time

import numpy as np
import rosbag

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from demo_monitor import aligned_error, path_positions  # noqa: E402


def check_topics(bag_path, topics):
    with rosbag.Bag(bag_path) as bag:
        info = bag.get_type_and_topic_info().topics
    have = {t.lstrip("/"): (t, i.msg_type, i.message_count) for t, i in info.items()}
    missing = [t for t in topics if t.lstrip("/") not in have]
    if not missing:
        return 0
    print("the bag has no %s; it holds:" % ", ".join(missing))
    for name in sorted(have):
        topic, kind, count = have[name]
        print("  %-45s %-32s %d messages" % (topic, kind, count))
    print("name the stack whose output it holds (--stack), or its topics (--stack topics --cloud-topic T "
          "--odom-topic T)")
    return 2


def read_truth(bag_path):
    """The ground truth's positions by stamp [ns], if the bag has one."""
    truth = {}
    with rosbag.Bag(bag_path) as bag:
        for _, msg, _ in bag.read_messages(topics=["ground_truth", "/ground_truth"]):
            p = msg.pose.pose.position
            truth[msg.header.stamp.to_nsec()] = (p.x, p.y, p.z)
    return truth


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--check-topics":
        return check_topics(sys.argv[2], sys.argv[3:])
    import rospy
    from nav_msgs.msg import Odometry, Path
    from scan_context_loop.msg import LoopClosure

    parser = argparse.ArgumentParser()
    parser.add_argument("bag")
    parser.add_argument("--played", required=True, help="a file that exists once the replay ended")
    parser.add_argument("--radius", type=float, default=10.0)
    parser.add_argument("--idle", type=float, default=3.0)
    parser.add_argument("--timeout", type=float, default=3600.0)
    args = parser.parse_args(rospy.myargv()[1:])
    truth = read_truth(args.bag)

    seen = {"keyframes": [], "loops": [], "path": None, "last": time.time()}

    def on_keyframe(msg):
        seen["keyframes"].append(msg.header.stamp.to_nsec())
        seen["last"] = time.time()

    def on_loop(msg):
        seen["loops"].append(msg)
        seen["last"] = time.time()

    rospy.init_node("bag_monitor", anonymous=True)
    rospy.Subscriber("selected_keyframe_odom", Odometry, on_keyframe, queue_size=1000)
    rospy.Subscriber("loop_closures", LoopClosure, on_loop, queue_size=1000)
    rospy.Subscriber("corrected_path", Path, lambda m: seen.__setitem__("path", m), queue_size=2)
    paths = {}
    rospy.Subscriber("odometry_path", Path, lambda m: paths.__setitem__("odometry", m), queue_size=2)
    start = time.time()
    while not rospy.is_shutdown() and time.time() - start < args.timeout:
        if os.path.exists(args.played) and time.time() - seen["last"] > args.idle:
            break
        time.sleep(0.2)
    deadline = time.time() + 60.0
    while time.time() < deadline and not rospy.is_shutdown() and seen["keyframes"]:
        if seen["path"] is not None and len(seen["path"].poses) >= len(seen["keyframes"]):
            break
        time.sleep(0.5)

    keyframes, loops = seen["keyframes"], seen["loops"]
    verified = sum(1 for loop in loops if loop.verified)
    print("\n%d keyframes selected, %d loops published (%d verified)" % (len(keyframes), len(loops), verified))
    shown = loops if len(loops) <= 20 else loops[:10] + [None] + loops[-10:]
    for loop in shown:
        if loop is None:
            print("  ... %d more ..." % (len(loops) - 20))
            continue
        print("  keyframe %5d -> %5d  at %.2f s -> %.2f s  %s" % (
            loop.query_id, loop.match_id, loop.query_stamp.to_sec(), loop.match_stamp.to_sec(),
            "verified, fitness %.3f" % loop.fitness if loop.verified else "descriptor only"))
    status = 0 if keyframes else 1
    if not keyframes:
        print("no keyframe was selected: the clouds and poses did not reach the node, or it refused them "
              "(the launch log names the reason)")
    path = seen["path"]
    if path is not None:
        print("corrected path: %d poses in %s" % (len(path.poses), path.header.frame_id))
    if truth:
        far = 0
        for loop in loops:
            q, m = truth.get(loop.query_stamp.to_nsec()), truth.get(loop.match_stamp.to_nsec())
            if q is not None and m is not None and math.dist(q, m) > args.radius:
                far += 1
        print("against the bag's ground truth: %d of %d loops join places within %.0f m" % (
            len(loops) - far, len(loops), args.radius))
        status = status or (1 if far else 0)
        if path is not None and "odometry" in paths:
            truth_xyz = {k: v + (0.0,) for k, v in truth.items()}  # path_positions reads [:3]
            rmse = []
            for p in (paths["odometry"], path):
                est, tru = path_positions(p, truth_xyz)
                if len(est) >= 3:
                    rmse.append(math.sqrt(float(np.mean(aligned_error(est, tru) ** 2))))
            if len(rmse) == 2:
                print("trajectory error (positions, rigidly aligned): odometry %.2f m, corrected %.2f m" % tuple(rmse))
    return status


if __name__ == "__main__":
    sys.exit(main())
