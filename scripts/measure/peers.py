#!/usr/bin/env python3
"""Measures other loop-closure programs ("peers": the published Scan Context code, Contour Context, ...,
built by whoever runs this) beside this package's evaluator on the same sequences, in one run: per
sequence, its scans are read once (so that every program finds them in the page cache), then each run
starts this package's evaluator and then every peer, one after the other, and takes the CPU time (user +
system) of each whole process tree from the kernel (wait4: the process and every child it waited for).
The median over the runs, divided by the sequence's keyframes, is what results_page.py shows.

The peers file has one peer a line, `NAME = COMMAND` (blank lines and `#` comments are skipped). COMMAND
is run by /bin/sh with these placeholders filled in:
  {sequence}   the sequence's folder (KITTI layout: velodyne/%06d.bin, poses.txt, odom_poses.txt, ...)
  {scans}      {sequence}/velodyne
  {keyframes}  the number of scans in it
  {output}     an empty folder of its own for whatever it writes (removed after the run)
A peer that exits non-zero or runs out of time is reported as failed (with its exit status) and gets no
ratio; its output goes to OUT.logs/NAME_SEQUENCE.log either way.

Usage: peers.py --peers FILE --ours 'COMMAND' --out peers.json [--runs 3] [--timeout S] SEQUENCE_DIR...
       peers.py --peers FILE --check    (only reads the peers file)
(scripts/measure/results calls it when SCL_PEERS names a peers file; see doc/benchmark.md.)
"""
import argparse
import glob
import json
import os
import re
import shlex
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading

OURS = "this package"
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9 ._+-]*$")
PLACEHOLDERS = ("sequence", "scans", "keyframes", "output")


def parse_peers(text):
    """[(name, command)] from a peers file's text; raises ValueError naming the bad line."""
    peers = []
    for number, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        name, sep, command = line.partition("=")
        name, command = name.strip(), command.strip()
        if not sep or not NAME.match(name) or not command:
            raise ValueError("line %d: expected NAME = COMMAND, got %r" % (number, line))
        if name == OURS or name in (n for n, _ in peers):
            raise ValueError("line %d: the name %r is taken" % (number, name))
        for field in re.findall(r"{(\w*)}", command):
            if field not in PLACEHOLDERS:
                raise ValueError("line %d: unknown placeholder {%s} (known: %s)" % (
                    number, field, ", ".join("{%s}" % p for p in PLACEHOLDERS)))
        peers.append((name, command))
    if not peers:
        raise ValueError("no peer in the file")
    return peers


def fill(command, values):
    """The command with its placeholders replaced by shell-quoted values."""
    return re.sub(r"{(\w+)}", lambda m: shlex.quote(str(values[m.group(1)])), command)


def run_measured(command, log_path, timeout):
    """Runs `command` with /bin/sh; returns (cpu seconds of its process tree, exit status or None when it
    was stopped at `timeout`)."""
    with open(log_path, "w") as log:
        process = subprocess.Popen(["/bin/sh", "-c", command], stdout=log, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, start_new_session=True)
        timed_out = threading.Event()

        def stop():
            timed_out.set()
            try:
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass

        timer = threading.Timer(timeout, stop)
        timer.start()
        try:
            _, status, usage = os.wait4(process.pid, 0)
        finally:
            timer.cancel()
        code = os.WEXITSTATUS(status) if os.WIFEXITED(status) else -os.WTERMSIG(status)
        process.returncode = code  # reaped by wait4: Popen must not wait for it again
    return usage.ru_utime + usage.ru_stime, (None if timed_out.is_set() else code)


def warm(scans):
    """Reads every scan once, so that no program pays for the disk."""
    for path in scans:
        with open(path, "rb") as f:
            while f.read(1 << 22):
                pass


