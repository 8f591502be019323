#!/usr/bin/env python3
"""Checks package.xml the way `rosdep install --from-paths` and a Noetic build read it, offline.

- Every dependency is a rosdep key that resolves on Ubuntu 20.04 (focal) or a package released into
  Noetic (rosdep's base.yaml and python.yaml, Noetic's distribution.yaml, from --rosdep DIR).
- Every ROS package the build finds (find_package(catkin COMPONENTS ...) in CMakeLists.txt, the
  find_package(NAME REQUIRED) calls of cmake/*.cmake and sim/CMakeLists.txt) is a build dependency.
- Every package a shipped launch file starts is an exec dependency; a viewer (RViz) is started only on
  request and declared with a condition, so that `rosdep install` does not pull it onto a robot.
- The checks themselves reject a wrong package.xml (an unknown key, an undeclared component).

Writes a JUnit file (--xunit) with one test case per check; exits 1 when one fails.
"""
import argparse
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from check_report import report  # noqa: E402

DEPENDENCY_TAGS = ("depend", "build_depend", "build_export_depend", "buildtool_depend", "exec_depend",
                   "test_depend", "doc_depend")
BUILD_TAGS = ("depend", "build_depend", "buildtool_depend")
EXEC_TAGS = ("depend", "exec_depend")
PLATFORM = ("ubuntu", "focal")
# Viewers: the launch files start them only on request, and package.xml declares them with a condition.
VIEWERS = {"rviz"}


def read_dependencies(package_xml_text):
    """[(tag, name, condition)] of a package.xml's text."""
    root = ET.fromstring(package_xml_text)
    return [(child.tag, (child.text or "").strip(), child.get("condition"))
            for child in root if child.tag in DEPENDENCY_TAGS]


def load_index(rosdep_dir):
    keys = {}
    for name in ("base.yaml", "python.yaml"):
        with open(os.path.join(rosdep_dir, name)) as f:
            keys.update(yaml.safe_load(f))
    with open(os.path.join(rosdep_dir, "noetic-distribution.yaml")) as f:
        distribution = yaml.safe_load(f)
    packages = set()
    for repo, entry in distribution.get("repositories", {}).items():
        release = entry.get("release")
        if release is None:
            continue
        packages.update(release.get("packages", [repo]))
    return keys, packages


def rule_resolves(rule, codename):
    """Whether rosdep's rule for one OS installs something on `codename` (None: not available)."""
    if rule is None:
        return False
    if isinstance(rule, list):
        return True
    if isinstance(rule, dict):
        if any(k in rule for k in ("packages", "apt", "pip", "source")):
            return True
        for version in (codename, "*"):
            if version in rule:
                return rule[version] is not None
    return False


def check_keys(dependencies, keys, packages):
    errors = []
    for tag, name, _ in dependencies:
        if name in packages:
            continue
        if name not in keys:
            errors.append("<%s>%s</%s> is neither a rosdep key nor a package released into Noetic"
                          % (tag, name, tag))
        elif not rule_resolves(keys[name].get(PLATFORM[0]), PLATFORM[1]):
            errors.append("rosdep key %s has no rule for %s %s" % (name, PLATFORM[0], PLATFORM[1]))
    return errors


def build_components(package_dir):
    """The ROS packages the CMake build finds."""
    found = set()
    with open(os.path.join(package_dir, "CMakeLists.txt")) as f:
        top = f.read()
    for block in re.findall(r"set\(SCL_ROS_COMPONENTS(.*?)\)", top, re.S):
        found.update(block.split())
    for block in re.findall(r"find_package\(catkin REQUIRED COMPONENTS(.*?)\)", top, re.S):
        found.update(w for w in block.split() if not w.startswith("$"))
    files = glob.glob(os.path.join(package_dir, "cmake", "*.cmake")) + [os.path.join(package_dir, "sim", "CMakeLists.txt")]
    for path in files:
        if os.path.exists(path):
            with open(path) as f:
                found.update(re.findall(r"find_package\((\w+) REQUIRED\)", f.read()))
    return found


def check_build_components(dependencies, components, packages):
    declared = {name for tag, name, _ in dependencies if tag in BUILD_TAGS + ("test_depend",)}
    return ["the build finds %s, which package.xml does not declare as a build or test dependency" % c
            for c in sorted(components) if c in packages and c not in declared]


def launch_nodes(package_dir):
    """[(launch file name, pkg, whether the node is optional: an `if` or `unless` attribute)]."""
    nodes = []
    for path in sorted(glob.glob(os.path.join(package_dir, "launch", "*.launch"))):
        for node in ET.parse(path).getroot().iter("node"):
            nodes.append((os.path.basename(path), node.get("pkg"), "if" in node.attrib or "unless" in node.attrib))
    return nodes


def check_launch_dependencies(dependencies, nodes, self_name):
    errors = []
    exec_deps = {name: condition for tag, name, condition in dependencies if tag in EXEC_TAGS}
    for launch, pkg, optional in nodes:
        if pkg == self_name:
            continue
        if pkg not in exec_deps:
            errors.append("%s starts %s, which is not an exec dependency" % (launch, pkg))
        elif pkg in VIEWERS and not optional:
            errors.append("%s always starts %s: a viewer is started only on request (an if= argument)" % (launch, pkg))
    for pkg in sorted(VIEWERS & set(exec_deps)):
        if not exec_deps[pkg]:
            errors.append("%s is an unconditional exec dependency: rosdep would put a viewer on every robot" % pkg)
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--package", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    parser.add_argument("--rosdep", required=True, help="folder with base.yaml, python.yaml, noetic-distribution.yaml")
    parser.add_argument("--xunit", help="JUnit result file to write")
    args = parser.parse_args()

    with open(os.path.join(args.package, "package.xml")) as f:
        text = f.read()
    keys, packages = load_index(args.rosdep)
    dependencies = read_dependencies(text)
    name = ET.fromstring(text).findtext("name")
    components = build_components(args.package)
    nodes = launch_nodes(args.package)

    # A package.xml with an unknown key and one without a component the build finds must both fail.
    unknown = read_dependencies(text.replace("</package>", "<depend>flann</depend></package>"))
    component = sorted(c for c in components if c in packages)[0]
    undeclared = [d for d in dependencies if d[1] != component]
    cases = [
        ("dependencies_resolve_on_noetic", check_keys(dependencies, keys, packages)),
        ("build_finds_only_declared_packages", check_build_components(dependencies, components, packages)),
        ("launch_files_start_declared_packages", check_launch_dependencies(dependencies, nodes, name)),
        ("check_rejects_an_unknown_key",
         [] if any("flann" in e for e in check_keys(unknown, keys, packages)) else ["flann was accepted"]),
        ("check_rejects_an_undeclared_component",
         [] if check_build_components(undeclared, components, packages) else ["%s was not missed" % component]),
    ]
    return report("package_xml", cases, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
