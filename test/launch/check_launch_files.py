#!/usr/bin/env python3
"""Loads the launch files a user starts (loop_closure.launch and the four stack files) with roslaunch's
own loader, without starting anything, and checks what they would start:

- with defaults: one standalone loop-closure node, /loop_closure, remapped to the stack's topics, the
  stack's settings in its private namespace and nowhere else, no RViz, no /use_sim_time;
- renamed (name:=other) in a namespace (ROS_NAMESPACE), in a manager (manager:=mgr), with custom topics,
  use_sim_time:=true and rviz:=true: the nodelet loads into mgr, every setting lands on the renamed node,
  the remaps carry the given topics, /use_sim_time is true, and RViz runs in the node's namespace with
  the stack's fixed frame, config/loop_closure.rviz and the node's topics;
- inside an enclosing <group ns>: the settings follow the node there;
- the order of the layers: the stack's settings over a sensor preset, `overrides` over everything;
- the stacks' settings: gravity_alignment auto everywhere (it measures a world frame that is not gravity
  aligned, A-LOAM's, FAST-LIO's and LeGO-LOAM's, and corrects a y-up one), a 30 s exclusion for
  LIO-SAM; every key of config/stacks/ is a key of config/default.yaml;
- pose_graph.launch loads config/pose_graph.yaml, then `overrides`, then its arguments (and
  loop_closure.launch's pose_graph_overrides reaches it); every launch argument a user sets has a doc;
- config/loop_closure.rviz and config/pose_graph.rviz subscribe only to relative topics and are framed on
  the fixed frame's origin; pose_graph.rviz shows the backend's map, paths and loops; rviz:=true with
  pose_graph:=true starts RViz with it in the frame where the backend's output is whole (map; LIO-SAM's
  odom);
- the backend switch: no backend by default; with pose_graph:=true one pose_graph beside the node (the
  standalone node, or loaded into the node's manager, in its namespace) on the node's selected keyframes
  and loops, with the stack's frames (map_frame, publish_tf: A-LOAM and FAST-LIO send map -> camera_init,
  LeGO-LOAM keeps camera_init under run.launch's map, LIO-SAM under its own map -> odom); map_save:=DIR
  reaches its map_save, and only then, as a string even when it looks like a number (the backend reads it
  strictly); loop_closure.launch's map_directory:=DIR reaches its map_directory the same way.

The package under test is --package (default: the tree holding this file); it is put first on
ROS_PACKAGE_PATH, so the check runs from a plain shell with Debian's python3 and ROS's Python modules:
    /usr/bin/python3 test/launch/check_launch_files.py
Writes a JUnit file (--xunit) with one test case per check; exits 1 when one fails.
"""
import argparse
import contextlib
import glob
import os
import sys
import tempfile

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from check_report import report  # noqa: E402

PACKAGE = "scan_context_loop"

