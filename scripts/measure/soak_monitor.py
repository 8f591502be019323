#!/usr/bin/env python3
"""Watches the loop-closure node during scripts/measure/soak, as a user's RViz and backend would, and records
what the soak measures.

- Subscribes to loop_markers (visualization_msgs/MarkerArray) and keeps every marker by (namespace, id),
  as RViz does, so the node builds and sends its markers all through the run.
- keyframe_timing (scan_context_loop/KeyframeTiming): every keyframe's queue wait and processing time,
  and the worker's own CPU time, preemptions and page faults over it.
- loop_closures: the loops published. /diagnostics: the node's counters (dropped, rejected, failed).
- /proc/PID/status of the nodelet manager: VmRSS, sampled every 2 s and at every 1,000 keyframes.

Writes CSV (one row per 1,000 keyframes processed: latency percentiles of that window, resident memory,
counters, load average, the machine's busy fraction), CSV with "_rss" before its extension (every RSS
sample), with "_keyframes" (every keyframe's timing message), with "_loops" (every
loop: ids, verified, distance, relative pose; scripts/measure/soak_check_loops.py scores it), and, when the feeder's
PROGRESS file says all KEYFRAMES were fed and the node has processed all it accounts for (or nothing has
moved for --quiet seconds), SUMMARY (key: value lines). Exits 0, or 1 when the manager died.

usage: soak_monitor.py CSV SUMMARY PROGRESS KEYFRAMES MANAGER_PID [--window 1000] [--quiet 60]"""
import argparse
import csv
import os
import sys
import threading
import time

import numpy as np
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from scan_context_loop.msg import KeyframeTiming, LoopClosure
from visualization_msgs.msg import MarkerArray


def rss_kb(pid):
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def worker_schedstat(pid):
    """(ns on a CPU, ns runnable but waiting for one) of the node's worker thread (named scl_loop_worker),
    from /proc/PID/task/TID/schedstat, or None."""
    try:
        for tid in os.listdir("/proc/%d/task" % pid):
            with open("/proc/%d/task/%s/comm" % (pid, tid)) as f:
                if f.read().strip() != "scl_loop_worker":
                    continue
            with open("/proc/%d/task/%s/schedstat" % (pid, tid)) as f:
                run_ns, wait_ns = f.read().split()[:2]
            return int(run_ns), int(wait_ns)
    except (OSError, ValueError):
        return None
    return None


def cpu_jiffies():
    """(busy, total) jiffies of all CPUs from /proc/stat, or None."""
    try:
        with open("/proc/stat") as f:
            values = [int(v) for v in f.readline().split()[1:]]
    except (OSError, ValueError):
        return None
    idle = values[3] + (values[4] if len(values) > 4 else 0)
    return sum(values) - idle, sum(values)


def read_progress(path):
    try:
        with open(path) as f:
            fed, seconds = f.read().split()
            return int(fed), float(seconds)
    except (OSError, ValueError):
        return 0, 0.0


