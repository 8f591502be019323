#include "scan_context_loop/graph/pose_graph_settings.h"

#include <algorithm>
#include <sstream>

#include "../core/setting_rows.h"
#include "scan_context_loop/core/team_matcher.h"

namespace scan_context_loop {

namespace {

using namespace rows;

#define G(expr) SCL_MEMBER(PoseGraphConfig, expr)
#define M(expr) SCL_MEMBER(KeyframeMapConfig, expr)
#define O(expr) SCL_MEMBER(PoseGraphOptions, expr)

// The sections of config/pose_graph.yaml, in this order; rows of the three tables share them.
const SettingGroup kGraph{"graph", "graph"};
const SettingGroup kRobots{"robots", "several robots (doc/pose_graph.md#several-robots)"};
const SettingGroup kFrames{"frames", "frames and tf"};
const SettingGroup kMap{"map", "map"};
const SettingGroup kSaving{"saving", "saving the map"};

std::vector<Setting<PoseGraphConfig>> makePoseGraphSettings() {
  using PG = PoseGraphConfig;
  return group<PG>(
      kGraph, {
                  doubleSetting<PG>(
                      "odometry_translation_floor", G(odometry_translation_floor), positive(),
                      "odometry noise per step: translation standard deviation floor [m]",
                      "The standard deviation is this plus odometry_translation_per_metre times the step length."),
                  doubleSetting<PG>("odometry_translation_per_metre", G(odometry_translation_per_metre), atLeast(0),
                                    "growth of the translation standard deviation per metre of the step [m/m]"),
                  doubleSetting<PG>("odometry_rotation_floor", G(odometry_rotation_floor), positive(),
                                    "odometry noise per step: rotation standard deviation floor [rad]",
                                    "0.0005 rad are 0.03 deg; the standard deviation is this plus "
                                    "odometry_rotation_per_metre times the step length plus "
                                    "odometry_rotation_per_radian times the step's rotation angle."),
                  doubleSetting<PG>("odometry_rotation_per_metre", G(odometry_rotation_per_metre), atLeast(0),
                                    "growth of the rotation standard deviation per metre of the step [rad/m]"),
                  doubleSetting<PG>("odometry_rotation_per_radian", G(odometry_rotation_per_radian), atLeast(0),
                                    "growth of the rotation standard deviation per radian the step turns [rad/rad]",
                                    "For an odometry whose heading errs in its turns more than with the metres "
                                    "driven (0: not at all)."),
                  doubleSetting<PG>("loop_robust_scale", G(loop_robust_scale), atLeast(0, " (0: none)"),
                                    "Cauchy loss scale on a loop's whitened residual (0: plain least squares)"),
                  intSetting<PG>("max_iterations", G(max_iterations), atLeast(1), "solver iterations per solve"),
              });
}

std::vector<Setting<KeyframeMapConfig>> makeKeyframeMapSettings() {
  using KM = KeyframeMapConfig;
  return group<KM>(kMap,
                   {
                       // PCL's voxel grid refuses grids of more than 2^31 cells: a map of 10 km at 5 cm would be one.
                       doubleSetting<KM>("map_voxel", M(voxel), closed(0.05, 10),
                                         "voxel edge of the stored clouds and of the map [m]"),
                       doubleSetting<KM>("map_max_range", M(max_range), openLow(0, 1000),
                                         "points beyond this horizontal range from the sensor are not kept [m]"),
                       intSetting<KM>("map_keyframe_stride", M(keyframe_stride), atLeast(1),
                                      "keep the cloud of every n-th keyframe only (1: all)"),
                   });
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string word; in >> word;) out.push_back(word);
  return out;
}

/// "" when `robots` names robots by valid, distinct ids, else the rule it breaks.
std::string robotsRule(const PoseGraphOptions& o) {
  const std::vector<std::string> ids = words(o.robots);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (!validRobotId(ids[i])) return std::string("robot ids must be ") + kRobotIdRule + " (\"" + ids[i] + "\" is not)";
    if (std::find(ids.begin(), ids.begin() + i, ids[i]) != ids.begin() + i)
      return "robot " + ids[i] + " is listed twice";
  }
  if (ids.size() > PoseGraph::kMaxChains) return "at most " + std::to_string(PoseGraph::kMaxChains) + " robots";
  return "";
}

std::string anchorRule(const PoseGraphOptions& o) {
  if (o.anchor_robot.empty()) return "";
  const std::vector<std::string> ids = words(o.robots);
  if (std::find(ids.begin(), ids.end(), o.anchor_robot) == ids.end()) return "must be one of robots";
  return "";
}