# What each launch file must start with its defaults: the input topics, LIO-SAM's hook, RViz's fixed
# frame, and settings the stack needs (beyond those its config/stacks file lists, all checked).
STACKS = {
    "loop_closure": dict(cloud="keyframe_cloud", odom="keyframe_odom", lio="lio_loop", frame="odom",
                         settings={}),
    "aloam": dict(cloud="/velodyne_cloud_registered", odom="/aft_mapped_to_init", lio="lio_loop",
                  frame="camera_init", settings={"gravity_alignment": "auto", "cloud_in_world_frame": True}),
    "lego_loam": dict(cloud="/full_cloud_projected", odom="/integrated_to_init", lio="lio_loop", frame="map",
                      settings={"gravity_alignment": "auto", "cloud_in_world_frame": False}),
    "lio_sam": dict(cloud="/lio_sam/mapping/cloud_registered_raw", odom="/lio_sam/mapping/odometry",
                    lio="/lio_loop/loop_closure_detection", frame="odom",
                    settings={"gravity_alignment": "auto", "exclude_recent_seconds": 30.0, "lio_sam_output": True,
                              "cloud_in_world_frame": True}),
    "fast_lio": dict(cloud="/cloud_registered_body", odom="/Odometry", lio="lio_loop", frame="camera_init",
                     settings={"gravity_alignment": "auto", "cloud_in_world_frame": False}),
    # Sensor-frame points labelled /camera_init: their real frame named, never taken as registered.
    "sc_aloam": dict(cloud="/velodyne_cloud_registered_local", odom="/aft_mapped_to_init", lio="lio_loop",
                     frame="camera_init", settings={"gravity_alignment": "auto", "cloud_in_world_frame": False,
                                                    "sensor_frame": "aft_mapped"}),
    "hdl_graph_slam": dict(cloud="/filtered_points", odom="/odom", lio="lio_loop", frame="odom",
                           settings={"gravity_alignment": "auto", "cloud_in_world_frame": False}),
}
# The backend each launch file sets up with pose_graph:=true: the frame of its corrected poses and whether
# it sends the tf map_frame -> odometry frame.
BACKEND = {
    "loop_closure": dict(map_frame="map", publish_tf=True),
    "aloam": dict(map_frame="map", publish_tf=True),
    "lego_loam": dict(map_frame="camera_init", publish_tf=False),
    "lio_sam": dict(map_frame="odom", publish_tf=False),
    "fast_lio": dict(map_frame="map", publish_tf=True),
    "sc_aloam": dict(map_frame="map", publish_tf=True),
    "hdl_graph_slam": dict(map_frame="odom", publish_tf=False),  # it sends map -> odom itself
}
# RViz's fixed frame with the backend: where its output is whole (LeGO-LOAM: run.launch's map above camera_init).
BACKEND_RVIZ_FRAME = {"loop_closure": "map", "aloam": "map", "lego_loam": "map", "lio_sam": "odom", "fast_lio": "map",
                      "sc_aloam": "map", "hdl_graph_slam": "odom"}
# What RViz must show with the backend (config/pose_graph.rviz), beside the node's own displays.
BACKEND_DISPLAYS = {"map_cloud", "corrected_path", "odometry_path", "graph_markers", "loop_markers", "keyframe_cloud"}
# The non-default arguments, and the remaps they must give (node's name -> the topic it is remapped to).
CUSTOM_ARGS = ["name:=other", "manager:=mgr", "cloud_topic:=/my/cloud", "odom_topic:=my_odom",
               "loops_topic:=my_loops", "markers_topic:=my_markers", "lio_topic:=my_lio",
               "use_sim_time:=true", "rviz:=true"]
CUSTOM_REMAPS = {"keyframe_cloud": "/my/cloud", "keyframe_odom": "my_odom", "loop_closures": "my_loops",
                 "loop_markers": "my_markers", "lio_loop": "my_lio"}
RVIZ_REMAPS = {"keyframe_cloud": "/my/cloud", "loop_markers": "my_markers"}


@contextlib.contextmanager
def ros_namespace(ns):
    old = os.environ.get("ROS_NAMESPACE")
    if ns is None:
        os.environ.pop("ROS_NAMESPACE", None)
    else:
        os.environ["ROS_NAMESPACE"] = ns
    try:
        yield
    finally:
        if old is None:
            os.environ.pop("ROS_NAMESPACE", None)
        else:
            os.environ["ROS_NAMESPACE"] = old


def load(path=None, args=(), ns=None, text=None):
    """roslaunch's configuration of a launch file (or of launch XML `text`), or the error loading it."""
    import roslaunch.config
    try:
        with ros_namespace(ns), open(os.devnull, "w") as quiet, contextlib.redirect_stdout(quiet):
            if text is not None:
                return roslaunch.config.load_config_default([], None, roslaunch_strs=[text], verbose=False)
            return roslaunch.config.load_config_default([(path, list(args))], None, verbose=False)
    except Exception as e:  # the loader raises several unrelated types; all are a failed check here
        return "cannot load %s %s: %s: %s" % (os.path.basename(path or "XML"), " ".join(args), type(e).__name__, e)


