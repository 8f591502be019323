#!/usr/bin/env python3
"""Writes doc/results.md, doc/results_recall.png and README.md's short results table (between
`<!-- results:begin -->` and `<!-- results:end -->`) from the baseline's evaluations (SEQ/eval for the
defaults, SEQ/eval_plain for plain Scan Context), the benchmark's table and, if given, a soak's summary.
Called by scripts/measure/results, which runs them."""
import argparse
import json
import os
import platform
import re
import shutil
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peers as peer_cpu  # noqa: E402

# README's groups of sequences: a row each, with the range over its sequences.
GROUPS = [
    ("KITTI 00 and 08 trajectories (HDL-64E, VLP-16, OS1-64)",
     lambda n: n.startswith(("kitti00_", "kitti08_")) and "livox" not in n),
    ("changed worlds: KITTI 08 and city drives, rush-hour traffic, a tilting sensor (HDL-64E, VLP-16)",
     lambda n: "-changed" in n),
    ("lane offsets and reverse revisits: procedural drive", lambda n: n.startswith("procedural_")),
    ("tilted hand-held sensor, narrow lanes (HDL-64E)", lambda n: n.startswith(("kitti00-tilted_", "narrow_"))),
    ("Livox Avia and Mid-360 (non-repetitive scans)", lambda n: "livox" in n),
]


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def sequence_row(baseline, name):
    seq = os.path.join(baseline, name)
    row = {"name": name, "default": load(os.path.join(seq, "eval", "metrics.json")),
           "plain": load(os.path.join(seq, "eval_plain", "metrics.json")),
           "ate": load(os.path.join(seq, "eval", "trajectory_error.json"))}
    return row


def fmt(value, digits=3):
    return "n/a" if value is None else ("%.*f" % (digits, value))


def span(values, digits=3):
    values = [v for v in values if v is not None]
    if not values:
        return "n/a"
    lo, hi = min(values), max(values)
    return fmt(lo, digits) if abs(hi - lo) < 0.5 * 10 ** -digits else "%s-%s" % (fmt(lo, digits), fmt(hi, digits))


def verified(row, key):
    m = row["default"]
    return None if not m or not m.get("verified") else m["verified"][key]


def plain(row, key="recall_at_100_precision"):
    return None if not row["plain"] else row["plain"][key]


def machine():
    cpu = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    memory = ""
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                memory = ", %.0f GiB" % (int(line.split()[1]) / 2 ** 20)
    except OSError:
        pass
    system = platform.system() + " " + platform.release()
    try:
        for line in open("/etc/os-release"):
            if line.startswith("PRETTY_NAME="):
                system = line.split("=", 1)[1].strip().strip('"') + ", Linux " + platform.release()
    except OSError:
        pass
    return "%s, %d cores%s; %s" % (cpu, os.cpu_count() or 0, memory, system)


