#!/usr/bin/env python3
"""The package as a user gets it from `catkin_make install` / `catkin build` with an install space:
only INSTALL/setup.bash is sourced (no devel space, no source tree on any path), then

- `rospack find scan_context_loop` is the install space's share folder, and the simulator, a test-only
  tool, is not installed;
- loop_closure.launch starts the standalone node, and with manager:=NAME the nodelet in a manager; each
  advertises its outputs and services and subscribes to its inputs; the standalone node answers
  `rosservice call /loop_closure/reset` and `rostopic echo -n 1 /diagnostics` (their Python message
  packages are installed);
- with --backend, pose_graph.launch does the same for the reference backend;
- the service types (SaveDatabase, LoadDatabase, Relocalize, SaveMap) are installed: their
  definitions (rossrv) and their Python modules (what rosservice call imports);
- `rosrun scan_context_loop scan_context_evaluate --help` prints the evaluator's usage.

Each check is one test case of the JUnit file --xunit; exits 1 when one fails. A master of its own runs
on a free port, so it can run beside other tests.
"""
import argparse
import os
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from check_report import report  # noqa: E402

LOOP_CLOSURE = {
    "publishes": ["/loop_closures", "/loop_markers", "/loop_closure_pairs", "/keyframe_timing",
                  "/selected_keyframe_odom", "/selected_keyframe_cloud"],
    "subscribes": ["/keyframe_cloud", "/keyframe_odom"],
    "services": ["save_database", "load_database", "reset"],
}
POSE_GRAPH = {
    "publishes": ["/corrected_path", "/odometry_path", "/graph_markers", "/map_cloud"],
    "subscribes": ["/selected_keyframe_odom", "/loop_closures", "/selected_keyframe_cloud"],
    "services": ["publish_map", "save_map"],
}
# What a user types at a running loop_closure node (doc/node.md): services whose types come from other
# packages (std_srvs) and a diagnostics message need those packages' Python modules.
USER_COMMANDS = [
    ["rosservice", "call", "/loop_closure/reset"],
    ["rostopic", "echo", "-n", "1", "/diagnostics"],
]
# The service types a user calls the nodes' services with (rosservice call imports their Python modules).
SERVICE_TYPES = ["SaveDatabase", "LoadDatabase", "Relocalize", "SaveMap"]


def install_environment(install):
    """The environment a shell has after sourcing only INSTALL/setup.bash."""
    clean = {"HOME": os.environ.get("HOME", "/tmp"), "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}
    out = subprocess.check_output(["bash", "-c", 'source "$0/setup.bash" && env -0', install], env=clean)
    env = dict(item.split("=", 1) for item in out.decode().split("\0") if "=" in item)
    return env


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Master:
    def __init__(self, env):
        self.port = free_port()
        # Unbuffered: the launches' output reaches their log files even when they are stopped.
        self.env = dict(env, ROS_MASTER_URI="http://127.0.0.1:%d" % self.port, ROS_HOSTNAME="127.0.0.1",
                        PYTHONUNBUFFERED="1")
        self.process = subprocess.Popen(["rosmaster", "--core", "-p", str(self.port)], env=self.env,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
                                        start_new_session=True)
        self.proxy = xmlrpc.client.ServerProxy(self.env["ROS_MASTER_URI"])
        deadline = time.time() + 20
        while time.time() < deadline:
            try:
                self.proxy.getSystemState("/check_install_space")
                return
            except OSError:
                time.sleep(0.2)
        raise RuntimeError("the master did not come up")

    def state(self):
        code, _, (publishers, subscribers, services) = self.proxy.getSystemState("/check_install_space")
        return ({t: n for t, n in publishers}, {t: n for t, n in subscribers}, {s: n for s, n in services})

    def stop(self):
        stop(self.process)


def stop(process):
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGINT)
        try:
            process.wait(15)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def wait_for_interface(master, node, owner, expected, seconds=40):
    """Errors (empty when OWNER, the node or the manager a nodelet runs in, publishes and subscribes to
    everything EXPECTED lists, and NODE's private services are offered)."""
    deadline = time.time() + seconds
    while True:
        publishers, subscribers, services = master.state()
        errors = []
        errors += ["%s does not publish %s" % (owner, t) for t in expected["publishes"]
                   if owner not in publishers.get(t, [])]
        errors += ["%s does not subscribe to %s" % (owner, t) for t in expected["subscribes"]
                   if owner not in subscribers.get(t, [])]
        errors += ["%s/%s is not offered" % (node, s) for s in expected["services"]
                   if "%s/%s" % (node, s) not in services]
        if not errors or time.time() > deadline:
            return errors
        time.sleep(0.5)