def full_name(node):
    return (node.namespace or "/").rstrip("/") + "/" + node.name


def is_loop_node(node):
    """The standalone node, or the nodelet's loader."""
    if (node.package, node.type) == (PACKAGE, "loop_closure_node"):
        return True
    return (node.package, node.type) == ("nodelet", "nodelet") and "LoopClosureNodelet" in (node.args or "")


def the_loop_node(config, errors):
    nodes = [n for n in config.nodes if is_loop_node(n)]
    if len(nodes) != 1:
        errors.append("%d loop-closure nodes, not one: %s" % (len(nodes), [full_name(n) for n in nodes]))
        return None
    return nodes[0]


def is_backend(node):
    """The reference backend's standalone node, or the nodelet's loader."""
    if (node.package, node.type) == (PACKAGE, "pose_graph_node"):
        return True
    return (node.package, node.type) == ("nodelet", "nodelet") and "PoseGraphNodelet" in (node.args or "")


def load_loop_node(path=None, args=(), ns=None, text=None):
    """(config, the loop node, errors) of a launch file or XML; config and node are None when it did not
    load."""
    config = load(path, args, ns=ns, text=text)
    if isinstance(config, str):
        return None, None, [config]
    errors = []
    return config, the_loop_node(config, errors), errors


def expected_settings(package, stack):
    """The settings the node must get: the stack's file (config/stacks/STACK.yaml), then STACKS'."""
    settings = {}
    path = os.path.join(package, "config", "stacks", stack + ".yaml")
    if stack != "loop_closure" and os.path.exists(path):
        with open(path) as f:
            settings.update(yaml.safe_load(f) or {})
    settings.update(STACKS[stack]["settings"])
    return settings


def check_settings(config, node_ns, settings, errors):
    for key, value in sorted(settings.items()):
        param = config.params.get(node_ns + key)
        if param is None:
            errors.append("%s%s is not set (expected %r)" % (node_ns, key, value))
        elif param.value != value:
            errors.append("%s%s is %r, not %r" % (node_ns, key, param.value, value))


def check_no_stray_params(config, node_ns, errors, allowed=("/use_sim_time", "/run_id", "/rosdistro", "/rosversion")):
    stray = sorted(k for k in config.params if not k.startswith(node_ns) and k not in allowed)
    if stray:
        errors.append("parameters outside the node's namespace %s: %s" % (node_ns, ", ".join(stray[:8])))


def check_remaps(node, expected, errors, what="the node"):
    remaps = dict(node.remap_args)
    for source, target in sorted(expected.items()):
        if remaps.get(source) != target:
            errors.append("%s remaps %s to %r, not %r" % (what, source, remaps.get(source), target))


def option(args, flag):
    words = (args or "").split()
    return words[words.index(flag) + 1] if flag in words[:-1] else None


def case_defaults(package, stack, path):
    config, node, errors = load_loop_node(path)
    if node is None:
        return errors
    if full_name(node) != "/loop_closure":
        errors.append("the node is %s, not /loop_closure" % full_name(node))
    if (node.package, node.type) != (PACKAGE, "loop_closure_node"):
        errors.append("without a manager the node is %s/%s, not the standalone node" % (node.package, node.type))
    s = STACKS[stack]
    check_remaps(node, {"keyframe_cloud": s["cloud"], "keyframe_odom": s["odom"], "lio_loop": s["lio"]}, errors)
    check_settings(config, "/loop_closure/", expected_settings(package, stack), errors)
    check_no_stray_params(config, "/loop_closure/", errors)
    if "/use_sim_time" in config.params:
        errors.append("/use_sim_time is set without use_sim_time:=true")
    if any(n.package == "rviz" for n in config.nodes):
        errors.append("RViz starts without rviz:=true")
    if any(is_backend(n) for n in config.nodes):
        errors.append("the backend starts without pose_graph:=true")
    return errors