def sequence_table(rows):
    out = ["| sequence | revisits | plain Scan Context: F1-max / recall @100% P | defaults, descriptor stage: "
           "F1-max / recall @100% P | defaults, verified: precision / recall / F1 | translation error median / "
           "p90 [m] | yaw error median / p90 [deg] | verification median / p99 / max [ms] |",
           "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        d, p = r["default"], r["plain"]
        if not d:
            out.append("| %s | not evaluated | | | | | | |" % r["name"])
            continue
        v = d.get("verified") or {}
        out.append("| %s | %d | %s | %s / %s | %s / %s / %s | %s / %s | %s / %s | %s / %s / %s |" % (
            r["name"], d["true_revisits"],
            "%s / %s" % (fmt(p["f1_max"]), fmt(p["recall_at_100_precision"])) if p else "not run",
            fmt(d["f1_max"]), fmt(d["recall_at_100_precision"]),
            fmt(v.get("precision")), fmt(v.get("recall")), fmt(v.get("f1")),
            fmt(v["translation_error_m"]["median"], 2) if v else "n/a",
            fmt(v["translation_error_m"]["p90"], 2) if v else "n/a",
            fmt(v["yaw_error_deg"]["median"], 2) if v else "n/a", fmt(v["yaw_error_deg"]["p90"], 2) if v else "n/a",
            fmt(v["verify_ms"]["median"], 1) if v else "n/a", fmt(v["verify_ms"]["p99"], 0) if v else "n/a",
            fmt(v["verify_ms"]["max"], 0) if v else "n/a"))
    return out


def error_pair(t, key):
    """RMSE / max of one of trajectory_error.json's trajectories [m]."""
    return "%s / %s" % (fmt(t[key]["rmse_m"], 2), fmt(t[key]["max_m"], 2)) if key in t else "n/a"


def trajectory_table(rows):
    """Per sequence, the odometry's and the corrected path's absolute trajectory error (trajectory_error.json)."""
    out = ["| sequence | odometry | keyframes | odometry: ATE RMSE / max [m] | corrected with the verified loops: "
           "ATE RMSE / max [m] | loops | corrected / odometry RMSE | plain Scan Context: ATE RMSE / max [m] "
           "(loops, false) | with one false loop added: ATE RMSE / max [m] | oracle loops: ATE RMSE / max [m] "
           "(revisits) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        t = r["ate"]
        if not t or not t.get("computed"):
            out.append("| %s | not computed%s | | | | | | | | |" % (r["name"], ": " + t["note"] if t and t.get("note") else ""))
            continue
        odometry = "the truth" if t.get("odometry_source") == "truth" else "its own (drifting)"
        loops = "%d" % t["loops"]
        if t.get("prior_loops"):
            loops += " (%d into the prior)" % t["prior_loops"]
        share = t["corrected"]["rmse_m"] / t["odometry"]["rmse_m"] if t["odometry"]["rmse_m"] > 0 else None
        out.append("| %s | %s | %d | %s | **%s** | %s | %s | %s (%d, %d) | %s | %s (%s) |" % (
            r["name"], odometry, t["keyframes"], error_pair(t, "odometry"), error_pair(t, "corrected"), loops,
            "n/a" if share is None else "%.0f%%" % (100 * share), error_pair(t, "plain_scan_context"),
            t.get("plain_loops", 0), t.get("plain_false_loops", 0), error_pair(t, "with_one_false_loop"),
            error_pair(t, "oracle"), t.get("oracle_loops", "n/a")))
    return out


def cost_table(rows):
    """Per sequence, the CPU a keyframe costs the whole evaluator process (reading the scan, describing it,
    searching, verifying), with the defaults and with plain Scan Context in the same run."""
    out = ["| sequence | defaults: CPU a keyframe [ms] | descriptors, all viewpoints: median / p99 [ms] | search and insert: "
           "median / p99 [ms] | "
           "plain Scan Context: CPU a keyframe [ms] | defaults / plain |", "|---|---|---|---|---|---|"]
    for r in rows:
        d, p = r["default"], r["plain"]
        if not d or "cpu_ms_per_keyframe" not in d:
            out.append("| %s | not measured | | | | |" % r["name"])
            continue
        ours = d["cpu_ms_per_keyframe"]
        theirs = p.get("cpu_ms_per_keyframe") if p else None
        out.append("| %s | %s | %s / %s | %s / %s | %s | %s |" % (
            r["name"], fmt(ours, 2), fmt(d["descriptor_ms"]["median"]), fmt(d["descriptor_ms"]["p99"]),
            fmt(d["query_ms"]["median"]), fmt(d["query_ms"]["p99"]), fmt(theirs, 2),
            "%.1fx" % (ours / theirs) if theirs else "n/a"))
    return out


def summary_table(rows, peers=None):
    out = ["| sequences | plain Scan Context: recall @100% precision | this package, defaults: verified "
           "precision / recall |", "|---|---|---|"]
    for title, member in GROUPS:
        group = [r for r in rows if member(r["name"])]
        if not group:
            continue
        out.append("| %s | %s | %s / %s |" % (title, span([plain(r) for r in group]),
                                            span([verified(r, "precision") for r in group]),
                                            span([verified(r, "recall") for r in group])))
    measured = [p for p in (peers or {}).get("programs", []) if p != peer_cpu.OURS]
    for p in measured:
        r = peer_cpu.ratios(peers, p)
        out.append("| %s, measured beside it | whole-process CPU a keyframe, this package / %s: %s | |" % (
            p, p, ("%sx (%d sequence%s)" % (span(r, 2), len(r), "" if len(r) == 1 else "s")) if r else "n/a (failed)"))
    if not measured:
        out.append("| Contour Context (ICRA 2023), the published Scan Context code | not on the machine that made "
                   "these figures (`SCL_PEERS` measures them beside this package) | |")
    return out


def peers_section(peers):
    """The page's comparison with other programs (peers.py's output), or how to get one."""
    out = ["", "## Against other programs", ""]
    if not peers:
        return out + [
            "No other program was measured for this page. `SCL_PEERS=FILE scripts/measure/results` runs the "
            "programs FILE names (the published Scan Context code, Contour Context, ...) beside this package's "
            "evaluator on the same sequences and writes this section ([benchmark](benchmark.md#other-programs))."]
    return out + [
        "`scripts/measure/peers.py`, in the same run as the rest of this page: the CPU time (user + system) of "
        "each whole process tree, from start to exit, divided by the sequence's keyframes; this package is its "
        "evaluator with the defaults (reading, describing, searching, verifying, the reference pose graph and "
        "the output files). Each sequence's scans were read once before, and the programs took turns, %d "
        "run%s each; the median is shown ([benchmark](benchmark.md#other-programs))." % (
            peers["runs"], "" if peers["runs"] == 1 else "s"), ""] + peer_cpu.table(peers)


def recall_plot(rows, path):
    names = [r["name"] for r in rows if r["default"]]
    ours = [verified(r, "recall") or 0.0 for r in rows if r["default"]]
    base = [plain(r) or 0.0 for r in rows if r["default"]]
    precision = [verified(r, "precision") for r in rows if r["default"]]
    fig, ax = plt.subplots(figsize=(9, 0.38 * len(names) + 1.2))
    y = range(len(names))
    ax.barh([i + 0.2 for i in y], base, height=0.4, color="#bbbbbb", label="plain Scan Context: recall @100% P")
    ax.barh([i - 0.2 for i in y], ours, height=0.4, color="#2a7ab0", label="defaults, verified: recall")
    for i, p in enumerate(precision):
        if p is not None and p < 1.0:
            ax.text(ours[i] + 0.01, i - 0.2, "precision %.3f" % p, va="center", fontsize=7, color="#b02a2a")
    ax.set_yticks(list(y))
    ax.set_yticklabels(names, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(0, 1.05)
    ax.set_xlabel("recall")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def soak_title(folder):
    """What the soak in `folder` (scripts/measure/soak's output, named K_Rhz[_on_map_N]) was."""
    match = re.match(r"(\d+)_([\d.]+)hz(?:_on_map_(\d+))?$", os.path.basename(os.path.normpath(folder)))
    if not match:
        return "`scripts/measure/soak` (see [testing](testing.md#soak)):"
    keyframes, rate, map_size = match.groups()
    title = "`scripts/measure/soak` (see [testing](testing.md#soak)): %s keyframes fed at %s Hz" % (
        "{:,}".format(int(keyframes)), rate)
    if map_size:
        title += (", the node started on a map of %s keyframes (`SCL_SOAK_MAP=%s`, loaded from its file; the fed "
                  "keyframes' ids start after it)" % ("{:,}".format(int(map_size)), map_size))
    return title + ":"


def replace_between(path, begin, end, lines):
    text = open(path).read()
    start, stop = text.find(begin), text.find(end)
    if start < 0 or stop < start:
        sys.exit("%s has no %s ... %s block" % (path, begin, end))
    start += len(begin)
    with open(path, "w") as f:
        f.write(text[:start] + "\n" + "\n".join(lines) + "\n" + text[stop:])


def main():
    a = argparse.ArgumentParser(description=__doc__)
    a.add_argument("--baseline", required=True)
    a.add_argument("--bench", required=True)
    a.add_argument("--bench-database", default="")
    a.add_argument("--soak", default="")
    a.add_argument("--peers", default="", help="peers.py's output, if other programs were measured")
    a.add_argument("--repo", required=True)
    a.add_argument("sequences", nargs="+")
    args = a.parse_args()
    rows = [sequence_row(args.baseline, n) for n in args.sequences]
    if not any(r["default"] for r in rows):
        sys.exit("no evaluation under %s: run scripts/measure/results without --page first" % args.baseline)
    peers = load(args.peers) if args.peers else None
    doc = os.path.join(args.repo, "doc")
    recall_plot(rows, os.path.join(doc, "results_recall.png"))
    page = ["# Results", "",
            "Generated by `scripts/measure/results` (do not edit by hand) on %s." % machine(), "",
            "Simulated sequences with a keyframe every 2 m and drifting odometry (`scripts/measure/baseline`; "
            "[simulation and evaluation](simulation_and_evaluation.md) says how they are made and scored). "
            "A loop counts as true within 1 m and 2 deg (full rotation) of the truth. *Plain Scan Context* is "
            "the published method's stages alone: the descriptor, the ring-key search and the column shift "
            "(verification, lateral viewpoints, gravity alignment and the odometry gate off).", "",
            "## Summary", ""] + summary_table(rows, peers) + [
            "", "![verified recall per sequence](results_recall.png)", "",
            "## Per sequence", ""] + sequence_table(rows) + [
            "", "## Trajectory error", "",
            "What the loops do to the map: the absolute trajectory error (positions after the best rigid alignment "
            "to the truth) of the odometry's keyframe poses and of the path the reference pose graph corrects with "
            "the verified loops (`trajectory_error.json`; [pose graph](pose_graph.md)), beside plain Scan "
            "Context's loops (each best candidate under the threshold, the yaw prior only) and the verified loops "
            "with one false loop 40-100 m long added as sure as a verified one, and the oracle: every revisit "
            "(an earlier keyframe within the revisit radius, the nearest) at its true relative pose with a verified "
            "loop's covariance at its floors, what the graph makes of every loop there is to find "
            "([what limits the corrected trajectory](pose_graph.md#what-limits-the-corrected-trajectory)).", ""] + trajectory_table(rows) + [
            "", "## Cost per keyframe", "",
            "The CPU time (user + system, every thread) of the evaluator process while it goes through the "
            "sequence, divided by its keyframes: reading each scan (from the page cache: the baseline reads a "
            "sequence's scans once before evaluating it), gravity alignment, the descriptors of the three "
            "viewpoints, the search, the registration data and verification, with the defaults; and the same with "
            "plain Scan Context's stages only, in the same run. The reference pose graph and the output files "
            "come after and are not in it. The descriptor and search columns are wall times per "
            "keyframe with the defaults (the real viewpoint and both lateral ones). [Performance](performance.md) "
            "says where the time goes.", ""] + cost_table(rows) + peers_section(peers)
    bench = open(args.bench).read().strip() if os.path.exists(args.bench) else ""
    page += ["", "## Benchmark", "",
             "`scripts/measure/bench` on the real KITTI scans in `../shared/data`: one thread, the database grown "
             "online to the largest size.", ""]
    page += [bench] if bench else ["Not run (`scripts/measure/bench`)."]
    if args.bench_database and os.path.exists(args.bench_database):
        page += ["", "## Database file", "",
                 "`scripts/measure/bench_database`: saving and loading the database file ([database file]"
                 "(database_file.md)) of the benchmark's largest size, synthetic descriptors from the real scans.", "",
                 open(args.bench_database).read().strip()]
    if args.soak and os.path.exists(os.path.join(args.soak, "summary.txt")):
        page += ["", "## Soak", "", soak_title(args.soak), "", "```",
                 open(os.path.join(args.soak, "summary.txt")).read().strip(), "```"]
        if os.path.exists(os.path.join(args.soak, "soak.png")):
            shutil.copyfile(os.path.join(args.soak, "soak.png"), os.path.join(doc, "soak.png"))
            page += ["", "![soak](soak.png)"]
    with open(os.path.join(doc, "results.md"), "w") as f:
        f.write("\n".join(page) + "\n")
    replace_between(os.path.join(args.repo, "README.md"), "<!-- results:begin -->", "<!-- results:end -->",
                    summary_table(rows, peers))


if __name__ == "__main__":
    main()
