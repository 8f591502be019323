#!/usr/bin/env python3
"""Watches the nodes of scripts/measure/team_soak: each node's resident memory (/proc/PID/status, every
2 s) and its diagnostics. When every node's database holds KEYFRAMES keyframes, or nothing has changed for
60 s, writes SUMMARY: a Markdown table with a row per node and the memory the team costs per keyframe
held (a team node's resident growth beyond the node without a team, over the others' keyframes it holds).
Exits 1 when a node died.

usage: team_soak_monitor.py SUMMARY KEYFRAMES NAME=PID [NAME=PID ...]"""
import sys
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray

KEYS = {
    "database size": "own",
    "team keyframes held": "held",
    "team records memory [bytes]": "records_bytes",
    "registration memory [bytes]": "registration_bytes",
    "team loops": "team_loops",
    "loops found": "loops",
    "team requests timed out": "timed_out",
    "team claims refused (robot id bound to another node)": "claims_refused",
    "team records refused (team_max_bytes)": "over_limit",
    "keyframes dropped": "dropped",
}


def status_kb(pid, key):
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def main():
    args = rospy.myargv()[1:]
    if len(args) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    summary, target = args[0], int(args[1])
    nodes = dict((item.split("=")[0], int(item.split("=")[1])) for item in args[2:])
    values = {name: {} for name in nodes}
    first_rss = {}
    lock = threading.Lock()

    def on_diagnostics(msg):
        with lock:
            for status in msg.status:
                for name in nodes:
                    if status.name.startswith(name + "/loop_closure"):
                        for kv in status.values:
                            if kv.key in KEYS:
                                values[name][KEYS[kv.key]] = float(kv.value)

    rospy.init_node("team_soak_monitor")
    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics, queue_size=100)
    last_change, last_seen, died = time.time(), None, []
    while not rospy.is_shutdown():
        time.sleep(2.0)
        with lock:
            snapshot = {name: dict(v) for name, v in values.items()}
        for name, pid in nodes.items():
            rss = status_kb(pid, "VmRSS")
            if rss is None:
                died.append(name)
            elif name not in first_rss and snapshot[name].get("own", 0) >= 1:
                first_rss[name] = rss
        if died:
            break
        seen = tuple(snapshot[name].get("own", 0) for name in nodes)
        if seen != last_seen:
            last_seen, last_change = seen, time.time()
        if all(v >= target for v in seen) and time.time() - last_change > 10.0:
            break
        if time.time() - last_change > 60.0:
            break
    rows = []
    with lock:
        final = {name: dict(v) for name, v in values.items()}
    end_rss = {name: status_kb(pid, "VmRSS") or 0 for name, pid in nodes.items()}
    peak_rss = {name: status_kb(pid, "VmHWM") or 0 for name, pid in nodes.items()}
    rows.append("| node | own keyframes | others' keyframes held | their records [MB] | registration memory [MB] | "
                "resident at the first keyframe / end / peak [MB] | loops | team loops | requests timed out | "
                "claims refused | dropped |")
    rows.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in nodes:
        v = final[name]
        rows.append("| %s | %d | %d | %.1f | %.1f | %.0f / %.0f / %.0f | %d | %d | %d | %d | %d |" % (
            name, v.get("own", 0), v.get("held", 0), v.get("records_bytes", 0) / 1e6,
            v.get("registration_bytes", 0) / 1e6, first_rss.get(name, 0) / 1024.0, end_rss[name] / 1024.0,
            peak_rss[name] / 1024.0, v.get("loops", 0), v.get("team_loops", 0), v.get("timed_out", 0),
            v.get("claims_refused", 0), v.get("dropped", 0)))
    if "solo" in nodes and "robot1" in nodes and final["robot1"].get("held", 0) > 0:
        solo_growth = (end_rss["solo"] - first_rss.get("solo", 0)) * 1024.0
        own = max(final["solo"].get("own", 1), 1)
        extra = (end_rss["robot1"] - end_rss["solo"]) * 1024.0
        rows.append("")
        rows.append("own keyframe (the node without a team): %.0f B resident each, registration data included" % (
            solo_growth / own))
        rows.append("robot1 beyond it: %.0f B resident for each of the %d others' keyframes it holds "
                    "(their records %.0f B each as accounted)" % (
                        extra / final["robot1"]["held"], final["robot1"]["held"],
                        final["robot1"].get("records_bytes", 0) / final["robot1"]["held"]))
    if died:
        rows.append("died: " + ", ".join(died))
    with open(summary, "w") as f:
        f.write("\n".join(rows) + "\n")
    return 1 if died else 0


if __name__ == "__main__":
    sys.exit(main())