def check_backend(config, node, stack, errors, loops="loop_closures", map_params=None):
    """One backend beside `node` (its namespace, its manager if it has one) with the stack's frames and
    `map_params` (map_save, map_directory: the given ones set to exactly these strings, the others unset)."""
    backends = [n for n in config.nodes if is_backend(n)]
    if len(backends) != 1:
        errors.append("%d backends with pose_graph:=true, not one" % len(backends))
        return
    backend = backends[0]
    if backend.namespace != node.namespace:
        errors.append("the backend is in %s, the node in %s" % (backend.namespace, node.namespace))
    manager = (node.args or "").split()[-1:] if node.type == "nodelet" else []
    if manager and (backend.type != "nodelet" or (backend.args or "").split()[-1:] != manager):
        errors.append("the backend is %s '%s', not loaded into the node's manager %s"
                      % (backend.type, backend.args, manager[0]))
    if not manager and backend.type != "pose_graph_node":
        errors.append("without a manager the backend is %s/%s, not the standalone node" % (backend.package, backend.type))
    check_remaps(backend, {"selected_keyframe_odom": "selected_keyframe_odom",
                           "selected_keyframe_cloud": "selected_keyframe_cloud", "loop_closures": loops},
                 errors, "the backend")
    backend_ns = full_name(backend) + "/"
    expected = dict(BACKEND[stack])
    expected.update(map_params or {})
    check_settings(config, backend_ns, expected, errors)
    for key in ("map_save", "map_directory"):
        param = config.params.get(backend_ns + key)
        if key not in expected and param is not None and param.value != "":
            errors.append("%s%s is %r without %s:=DIR" % (backend_ns, key, param.value, key))


def case_backend(package, stack, path):
    """pose_graph:=true beside the standalone node, then in a manager in a namespace with map_save."""
    config, node, errors = load_loop_node(path, ["pose_graph:=true"])
    if node is not None:
        check_backend(config, node, stack, errors)
    # Directory names that look like numbers stay strings.
    map_params = {"map_save": "2024"}
    if stack == "loop_closure":  # the stack files pass map_save on, not map_directory
        map_params["map_directory"] = "1.5"
    config, node, more = load_loop_node(path, ["pose_graph:=true", "manager:=mgr", "name:=other", "loops_topic:=my_loops"]
                                        + ["%s:=%s" % item for item in sorted(map_params.items())], ns="/robot")
    errors += more
    if node is not None:
        check_backend(config, node, stack, errors, loops="my_loops", map_params=map_params)
    # The stack's frames can be changed like any argument.
    config, node, more = load_loop_node(path, ["pose_graph:=true", "pose_graph_map_frame:=world",
                                               "pose_graph_publish_tf:=%s" % str(not BACKEND[stack]["publish_tf"]).lower()])
    errors += more
    if config is not None:
        backend_ns = "/pose_graph/"
        check_settings(config, backend_ns, {"map_frame": "world", "publish_tf": not BACKEND[stack]["publish_tf"]},
                       errors)
    return errors


def case_backend_settings(package):
    """pose_graph.launch loads config/pose_graph.yaml, then `overrides`, then sets its arguments (roslaunch
    puts a node's <param> over its <rosparam>); loop_closure.launch passes pose_graph_overrides on."""
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write("map_voxel: 0.25\nmap_max_range: 80.0\nmap_frame: world\n")
        overrides = f.name
    errors = []
    try:
        path = os.path.join(package, "launch", "pose_graph.launch")
        config = load(path, [])
        if isinstance(config, str):
            return [config]
        with open(os.path.join(package, "config", "pose_graph.yaml")) as f:
            defaults = yaml.safe_load(f)
        check_settings(config, "/pose_graph/", defaults, errors)
        for args, frame in ((["overrides:=" + overrides, "map_frame:=odom"], "odom"),
                            (["manager:=mgr", "overrides:=" + overrides], "map")):
            config = load(path, args)
            if isinstance(config, str):
                return errors + [config]
            check_settings(config, "/pose_graph/", {"map_voxel": 0.25, "map_max_range": 80.0, "map_frame": frame,
                                                    "publish_tf": True}, errors)
        config = load(os.path.join(package, "launch", "loop_closure.launch"),
                      ["pose_graph:=true", "pose_graph_overrides:=" + overrides])
        if isinstance(config, str):
            return errors + [config]
        check_settings(config, "/pose_graph/", {"map_voxel": 0.25, "map_max_range": 80.0}, errors)
    finally:
        os.unlink(overrides)
    return errors