def command_errors(master, commands):
    """Errors of the command-line calls a user makes to a running node (rosservice, rostopic): each must
    exit 0; a missing Python message package (std_srvs for reset) makes rosservice fail."""
    errors = []
    for command in commands:
        try:
            done = subprocess.run(command, env=master.env, capture_output=True, text=True, timeout=60)
        except subprocess.TimeoutExpired:
            errors.append("%s: no answer in 60 s" % " ".join(command))
            continue
        if done.returncode != 0:
            errors.append("%s: exit %d, %s" % (" ".join(command), done.returncode,
                                               (done.stdout + done.stderr).strip()[-300:]))
    return errors


def launch_case(master, log_dir, name, launch, node, expected, extra=(), manager=None, commands=()):
    processes = []
    log = open(os.path.join(log_dir, name + ".log"), "w")
    try:
        if manager:
            processes.append(subprocess.Popen(["rosrun", "nodelet", "nodelet", "manager", "__name:=" + manager],
                                              env=master.env, stdout=log, stderr=subprocess.STDOUT,
                                              start_new_session=True))
        processes.append(subprocess.Popen(["roslaunch", "scan_context_loop", launch] + list(extra),
                                          env=master.env, stdout=log, stderr=subprocess.STDOUT,
                                          start_new_session=True))
        errors = wait_for_interface(master, node, "/" + manager if manager else node, expected)
        if not errors:
            errors += command_errors(master, commands)
        for process in processes:
            if process.poll() is not None:
                errors.append("%s exited with %d" % (" ".join(process.args[:3]), process.returncode))
        if errors:
            errors.append("log: " + log.name)
        return errors
    finally:
        for process in reversed(processes):
            stop(process)
        log.close()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--install", required=True, help="the install space (holds setup.bash)")
    parser.add_argument("--backend", action="store_true", help="the pose-graph backend was built")
    parser.add_argument("--xunit", help="JUnit result file to write")
    parser.add_argument("--logs", help="folder for the launches' output (default: beside --xunit)")
    args = parser.parse_args()
    install = os.path.abspath(args.install)
    log_dir = args.logs or os.path.dirname(os.path.abspath(args.xunit or "install_space.xml"))
    os.makedirs(log_dir, exist_ok=True)

    cases = []
    if not os.path.exists(os.path.join(install, "setup.bash")):
        cases.append(("install_space_exists", ["no setup.bash in %s: install first (catkin_make install)" % install]))
    else:
        env = install_environment(install)
        found = subprocess.run(["rospack", "find", "scan_context_loop"], env=env, capture_output=True, text=True)
        share = os.path.join(install, "share", "scan_context_loop")
        errors = [] if found.stdout.strip() == share else ["rospack finds %r, not %s" % (found.stdout.strip(), share)]
        if os.path.exists(os.path.join(install, "lib", "scan_context_loop", "scan_context_simulate")):
            errors.append("the simulator is installed")
        cases.append(("package_found_in_install_space", errors))

        errors = []
        for srv in SERVICE_TYPES:
            shown = subprocess.run(["rossrv", "show", "scan_context_loop/" + srv], env=env, capture_output=True,
                                   text=True, timeout=60)
            if shown.returncode != 0 or "---" not in shown.stdout:
                errors.append("rossrv show scan_context_loop/%s: exit %d, %s"
                              % (srv, shown.returncode, (shown.stdout + shown.stderr).strip()[:200]))
        imported = subprocess.run(["python3", "-c", "from scan_context_loop.srv import " + ", ".join(SERVICE_TYPES)],
                                  env=env, capture_output=True, text=True, timeout=60)
        if imported.returncode != 0:
            errors.append("the Python service modules: %s" % imported.stderr.strip()[-300:])
        cases.append(("service_types_installed", errors))

        master = Master(env)
        try:
            cases.append(("loop_closure_launch_standalone", launch_case(
                master, log_dir, "loop_closure_standalone", "loop_closure.launch", "/loop_closure", LOOP_CLOSURE,
                commands=USER_COMMANDS)))
            cases.append(("loop_closure_launch_nodelet", launch_case(
                master, log_dir, "loop_closure_nodelet", "loop_closure.launch", "/loop_closure", LOOP_CLOSURE,
                extra=["manager:=install_check_manager"], manager="install_check_manager")))
            if args.backend:
                cases.append(("pose_graph_launch_standalone", launch_case(
                    master, log_dir, "pose_graph_standalone", "pose_graph.launch", "/pose_graph", POSE_GRAPH)))
        finally:
            master.stop()

        evaluate = subprocess.run(["rosrun", "scan_context_loop", "scan_context_evaluate", "--help"], env=env,
                                  capture_output=True, text=True, timeout=60)
        errors = [] if evaluate.returncode == 0 and "usage" in evaluate.stdout.lower() else [
            "rosrun scan_context_loop scan_context_evaluate --help: exit %d, %s" %
            (evaluate.returncode, (evaluate.stdout + evaluate.stderr).strip()[:300])]
        cases.append(("evaluator_runs_with_rosrun", errors))

    return report("install_space", cases, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
