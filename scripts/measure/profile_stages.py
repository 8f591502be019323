"""Groups a perf report's symbols into the pipeline's stages (called by scripts/measure/profile)."""
import json
import re
import sys

# (stage, substrings of "dso symbol"), first match wins; the order matters where names overlap.
STAGES = [
    ("pose graph (the evaluator's trajectory correction)", ["libscan_context_loop_graph", "ceres", "cholmod", "libcxsparse", "libamd", "libblas", "liblapack"]),
    ("reading scans (file reads, page faults)", ["[kernel", "readScan", "_copy_to_iter", "PointXYZI"]),
    ("gravity alignment (ground fit, turning the cloud)", ["gravityAlignment", "fitGround", "WorldTilt", "sincos", "transformedCloud", "rotatedCloud"]),
    ("descriptor: binning every viewpoint", ["binPoints", "makeHeightGrid", "makeDescriptor", "quantiseUnitColumn"]),
    ("ring-key search and column alignment", ["Database::", "flann", "distanceAtShift", "coarseShift", "alignHypotheses", "scan_context_loop::align(", "align<"]),
    ("registration data (1 m voxels and normals)", ["makeVoxelCloud", "locateBlock", "direct_selfadjoint_eigenvalues", "CloudStore", "atan2", "atanf"]),
    ("registration: coarse search, GICP, acceptance tests", ["alignVoxels", "VoxelIndex", "coarseSearch", "structureMap", "structureColumns", "freeSpace", "FreeSpace", "agreement", "Agreement", "sampleVoxels", "Verifier", "Matrix<double, 6, 6"]),
]
OTHER = "other (allocation, libc, bookkeeping)"


def main():
    report, metrics_path, log_path = sys.argv[1:4]
    shares = {}
    line_re = re.compile(r"^\s*([0-9.]+)%\s+(\S+)\s+\[[.k]\]\s+(.*)$")
    for line in open(report, errors="replace"):
        m = line_re.match(line)
        if not m:
            continue
        share, dso, sym = float(m.group(1)), m.group(2), m.group(3).strip()
        text = dso + " " + sym
        if "[kernel" in dso:
            text = "[kernel " + sym
        stage = next((name for name, keys in STAGES if any(k in text for k in keys)), OTHER)
        shares[stage] = shares.get(stage, 0.0) + share
        if "--symbols" in sys.argv and share >= 0.3:
            print("%6.2f%%  %-55s %s" % (share, stage[:55], text[:110]), file=sys.stderr)
    metrics = json.load(open(metrics_path))
    keyframes = metrics["keyframes"]
    whole = None
    for line in open(log_path):
        m = re.search(r"whole process ([0-9.]+) s", line)
        if m:
            whole = float(m.group(1))
    total = sum(shares.values()) or 1.0
    print("| stage | share of the process CPU | ms a keyframe |")
    print("|---|---|---|")
    for name in [s for s, _ in STAGES] + [OTHER]:
        share = shares.get(name, 0.0) / total
        ms = "%.2f" % (1e3 * whole * share / keyframes) if whole else "n/a"
        print("| %s | %.1f%% | %s |" % (name, 100.0 * share, ms))
    print()
    print("%d keyframes; whole process %s s CPU; scoring (reading, describing, querying, verifying) %.2f ms a "
          "keyframe; verification p99 %.1f ms, max %.1f ms" % (
              keyframes, "%.2f" % whole if whole else "n/a", metrics.get("cpu_ms_per_keyframe", 0.0),
              metrics.get("verified", {}).get("verify_ms", {}).get("p99", 0.0),
              metrics.get("verified", {}).get("verify_ms", {}).get("max", 0.0)))


if __name__ == "__main__":
    main()