def case_arguments_documented(package):
    """Every argument a user can set (a default, or neither default nor value) says what it does:
    roslaunch --ros-args prints that text; one with an empty default says what empty means."""
    import xml.etree.ElementTree as ET
    errors = []
    for path in sorted(glob.glob(os.path.join(package, "launch", "*.launch"))):
        for arg in ET.parse(path).getroot().findall("arg"):
            if "value" not in arg.attrib and not arg.attrib.get("doc", "").strip():
                errors.append("%s: argument %s has no doc" % (os.path.basename(path), arg.attrib.get("name")))
            # roslaunch --ros-args lists an argument whose default is empty under "Required Arguments": its
            # doc must say what leaving it empty does.
            elif arg.attrib.get("default") == "" and "empty" not in arg.attrib.get("doc", ""):
                errors.append("%s: argument %s (default empty) does not say what empty means"
                              % (os.path.basename(path), arg.attrib.get("name")))
    return errors


def case_renamed(package, stack, path):
    config, node, errors = load_loop_node(path, CUSTOM_ARGS, ns="/robot")
    if node is None:
        return errors
    if full_name(node) != "/robot/other":
        errors.append("the node is %s, not /robot/other" % full_name(node))
    if (node.package, node.type) != ("nodelet", "nodelet") or (node.args or "").split()[-1:] != ["mgr"]:
        errors.append("with manager:=mgr the node is %s/%s '%s', not the nodelet loaded into mgr"
                      % (node.package, node.type, node.args))
    check_remaps(node, CUSTOM_REMAPS, errors)
    check_settings(config, "/robot/other/", expected_settings(package, stack), errors)
    check_no_stray_params(config, "/robot/other/", errors)
    sim = config.params.get("/use_sim_time")
    if sim is None or sim.value is not True:
        errors.append("/use_sim_time is %s with use_sim_time:=true" % (sim.value if sim else "not set"))
    rviz = [n for n in config.nodes if n.package == "rviz"]
    if len(rviz) != 1:
        errors.append("%d RViz nodes with rviz:=true, not one" % len(rviz))
        return errors
    rviz = rviz[0]
    if rviz.namespace != node.namespace:
        errors.append("RViz is in %s, the node in %s" % (rviz.namespace, node.namespace))
    frame = option(rviz.args, "-f")
    if frame != STACKS[stack]["frame"]:
        errors.append("RViz's fixed frame is %r, not %r" % (frame, STACKS[stack]["frame"]))
    display = option(rviz.args, "-d")
    shipped = os.path.join(package, "config", "loop_closure.rviz")
    if display is None or os.path.realpath(display) != os.path.realpath(shipped):
        errors.append("RViz's config is %r, not %s" % (display, shipped))
    check_remaps(rviz, RVIZ_REMAPS, errors, "RViz")
    return errors


def case_in_group(package, stack, path):
    text = ('<launch><group ns="fleet/robot2"><include file="%s"><arg name="name" value="other"/>'
            '</include></group></launch>' % path)
    config, node, errors = load_loop_node(text=text)
    if node is None:
        return errors
    if full_name(node) != "/fleet/robot2/other":
        errors.append("the node is %s, not /fleet/robot2/other" % full_name(node))
    check_settings(config, "/fleet/robot2/other/", expected_settings(package, stack), errors)
    check_no_stray_params(config, "/fleet/robot2/other/", errors)
    return errors


