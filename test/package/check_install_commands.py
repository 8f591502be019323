#!/usr/bin/env python3
"""Checks what the scripts would install on each kind of machine (scripts/common.sh with SCL_DRY_RUN=1,
which prints the install commands instead of running them):

- a ros.org ROS (a stand-in /opt/ros/noetic, SCL_ROS_ROOT): its setup.bash is sourced; package.xml's
  dependencies go through `rosdep install --from-paths ... --rosdistro noetic` on a folder holding a copy
  of package.xml alone; apt installs only packages outside ROS, never one of Debian's ROS packages
  (a second ROS beside ros.org's), nor rviz or the Python messages asked for by name;
- Debian's ROS (no ros.org installation): a missing package goes to apt by its Debian name, and rosdep is
  not used.

Writes a JUnit file (--xunit); exits 1 when a check fails.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from check_report import report  # noqa: E402

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
# Not a package of any archive: always missing, so the install command must name it.
ABSENT = "scl-no-such-package"


def dry_run(ros_root, *packages):
    """(exit status, output) of scl_install_missing PACKAGES with SCL_ROS_ROOT=ros_root, printed only."""
    script = ('source "%s/scripts/common.sh"; echo "sourced=${SCL_FAKE_ROS:-no}"; scl_install_missing %s'
              % (ROOT, " ".join(packages)))
    env = dict(os.environ, SCL_ROS_ROOT=ros_root, SCL_DRY_RUN="1")
    env.pop("SCL_FAKE_ROS", None)
    done = subprocess.run(["bash", "-c", script], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=120)
    return done.returncode, done.stdout


def debian_ros_names():
    out = subprocess.run(["bash", "-c", 'source "%s/scripts/common.sh"; echo "${SCL_DEBIAN_ROS_PACKAGES[@]}"' % ROOT],
                         stdout=subprocess.PIPE, universal_newlines=True, check=True,
                         env=dict(os.environ, SCL_ROS_ROOT="/nonexistent")).stdout
    return set(out.split())


def apt_packages(output):
    names = []
    for line in output.splitlines():
        m = re.match(r"would run: apt-get install (.*)", line)
        if m:
            names += [w for w in m.group(1).split() if not w.startswith("-")]
    return names


def case_ros_org():
    errors = []
    with tempfile.TemporaryDirectory() as tmp:
        ros_root = os.path.join(tmp, "opt", "ros", "noetic")
        os.makedirs(ros_root)
        with open(os.path.join(ros_root, "setup.bash"), "w") as f:
            f.write("export SCL_FAKE_ROS=1\nexport ROS_DISTRO=noetic\n")
        status, out = dry_run(ros_root, "xvfb", "python3-rospy", "rviz", ABSENT)
    if status != 0:
        return ["exit status %d:\n%s" % (status, out)]
    if "sourced=1" not in out:
        errors.append("the ros.org setup.bash was not sourced")
    rosdep = [l for l in out.splitlines() if l.startswith("would run: rosdep install")]
    if len(rosdep) != 1:
        errors.append("%d rosdep install commands, not one:\n%s" % (len(rosdep), out))
    else:
        words = rosdep[0].split()
        if "--rosdistro" not in words or words[words.index("--rosdistro") + 1] != "noetic":
            errors.append("rosdep install without --rosdistro noetic: " + rosdep[0])
        paths = words[words.index("--from-paths") + 1] if "--from-paths" in words else ""
        if not paths or os.path.realpath(paths) == ROOT:
            errors.append("rosdep reads %r, not a folder with a copy of package.xml alone" % paths)
    apt = apt_packages(out)
    if ABSENT not in apt:
        errors.append("the missing tool %s is not installed with apt: %s" % (ABSENT, out))
    leaked = sorted(set(apt) & (debian_ros_names() | {"rviz", "python3-rospy"}))
    if leaked:
        errors.append("apt would install Debian's ROS packages beside ros.org's: %s" % ", ".join(leaked))
    return errors


def case_debian():
    status, out = dry_run("/nonexistent/ros", ABSENT)
    if status != 0:
        return ["exit status %d:\n%s" % (status, out)]
    errors = []
    if ABSENT not in apt_packages(out):
        errors.append("the missing package is not installed with apt:\n" + out)
    if "rosdep" in out:
        errors.append("rosdep is used without a ros.org ROS:\n" + out)
    if "sourced=no" not in out:
        errors.append("a ROS setup.bash was sourced without a ros.org ROS")
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--xunit", help="JUnit result file to write")
    args = parser.parse_args()
    cases = [("ros_org_noetic_through_rosdep", case_ros_org()), ("debian_ros_through_apt", case_debian())]
    return report("install_commands", cases, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
