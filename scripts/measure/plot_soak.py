#!/usr/bin/env python3
"""Draws the soak's plot from scripts/measure/soak's CSV: per-keyframe processing time (p50 and p99 of each
1,000-keyframe window, the p99 with the queue wait, and the p99 of the worker's own CPU time) and the nodelet manager's resident memory over
the keyframes, beside the registration data the node holds, the rest (RSS minus that), and the growth the
database's own bytes per keyframe predict for the rest from 10,000 keyframes on.

usage: plot_soak.py SOAK_CSV OUT_PNG"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    path, out = sys.argv[1], sys.argv[2]
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["rss_kb"]]
    if not rows:
        print("plot_soak: no rows in %s" % path, file=sys.stderr)
        return 1
    n = [int(r["keyframes"]) for r in rows]
    col = lambda key: [float(r[key]) for r in rows]  # noqa: E731
    rss = [x / 1024.0 for x in col("rss_kb")]
    store = [x / 2**20 for x in col("registration_bytes")]
    if rows[0].get("registration_memory_bytes"):
        # The store's arenas are outside the heap, resident as far as they are filled, and go back to the
        # system when a halving drops a level (over the few hundred keyframes that free its clouds): the
        # rest is RSS minus the data held now.
        held = store
    else:
        # Before the arenas, freed registration data stayed in the heap for reuse (RSS did not fall when
        # the store halved): the rest is RSS minus the most the store has held so far.
        held = [max(store[:i + 1]) for i in range(len(store))]
    rest = [a - b for a, b in zip(rss, held)]

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 8), sharex=True)
    top.plot(n, col("latency_p50_ms"), label="processing p50", color="tab:blue")
    top.plot(n, col("latency_p99_ms"), label="processing p99", color="tab:red")
    top.plot(n, col("total_p99_ms"), label="queue wait + processing p99", color="tab:orange", linestyle=":")
    if rows[0].get("cpu_p99_ms"):
        top.plot(n, col("cpu_p99_ms"), label="worker CPU time p99", color="tab:gray", linestyle="--")
    top.set_ylabel("per-keyframe time [ms]\n(each 1,000-keyframe window)")
    top.set_ylim(bottom=0)
    top.grid(alpha=0.3)
    top.legend(loc="upper left")
    # The feed rate between the first and the last window (the monitor starts before the feeder).
    span = float(rows[-1]["elapsed_s"]) - float(rows[0]["elapsed_s"])
    rate = (float(rows[-1]["fed"]) - float(rows[0]["fed"])) / span if span > 0 else 0.0
    top.set_title("scan_context_loop nodelet soak: %d keyframes, fed at %.1f Hz; %s loops, %s dropped" % (
        n[-1], rate, rows[-1]["loops"], rows[-1]["dropped"]))

    bottom.plot(n, rss, label="manager RSS", color="black")
    bottom.plot(n, store, label="registration data held (verify_max_bytes: 1 GiB)", color="tab:green")
    bottom.plot(n, rest, label="RSS minus the registration data", color="tab:purple")
    bpk = col("database_bytes_per_keyframe")
    anchor = next((i for i, k in enumerate(n) if k >= 10000), None)
    if anchor is not None and bpk[-1] > 0:
        expected = [rest[anchor] + (k - n[anchor]) * bpk[-1] / 2**20 for k in n[anchor:]]
        bottom.plot(n[anchor:], expected, label="%d bytes/keyframe (database) from 10k" % bpk[-1],
                    color="tab:purple", linestyle="--")
    bottom.set_xlabel("keyframes processed")
    bottom.set_ylabel("MiB")
    bottom.set_ylim(bottom=0)
    bottom.grid(alpha=0.3)
    bottom.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