class Monitor:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.markers = {}
        self.marker_messages = 0
        self.marker_points = 0
        self.loops = 0
        self.loops_verified = 0
        self.diag = {}
        self.processed = 0
        self.last_id = -1
        # The first keyframe's id: 0, or the number of keyframes a map loaded at start holds.
        self.first_id = None
        self.out_of_order = 0
        # (queue_ms, processing_ms, describe_query_ms, verify_ms, queue_length, cpu_ms, preemptions, page_faults)
        self.window = []
        self.all_processing = []
        self.all_cpu = []
        self.all_total = []
        self.start = time.time()
        self.last_activity = time.time()
        self.manager_died = False
        self.rows = []
        self.csv = open(args.csv, "w", newline="")
        self.writer = csv.writer(self.csv)
        self.writer.writerow([
            "keyframes", "elapsed_s", "fed", "database_size", "rss_kb", "latency_p50_ms", "latency_p99_ms",
            "latency_max_ms", "total_p50_ms", "total_p99_ms", "describe_query_p50_ms", "describe_query_p99_ms",
            "verify_p50_ms", "verify_p99_ms", "queue_length_max", "dropped", "rejected", "failed", "loops",
            "loops_verified", "markers_shown", "marker_messages", "registration_bytes", "database_bytes_per_keyframe",
            "heap_allocated_bytes", "heap_free_bytes", "load1", "load5", "load15",
            # The worker thread's CPU time and its time runnable but waiting for a CPU (preempted), per
            # keyframe of the window [ms]: tells the node's own cost from the machine's.
            "worker_cpu_ms_per_keyframe", "worker_runqueue_wait_ms_per_keyframe",
            # From the timing messages: the worker's CPU time per keyframe (p50, p99), the fraction of
            # keyframes preempted at least once, the processing p99 of the keyframes never preempted; and
            # the fraction of the machine's CPU time busy over the window (every process).
            "cpu_p50_ms", "cpu_p99_ms", "preempted_fraction", "unpreempted_latency_p99_ms", "machine_busy",
            # The memory the registration data's arenas hold (their bytes plus each level's unused block end).
            "registration_memory_bytes"])
        self.last_schedstat = None
        self.last_jiffies = cpu_jiffies()
        base, ext = os.path.splitext(args.csv)
        self.rss_csv = open(base + "_rss" + ext, "w", newline="")
        self.rss_writer = csv.writer(self.rss_csv)
        self.rss_writer.writerow(["elapsed_s", "keyframes", "rss_kb"])
        self.keyframes_csv = open(base + "_keyframes" + ext, "w", newline="")
        self.keyframes_writer = csv.writer(self.keyframes_csv)
        self.keyframes_writer.writerow(["keyframe_id", "database_size", "queue_ms", "processing_ms",
                                        "describe_query_ms", "verify_ms", "cpu_ms", "preemptions", "page_faults",
                                        "queue_length", "ground_check_ms", "choose_ms", "detect_ms",
                                        "publish_ms", "received_s"])
        self.loops_csv = open(base + "_loops" + ext, "w", newline="")
        self.loops_writer = csv.writer(self.loops_csv)
        self.loops_writer.writerow(["query_id", "match_id", "verified", "distance", "x", "y", "z", "qx", "qy", "qz",
                                    "qw"])

    # ---- callbacks -----------------------------------------------------------------------------
    def on_markers(self, msg):
        with self.lock:
            for m in msg.markers:
                self.markers[(m.ns, m.id)] = len(m.points)
            self.marker_messages += 1
            self.marker_points += sum(len(m.points) for m in msg.markers)

    def on_loop(self, msg):
        p = msg.relative_pose
        with self.lock:
            self.loops += 1
            self.loops_verified += bool(msg.verified)
            self.loops_writer.writerow([msg.query_id, msg.match_id, int(msg.verified), "%.4f" % msg.distance,
                                        "%.4f" % p.position.x, "%.4f" % p.position.y, "%.4f" % p.position.z,
                                        "%.6f" % p.orientation.x, "%.6f" % p.orientation.y, "%.6f" % p.orientation.z,
                                        "%.6f" % p.orientation.w])

    def on_diagnostics(self, msg):
        for status in msg.status:
            if "loop closure" not in status.name:
                continue
            with self.lock:
                self.diag = {kv.key: kv.value for kv in status.values}
                self.diag["level"] = status.level
                self.diag["message"] = status.message

    def on_timing(self, msg):
        received = time.monotonic()  # the clock of machine_stalls.py's probe
        with self.lock:
            if self.first_id is None:
                self.first_id = msg.keyframe_id
                self.last_id = msg.keyframe_id - 1
            if msg.keyframe_id != self.last_id + 1:
                self.out_of_order += 1
            self.last_id = msg.keyframe_id
            self.processed += 1
            self.last_activity = time.time()
            self.window.append((msg.queue_ms, msg.processing_ms, msg.describe_query_ms, msg.verify_ms,
                                msg.queue_length, msg.cpu_ms, msg.preemptions, msg.page_faults))
            self.keyframes_writer.writerow([msg.keyframe_id, msg.database_size, "%.3f" % msg.queue_ms,
                                            "%.3f" % msg.processing_ms, "%.3f" % msg.describe_query_ms,
                                            "%.3f" % msg.verify_ms, "%.3f" % msg.cpu_ms, msg.preemptions,
                                            msg.page_faults, msg.queue_length, "%.3f" % msg.ground_check_ms,
                                            "%.3f" % msg.choose_ms, "%.3f" % msg.detect_ms,
                                            "%.3f" % msg.publish_ms, "%.6f" % received])
            self.all_processing.append(msg.processing_ms)
            self.all_cpu.append(msg.cpu_ms)
            self.all_total.append(msg.queue_ms + msg.processing_ms)
            if len(self.window) >= self.args.window:
                self.write_row(msg.database_size)

    # ---- output --------------------------------------------------------------------------------
    def diag_int(self, key):
        try:
            return int(float(self.diag.get(key, "0")))
        except ValueError:
            return 0

    def write_row(self, database_size):
        w = np.array(self.window)
        self.window = []
        rss = rss_kb(self.args.pid)
        fed, _ = read_progress(self.args.progress)
        load = os.getloadavg()
        p = lambda col, q: float(np.percentile(w[:, col], q))  # noqa: E731
        total = w[:, 0] + w[:, 1]
        row = [self.processed, round(time.time() - self.start, 1), fed, database_size, rss if rss else "",
               "%.3f" % p(1, 50), "%.3f" % p(1, 99), "%.3f" % w[:, 1].max(),
               "%.3f" % np.percentile(total, 50), "%.3f" % np.percentile(total, 99),
               "%.3f" % p(2, 50), "%.3f" % p(2, 99), "%.3f" % p(3, 50), "%.3f" % p(3, 99), int(w[:, 4].max()),
               self.diag_int("keyframes dropped"), self.diag_int("keyframes rejected"),
               self.diag_int("keyframes and service calls failed (exception)"), self.loops, self.loops_verified,
               sum(self.markers.values()), self.marker_messages, self.diag_int("registration data [bytes]"),
               self.diag_int("database bytes per keyframe"), self.diag_int("heap allocated [bytes]"),
               self.diag_int("heap free [bytes]"), "%.2f" % load[0], "%.2f" % load[1],
               "%.2f" % load[2]]
        sched = worker_schedstat(self.args.pid)
        if sched and self.last_schedstat:
            row += ["%.3f" % ((sched[0] - self.last_schedstat[0]) / 1e6 / len(w)),
                    "%.3f" % ((sched[1] - self.last_schedstat[1]) / 1e6 / len(w))]
        else:
            row += ["", ""]
        self.last_schedstat = sched
        unpreempted = w[w[:, 6] == 0, 1]
        jiffies = cpu_jiffies()
        busy = ""
        if jiffies and self.last_jiffies and jiffies[1] > self.last_jiffies[1]:
            busy = "%.3f" % ((jiffies[0] - self.last_jiffies[0]) / (jiffies[1] - self.last_jiffies[1]))
        self.last_jiffies = jiffies
        row += ["%.3f" % p(5, 50), "%.3f" % p(5, 99), "%.3f" % float(np.mean(w[:, 6] > 0)),
                "%.3f" % np.percentile(unpreempted, 99) if len(unpreempted) else "", busy,
                self.diag_int("registration memory [bytes]")]
        self.writer.writerow(row)
        self.csv.flush()
        self.rows.append(row)
        sys.stderr.write("soak: %6d keyframes, fed %6d, RSS %7.1f MiB, p50 %.1f ms, p99 %.1f ms, loops %d, dropped %d, "
                         "load %.2f, cpu p99 %.1f ms, preempted %.1f%%, busy %s\n" % (
                             self.processed, fed, (rss or 0) / 1024.0, p(1, 50), p(1, 99), self.loops,
                             self.diag_int("keyframes dropped"), load[0], p(5, 99), 100.0 * float(np.mean(w[:, 6] > 0)),
                             busy or "-"))

    def sample_rss(self):
        while not rospy.is_shutdown():
            rss = rss_kb(self.args.pid)
            with self.lock:
                if rss is None:
                    self.manager_died = True
                    return
                self.rss_writer.writerow(["%.1f" % (time.time() - self.start), self.processed, rss])
                self.rss_csv.flush()
            time.sleep(2.0)

    def done(self):
        fed, _ = read_progress(self.args.progress)
        with self.lock:
            accounted = self.processed + self.diag_int("keyframes dropped") + self.diag_int("keyframes rejected")
            if self.manager_died:
                return True
            if fed >= self.args.keyframes and accounted >= fed:
                return True
            return time.time() - self.last_activity > self.args.quiet and fed >= self.args.keyframes

    def summary(self):
        fed, feed_seconds = read_progress(self.args.progress)
        time.sleep(3.0)  # the diagnostics' next update
        with self.lock:
            if self.window:
                self.write_row(self.last_id + 1)
            processing = np.array(self.all_processing) if self.all_processing else np.zeros(1)
            cpu = np.array(self.all_cpu) if self.all_cpu else np.zeros(1)
            lines = {
                "fed": fed,
                "feed_seconds": "%.1f" % feed_seconds,
                "feed_rate_hz": "%.2f" % (fed / feed_seconds if feed_seconds > 0 else 0.0),
                "processed": self.processed,
                "first_keyframe_id": self.first_id if self.first_id is not None else "",
                "keyframe_ids_out_of_order": self.out_of_order,
                "dropped": self.diag_int("keyframes dropped"),
                "rejected": self.diag_int("keyframes rejected"),
                "failed": self.diag_int("keyframes and service calls failed (exception)"),
                "unaccounted": fed - self.processed - self.diag_int("keyframes dropped")
                - self.diag_int("keyframes rejected"),
                # Where the unaccounted ones went: lost before the node (roscpp's subscriber queue), or
                # received without their pose ever pairing with them.
                "clouds_received": self.diag_int("clouds received"),
                "lost_before_the_node": fed - self.diag_int("clouds received"),
                "received_never_paired": self.diag_int("clouds received") - self.diag_int("clouds paired with a pose"),
                "database_size": self.diag.get("database size", ""),
                "database_bytes_per_keyframe": self.diag.get("database bytes per keyframe", ""),
                "registration_bytes_end": self.diag.get("registration data [bytes]", ""),
                "longest_keyframe_ms_diagnostics": self.diag.get("longest keyframe time [ms]", ""),
                "loops": self.loops,
                "loops_verified": self.loops_verified,
                "loops_found_diagnostics": self.diag.get("loops found", ""),
                "markers_shown": sum(self.markers.values()),
                "marker_messages": self.marker_messages,
                "latency_p50_ms_all": "%.3f" % np.percentile(processing, 50),
                "latency_p99_ms_all": "%.3f" % np.percentile(processing, 99),
                "latency_max_ms_all": "%.3f" % processing.max(),
                "cpu_p50_ms_all": "%.3f" % np.percentile(cpu, 50),
                "cpu_p99_ms_all": "%.3f" % np.percentile(cpu, 99),
                "manager_died": int(self.manager_died),
                "manager_rss_kb_end": rss_kb(self.args.pid) or "",
                # With SCL_SOAK_AUTOSAVE: the database saves written while the feed ran, and the last one.
                "database_saves": self.diag_int("database saves"),
                "database_saves_failed": self.diag_int("database saves failed"),
                "last_save_keyframes": self.diag.get("last save [keyframes]", ""),
                "last_save_seconds": self.diag.get("last save written in [s]", ""),
                "diagnostics_level": self.diag.get("level", ""),
                "diagnostics_message": self.diag.get("message", ""),
            }
        with open(self.args.summary, "w") as f:
            for key, value in lines.items():
                f.write("%s: %s\n" % (key, value))
        self.csv.close()
        self.rss_csv.close()
        self.keyframes_csv.close()
        self.loops_csv.close()
        return lines


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("csv")
    parser.add_argument("summary")
    parser.add_argument("progress")
    parser.add_argument("keyframes", type=int)
    parser.add_argument("pid", type=int)
    parser.add_argument("--window", type=int, default=1000)
    parser.add_argument("--quiet", type=float, default=60.0)
    args = parser.parse_args(rospy.myargv()[1:])

    monitor = Monitor(args)
    rospy.init_node("soak_monitor")
    rospy.Subscriber("loop_markers", MarkerArray, monitor.on_markers, queue_size=100)
    rospy.Subscriber("loop_closures", LoopClosure, monitor.on_loop, queue_size=1000)
    rospy.Subscriber("keyframe_timing", KeyframeTiming, monitor.on_timing, queue_size=1000)
    rospy.Subscriber("/diagnostics", DiagnosticArray, monitor.on_diagnostics, queue_size=10)
    threading.Thread(target=monitor.sample_rss, daemon=True).start()
    while not rospy.is_shutdown() and not monitor.done():
        time.sleep(1.0)
    lines = monitor.summary()
    for key, value in lines.items():
        sys.stderr.write("soak: %s: %s\n" % (key, value))
    return 1 if lines["manager_died"] else 0


if __name__ == "__main__":
    sys.exit(main())