std::vector<Setting<PoseGraphOptions>> makePoseGraphNodeSettings() {
  using PO = PoseGraphOptions;
  const auto not_empty = [](const PO& o) { return o.map_frame.empty() ? std::string("must not be empty") : ""; };
  return joined<PO>({
      group<PO>(kGraph,
                {
                    boolSetting<PO>("verified_only", O(verified_only), "only verified loops enter the graph",
                                    "false: unverified ones too, under the robust loss."),
                    doubleSetting<PO>("stamp_tolerance", O(stamp_tolerance), closed(0, 1),
                                      "a loop's and a cloud's stamp match a keyframe's within this [s]"),
                    doubleSetting<PO>("min_solve_interval", O(min_solve_interval), atLeast(0),
                                      "solve at most this often while loops keep coming [s] (0: after every new loop)"),
                    intSetting<PO>("queue_size", O(queue_size), closed(1, 1000000), "events waiting for the worker",
                                   "Keyframes, clouds and loops."),
                }),
      group<PO>(kRobots,
                {
                    alsoCheck<PO>(
                        robotsRule, "valid, distinct robot ids",
                        stringSetting<PO>("robots", O(robots), {},
                                          "several robots: their ids, a list (or one string, separated by spaces); "
                                          "empty: one robot",
                                          "A list (robots: [robot1, robot2, robot3]) or one string; each robot's "
                                          "topics are <robot>/selected_keyframe_odom, ... and the paths "
                                          "<robot>/corrected_path, ...; with one robot the topics are in the node's "
                                          "namespace.")),
                    alsoCheck<PO>(
                        anchorRule, "empty or one of robots",
                        stringSetting<PO>("anchor_robot", O(anchor_robot), {},
                                          "the robot whose odometry frame is the map's (empty: the first of robots)")),
                }),
      group<PO>(
          kFrames,
          {
              alsoCheck<PO>(not_empty, "not empty",
                            stringSetting<PO>("map_frame", O(map_frame), {},
                                              "frame of the corrected poses; tf map_frame -> odometry frame is the "
                                              "correction",
                                              "Also the frame of the map cloud and the paths.")),
              boolSetting<PO>("publish_tf", O(publish_tf), "send the map_frame -> odometry frame transform"),
              doubleSetting<PO>("tf_rate", O(tf_rate), openLow(0, 1000), "how often that transform is sent [Hz]",
                                "Stamped now."),
          }),
      group<PO>(
          kMap,
          {
              boolSetting<PO>("build_map", O(build_map), "keep the keyframe clouds for the map",
                              "false: selected_keyframe_cloud is not subscribed."),
              doubleSetting<PO>("map_period", O(map_period), atLeast(0, " (0: on request only)"),
                                "map_cloud is republished at most this often [s] (0: on the publish_map service only)",
                                "While it has subscribers and the graph changed."),
          }),
      group<PO>(kSaving,
                {
                    stringSetting<PO>("map_directory", O(map_directory), {},
                                      "~save_map writes only here (empty: $ROS_HOME/scan_context_loop/maps)",
                                      "Relative requests name a directory here."),
                    stringSetting<PO>(
                        "map_save", O(map_save), {},
                        "directory the map files are written to at shutdown (absolute, or relative to "
                        "map_directory; empty: none)",
                        "The files: map.pcd, corrected_tum.txt, odometry_tum.txt, corrected_kitti.txt, times.txt, "
                        "pose_graph.g2o."),
                }),
  });
}

#undef O
#undef M
#undef G

}  // namespace

std::vector<std::string> robotIds(const PoseGraphOptions& options) {
  std::vector<std::string> ids = words(options.robots);
  const auto anchor = std::find(ids.begin(), ids.end(), options.anchor_robot);
  if (anchor != ids.end()) std::rotate(ids.begin(), anchor, anchor + 1);  // the anchor first, the rest in order
  return ids;
}

const std::vector<Setting<PoseGraphConfig>>& poseGraphSettings() {
  static const std::vector<Setting<PoseGraphConfig>> table = makePoseGraphSettings();
  return table;
}

const std::vector<Setting<KeyframeMapConfig>>& keyframeMapSettings() {
  static const std::vector<Setting<KeyframeMapConfig>> table = makeKeyframeMapSettings();
  return table;
}

const std::vector<Setting<PoseGraphOptions>>& poseGraphNodeSettings() {
  static const std::vector<Setting<PoseGraphOptions>> table = makePoseGraphNodeSettings();
  return table;
}

}  // namespace scan_context_loop