def case_layers(package, stack, path):
    """The stack's settings over a sensor preset (FAST-LIO + Livox: FAST-LIO's 1 m keyframes, the Avia's
    accumulation), `overrides` over everything."""
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write("accumulate_seconds: 7.5\nexclude_recent_frames: 31\n")
        overrides = f.name
    try:
        config = load(path, ["sensor:=livox_avia", "overrides:=" + overrides])
    finally:
        os.unlink(overrides)
    if isinstance(config, str):
        return [config]
    errors = []
    with open(os.path.join(package, "config", "sensors", "livox_avia.yaml")) as f:
        settings = yaml.safe_load(f)  # the preset's ...
    settings.update(expected_settings(package, stack))  # ... under the stack's
    settings.update({"accumulate_seconds": 7.5, "exclude_recent_frames": 31})  # the overrides' last
    if stack == "fast_lio" and settings.get("keyframe_min_distance") != 1.0:
        errors.append("FAST-LIO with the Avia preset: keyframe_min_distance %r, not FAST-LIO's 1.0"
                      % settings.get("keyframe_min_distance"))
    if stack == "loop_closure" and settings.get("keyframe_min_distance") != 2.0:
        errors.append("no stack: keyframe_min_distance %r, not the preset's 2.0" % settings.get("keyframe_min_distance"))
    check_settings(config, "/loop_closure/", settings, errors)
    return errors


def case_stack_settings(package):
    """The per-stack settings that match the stacks' world frames and LIO-SAM's hook."""
    errors = []
    expected = {"aloam": {"gravity_alignment": "auto"}, "fast_lio": {"gravity_alignment": "auto"},
                "lego_loam": {"gravity_alignment": "auto"},
                "lio_sam": {"gravity_alignment": "auto", "exclude_recent_seconds": 30.0},
                "sc_aloam": {"gravity_alignment": "auto", "sensor_frame": "aft_mapped"},
                "hdl_graph_slam": {"gravity_alignment": "auto"}}
    for stack, settings in sorted(expected.items()):
        config = load(os.path.join(package, "launch", stack + ".launch"))
        if isinstance(config, str):
            errors.append(config)
            continue
        stack_errors = []
        check_settings(config, "/loop_closure/", settings, stack_errors)
        errors += ["%s: %s" % (stack, e) for e in stack_errors]
    return errors


def case_stack_keys(package):
    with open(os.path.join(package, "config", "default.yaml")) as f:
        known = set(yaml.safe_load(f))
    errors = []
    folder = os.path.join(package, "config", "stacks")
    files = sorted(n for n in os.listdir(folder) if n.endswith(".yaml")) if os.path.isdir(folder) else []
    if sorted(files) != sorted(s + ".yaml" for s in STACKS if s != "loop_closure"):
        errors.append("config/stacks holds %s, not one file per stack" % files)
    for name in files:
        with open(os.path.join(folder, name)) as f:
            keys = set(yaml.safe_load(f) or {})
        errors += ["config/stacks/%s: %s is not a key of config/default.yaml" % (name, k) for k in sorted(keys - known)]
    return errors


def topics_of(tree, found):
    """Every (key, value) of a parsed RViz config whose key names a topic."""
    if isinstance(tree, dict):
        for key, value in tree.items():
            if "Topic" in str(key) and isinstance(value, str):
                found.append((key, value))
            else:
                topics_of(value, found)
    elif isinstance(tree, list):
        for item in tree:
            topics_of(item, found)
    return found


