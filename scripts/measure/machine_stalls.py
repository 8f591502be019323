#!/usr/bin/env python3
"""Stalls of the machine during a soak or a benchmark, and the slow keyframes and steps they explain.

probe OUT.csv: one process per CPU, pinned to it at real-time priority (SCHED_FIFO when allowed), sleeps
2 ms at a time and records every wake-up that came 3 ms or more late: time the CPU did not run it even
though no task of the machine could hold it off, i.e. the (virtual) CPU itself was not running or had
its interrupts off. Rows: cpu, the monotonic time the wake-up was due [s], how late it came [ms],
whether the probe held real-time priority. Runs until SIGTERM.

attribute KEYFRAMES.csv STALLS.csv: for every keyframe whose queue wait and processing passed 20 ms
(soak_keyframes.csv, with the monitor's receive time), the stall time on any CPU within its interval
(from its queue entry to its timing message's arrival, 20 ms of slack before); prints summary lines:
how many keyframes passed 20 ms, how many of them overlapped a stall, and how many stay over 20 ms once
the overlapping stall time is taken off.

steps BENCH_OUTPUT STALLS.csv: the same for the slowest steps `scan_context_bench` lists.
"""
import csv
import os
import re
import signal
import sys
import time

LIMIT_MS = 20.0
PERIOD_S = 0.002
LATE_MS = 3.0
SLACK_S = 0.020


def probe_cpu(cpu, path):
    os.sched_setaffinity(0, {cpu})
    realtime = 1
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(50))
    except (PermissionError, OSError):
        realtime = 0
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["cpu", "due_s", "late_ms", "realtime"])
        while not stop:
            due = time.monotonic() + PERIOD_S
            time.sleep(PERIOD_S)
            late = (time.monotonic() - due) * 1e3
            if late >= LATE_MS:
                out.writerow([cpu, "%.6f" % due, "%.3f" % late, realtime])
                f.flush()


def probe(path):
    children = []
    for cpu in sorted(os.sched_getaffinity(0)):
        pid = os.fork()
        if pid == 0:
            probe_cpu(cpu, "%s.cpu%d" % (path, cpu))
            os._exit(0)
        children.append((cpu, pid))
    stop = []
    for sig in (signal.SIGTERM, signal.SIGINT):
        signal.signal(sig, lambda *_: stop.append(1))
    while not stop:
        signal.pause()
    for _, pid in children:
        os.kill(pid, signal.SIGTERM)
    for _, pid in children:
        os.waitpid(pid, 0)
    # One file, the CPUs' rows in time order.
    rows = []
    for cpu, _ in children:
        part = "%s.cpu%d" % (path, cpu)
        with open(part) as f:
            rows += list(csv.DictReader(f))
        os.remove(part)
    rows.sort(key=lambda r: float(r["due_s"]))
    with open(path, "w", newline="") as f:
        out = csv.DictWriter(f, fieldnames=["cpu", "due_s", "late_ms", "realtime"])
        out.writeheader()
        out.writerows(rows)


def load_stalls(stalls_path):
    """The probe's stalls as the union of their intervals over the CPUs (a stall of the whole machine
    shows on every CPU at once, and counts once), and whether the probe held real-time priority."""
    with open(stalls_path) as f:
        stalls = [(float(r["due_s"]), float(r["due_s"]) + float(r["late_ms"]) * 1e-3, int(r["realtime"]))
                  for r in csv.DictReader(f)]
    union = []
    for a, b, _ in sorted(stalls):
        if union and a <= union[-1][1]:
            union[-1][1] = max(union[-1][1], b)
        else:
            union.append([a, b])
    return union, all(s[2] for s in stalls)


def stalled_ms(union, start, end):
    return sum(max(0.0, min(b, end) - max(a, start)) for a, b in union) * 1e3


def print_stalls(union, realtime):
    print("machine_stalls: %d of %.0f ms or more on some CPU (%.1f ms in all, longest %.1f ms)%s" % (
        len(union), LATE_MS, sum((b - a) * 1e3 for a, b in union), max([(b - a) * 1e3 for a, b in union] or [0.0]),
        "" if realtime else "; the probe had no real-time priority, so these include the scheduler's own waits"))


def attribute(keyframes_path, stalls_path):
    union, realtime = load_stalls(stalls_path)
    over = overlapped = still_over = 0
    lefts = []
    with open(keyframes_path) as f:
        for r in csv.DictReader(f):
            total = float(r["queue_ms"]) + float(r["processing_ms"])
            if total <= LIMIT_MS or not r.get("received_s"):
                continue
            over += 1
            end = float(r["received_s"])
            stalled = stalled_ms(union, end - total * 1e-3 - SLACK_S, end)
            overlapped += stalled > 0.0
            left = total - stalled
            lefts.append(left)
            still_over += left > LIMIT_MS
    print_stalls(union, realtime)
    print("keyframes_over_%.0f_ms: %d" % (LIMIT_MS, over))
    print("keyframes_over_%.0f_ms_during_a_stall: %d" % (LIMIT_MS, overlapped))
    print("keyframes_over_%.0f_ms_without_the_stalls: %d (the stalls taken off, the longest of them %.1f ms)" % (
        LIMIT_MS, still_over, max(lefts, default=float("nan"))))


def steps(bench_output, stalls_path):
    """The benchmark's slowest steps (`scan_context_bench` prints each one's start on the monotonic
    clock) against the stalls."""
    union, realtime = load_stalls(stalls_path)
    found = []
    with open(bench_output) as f:
        for line in f:
            if "slowest steps:" in line:
                found = [(float(ms), int(k), float(at))
                         for ms, k, at in re.findall(r"([\d.]+) ms \(keyframe (\d+), at ([\d.]+) s", line)]
    print_stalls(union, realtime)
    if not found:
        print("slowest steps: none printed")
        return
    left = [(ms - stalled_ms(union, at, at + ms * 1e-3), ms, k) for ms, k, at in found]
    during = sum(1 for l, ms, _ in left if l < ms)
    worst = max(left)
    print("slowest steps during a machine stall: %d of %d; with the stalls taken off, the slowest %.3f ms "
          "(keyframe %d, %.3f ms in all)" % (during, len(found), worst[0], worst[2], worst[1]))


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "probe":
        probe(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "attribute":
        attribute(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "steps":
        steps(sys.argv[2], sys.argv[3])
    else:
        sys.exit("usage: machine_stalls.py probe OUT.csv | attribute KEYFRAMES.csv STALLS.csv | "
                 "steps BENCH_OUTPUT STALLS.csv")