def measure(sequences, programs, runs, timeout, log_dir):
    """{"runs", "sequences": [{"name", "keyframes", "programs": {name: {"cpu_s": [...], "status"}}}]}."""
    os.makedirs(log_dir, exist_ok=True)
    result = {"runs": runs, "programs": [name for name, _ in programs], "sequences": []}
    for sequence in sequences:
        scans = sorted(glob.glob(os.path.join(sequence, "velodyne", "*.bin")))
        name = os.path.basename(os.path.normpath(sequence))
        entry = {"name": name, "keyframes": len(scans), "programs": {}}
        result["sequences"].append(entry)
        if not scans:
            print("%s: no scans in %s/velodyne, skipped" % (name, sequence), file=sys.stderr)
            continue
        warm(scans)
        for _ in range(runs):
            for program, command in programs:
                slot = entry["programs"].setdefault(program, {"cpu_s": [], "status": 0})
                if slot["status"] != 0:
                    continue  # it failed on this sequence: no more runs of it
                output = tempfile.mkdtemp(prefix="scl_peer_")
                try:
                    values = {"sequence": os.path.abspath(sequence), "scans": os.path.abspath(
                        os.path.join(sequence, "velodyne")), "keyframes": len(scans), "output": output}
                    log = os.path.join(log_dir, re.sub(r"\W", "_", "%s_%s" % (program, name)) + ".log")
                    cpu, status = run_measured(fill(command, values), log, timeout)
                finally:
                    shutil.rmtree(output, ignore_errors=True)
                if status != 0:
                    slot["status"] = "timed out after %g s" % timeout if status is None else status
                    slot["cpu_s"] = []
                    print("%s on %s: %s, see %s" % (program, name, failure(slot["status"]), log), file=sys.stderr)
                    continue
                slot["cpu_s"].append(cpu)
                print("%s on %s: %.2f s CPU" % (program, name, cpu), file=sys.stderr)
    return result


def ms_per_keyframe(entry, program):
    """The median CPU of `program`'s runs on the sequence, in ms a keyframe, or None when it failed."""
    slot = entry["programs"].get(program)
    if not slot or slot["status"] != 0 or not slot["cpu_s"] or not entry["keyframes"]:
        return None
    return 1000.0 * statistics.median(slot["cpu_s"]) / entry["keyframes"]


def ratios(data, peer):
    """This package's CPU over `peer`'s on each sequence where both were measured."""
    out = []
    for entry in data["sequences"]:
        ours, theirs = ms_per_keyframe(entry, OURS), ms_per_keyframe(entry, peer)
        if ours is not None and theirs:
            out.append(ours / theirs)
    return out


def table(data):
    """The results page's Markdown table: a row a sequence, this package's and each peer's CPU a keyframe
    (whole process, median of the runs) and the ratio."""
    peers = [p for p in data["programs"] if p != OURS]
    header = "| sequence | keyframes | this package: CPU a keyframe [ms] |" + "".join(
        " %s: CPU a keyframe [ms] | this package / %s |" % (p, p) for p in peers)
    out = [header, "|---|---|---|" + "---|---|" * len(peers)]
    for entry in data["sequences"]:
        ours = ms_per_keyframe(entry, OURS)
        cells = [entry["name"], str(entry["keyframes"]), cell(entry, OURS)]
        for p in peers:
            theirs = ms_per_keyframe(entry, p)
            cells += [cell(entry, p), "%.2fx" % (ours / theirs) if ours is not None and theirs else "n/a"]
        out.append("| " + " | ".join(cells) + " |")
    return out


def cell(entry, program):
    slot = entry["programs"].get(program)
    if slot is None:
        return "not run"
    if slot["status"] != 0:
        return failure(slot["status"])
    return "%.2f" % ms_per_keyframe(entry, program)


def failure(status):
    """How a program's failed runs are told: its exit status (negative: the signal) or the time-out."""
    return "failed (%s)" % (("exit %d" % status) if isinstance(status, int) else status)


def main():
    a = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    a.add_argument("--peers", required=True, help="the peers file (NAME = COMMAND a line)")
    a.add_argument("--check", action="store_true", help="only check the peers file")
    a.add_argument("--ours", help="this package's evaluator, as a command with the same placeholders")
    a.add_argument("--out", help="the JSON file to write")
    a.add_argument("--runs", type=int, default=3)
    a.add_argument("--timeout", type=float, default=3600.0, help="seconds a run may take")
    a.add_argument("sequences", nargs="*")
    args = a.parse_args()
    try:
        with open(args.peers) as f:
            peers = parse_peers(f.read())
    except (OSError, UnicodeDecodeError, ValueError) as e:
        sys.exit("%s: %s" % (args.peers, e))
    if args.check:
        return 0
    if not args.ours or not args.out or not args.sequences:
        a.error("--ours, --out and at least one sequence are needed")
    if args.runs < 1 or not args.timeout > 0:
        a.error("--runs must be at least 1 and --timeout positive")
    data = measure(args.sequences, [(OURS, args.ours)] + peers, args.runs, args.timeout, args.out + ".logs")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(data, f, indent=1)
    print("\n".join(table(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