def case_rviz_config(package):
    errors = []
    for name in ("loop_closure.rviz", "pose_graph.rviz"):
        with open(os.path.join(package, "config", name)) as f:
            tree = yaml.safe_load(f)
        topics = topics_of(tree, [])
        errors += ["%s: %s: %s is absolute: RViz would not follow the node's namespace" % (name, k, v)
                   for k, v in topics if v.startswith("/")]
        if not topics:
            errors.append("%s: no display subscribes to a topic" % name)
        if name == "pose_graph.rviz":
            missing = BACKEND_DISPLAYS - {v for _, v in topics}
            if missing:
                errors.append("%s shows nothing of %s" % (name, ", ".join(sorted(missing))))
        view = tree["Visualization Manager"]["Views"]["Current"]
        centre = [view.get("X", 0), view.get("Y", 0)] if "X" in view else list(
            (view.get("Focal Point") or {}).get(k, 0) for k in ("X", "Y"))
        if any(abs(float(c)) > 1e-6 for c in centre):
            errors.append("%s: the view is centred on %s, not on the fixed frame's origin" % (name, centre))
    return errors


def case_rviz_with_backend(package, stack, path):
    """rviz:=true pose_graph:=true: config/pose_graph.rviz (the corrected map and paths too) in the frame
    where the backend's output is whole; an explicit rviz_config and rviz_fixed_frame still win."""
    errors = []
    for args, display, frame in (
            (["rviz:=true", "pose_graph:=true"], os.path.join(package, "config", "pose_graph.rviz"),
             BACKEND_RVIZ_FRAME[stack]),
            (["rviz:=true", "pose_graph:=true", "rviz_config:=/tmp/mine.rviz", "rviz_fixed_frame:=base"],
             "/tmp/mine.rviz", "base")):
        config = load(path, args)
        if isinstance(config, str):
            return errors + [config]
        rviz = [n for n in config.nodes if n.package == "rviz"]
        if len(rviz) != 1:
            errors.append("%s: %d RViz nodes, not one" % (" ".join(args), len(rviz)))
            continue
        shown = option(rviz[0].args, "-d")
        if shown is None or os.path.realpath(shown) != os.path.realpath(display):
            errors.append("%s: RViz's config is %r, not %s" % (" ".join(args), shown, display))
        if option(rviz[0].args, "-f") != frame:
            errors.append("%s: RViz's fixed frame is %r, not %r" % (" ".join(args), option(rviz[0].args, "-f"), frame))
    return errors


def case_package_found(package):
    import rospkg
    found = rospkg.RosPack().get_path(PACKAGE)
    if os.path.realpath(found) != os.path.realpath(package):
        return ["roslaunch finds %s at %s, not the tree under test %s" % (PACKAGE, found, package)]
    return []


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--package", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."),
                        help="the package's folder (holds package.xml)")
    parser.add_argument("--xunit", help="JUnit result file to write")
    args = parser.parse_args()
    package = os.path.realpath(args.package)
    # $(find scan_context_loop) in the launch files resolves to the tree under test.
    os.environ["ROS_PACKAGE_PATH"] = os.pathsep.join([package] + [p for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p])

    cases = [("package_found", case_package_found(package))]
    for stack in STACKS:
        path = os.path.join(package, "launch", stack + ".launch")
        cases.append(("%s_defaults" % stack, case_defaults(package, stack, path)))
        cases.append(("%s_renamed_in_namespace_with_manager_rviz_sim_time" % stack, case_renamed(package, stack, path)))
        cases.append(("%s_in_enclosing_group" % stack, case_in_group(package, stack, path)))
        cases.append(("%s_stack_over_preset_overrides_last" % stack, case_layers(package, stack, path)))
        cases.append(("%s_backend_switch_frames_manager_map_save" % stack, case_backend(package, stack, path)))
        cases.append(("%s_rviz_with_backend" % stack, case_rviz_with_backend(package, stack, path)))
    cases.append(("stack_gravity_alignment_and_lio_sam_exclusion", case_stack_settings(package)))
    cases.append(("stack_settings_use_known_keys", case_stack_keys(package)))
    cases.append(("rviz_config_relative_topics_origin_view", case_rviz_config(package)))
    cases.append(("backend_config_arguments_then_overrides", case_backend_settings(package)))
    cases.append(("every_launch_argument_documented", case_arguments_documented(package)))
    return report("launch_files", cases, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
