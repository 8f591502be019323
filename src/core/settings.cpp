#include "scan_context_loop/core/settings.h"

#include <cmath>

#include "setting_rows.h"

namespace scan_context_loop {

namespace {

using namespace rows;

#define C(expr) SCL_MEMBER(Config, expr)
#define N(expr) SCL_MEMBER(NodeOptions, expr)

std::vector<Setting<Config>> makeConfigSettings() {
  using Cfg = Config;
  return {
      // keyframe input
      boolSetting<Cfg>("cloud_in_world_frame", C(cloud_in_world_frame), "clouds arrive registered in the pose frame"),
      live(doubleSetting<Cfg>("keyframe_min_distance", C(keyframe_min_distance), atLeast(0, " (0 disables)"),
                              "keyframe selection: metres since the last keyframe")),
      live(doubleSetting<Cfg>("keyframe_min_angle", C(keyframe_min_angle), atLeast(0, " (0 disables)"),
                              "keyframe selection: degrees of yaw since the last keyframe")),
      doubleSetting<Cfg>("accumulate_seconds", C(accumulate_seconds), atLeast(0, " (0 disables)"),
                         "a keyframe merges the scans of this many seconds"),
      doubleSetting<Cfg>("accumulate_distance", C(accumulate_distance), atLeast(0, " (0 disables)"),
                         "and of this many metres of path"),
      doubleSetting<Cfg>("new_session_jump", C(new_session_jump), atLeast(0, " (0: never)"),
                         "a stamp this far back [s] starts a new session (3 in a row, or with an odometry jump)"),
      doubleSetting<Cfg>("max_stamp_step", C(max_stamp_step), atLeast(0, " (0: no bound)"),
                         "a stamp this far ahead [s] is refused unless 3 in a row agree"),
      boolSetting<Cfg>("prior_sessions_only", C(prior_sessions_only),
                       "only earlier sessions' keyframes are candidates (relocalization)"),
      doubleSetting<Cfg>("voxel_leaf", C(voxel_leaf), atLeast(0, " (0 disables)"),
                         "voxel filter before describing [m]"),
      live(doubleSetting<Cfg>("covariance_translation", C(covariance_translation), positive(),
                              "x, y, z variance of a yaw-prior-only loop [m^2]")),
      live(doubleSetting<Cfg>("covariance_rotation", C(covariance_rotation), positive(),
                              "roll, pitch variance of a yaw-prior-only loop [rad^2]")),
      // descriptor
      intSetting<Cfg>("num_rings", C(num_rings), closed(1, 1000), "radial bins of the polar grid"),
      intSetting<Cfg>("num_sectors", C(num_sectors), closed(3, 3600), "azimuthal bins of the polar grid"),
      doubleSetting<Cfg>("max_radius", C(max_radius), positive(),
                         "points beyond this horizontal range are ignored [m]"),
      doubleSetting<Cfg>("min_range", C(min_range), atLeast(0),
                         "points closer than this horizontal range are ignored [m]"),
      doubleSetting<Cfg>("lidar_height", C(lidar_height), {}, "added to every z before taking the bin maximum [m]"),
      enumSetting<Cfg, RingKeyType>("ring_key", C(ring_key), parseRingKeyType, ringKeyTypeName,
                                    {RingKeyType::kMeanHeight, RingKeyType::kOccupancy}, "what the ring key holds"),
      formerly({"levelling"},
               enumSetting<Cfg, GravityAlignmentMode>("gravity_alignment", C(gravity_alignment),
                                                      parseGravityAlignmentMode, gravityAlignmentModeName,
                                                      {GravityAlignmentMode::kAuto, GravityAlignmentMode::kPose,
                                                       GravityAlignmentMode::kGround, GravityAlignmentMode::kOff},
                                                      "where each keyframe's gravity alignment comes from")),
      formerly({"levelling_max_tilt"},
               doubleSetting<Cfg>("gravity_alignment_max_tilt", C(gravity_alignment_max_tilt), closed(0, 90),
                                  "auto gravity alignment: a pose tilted more than this is not trusted [deg]")),
      // search
      live(
          intSetting<Cfg>("num_candidates", C(num_candidates), closed(1, 10000), "ring-key neighbours scored in full")),
      intSetting<Cfg>("exact_search_limit", C(exact_search_limit), atLeast(0, " (0: always approximate)"),
                      "databases up to this many keyframes are searched exactly, larger ones approximately"),
      live(doubleSetting<Cfg>("search_ratio", C(search_ratio), closed(0, 1),
                              "column search width around the coarse shift")),
      live(doubleSetting<Cfg>("distance_threshold", C(distance_threshold), openLow(0, 2),
                              "a descriptor match is below this distance")),
      doubleSetting<Cfg>("lateral_offset_step", C(lateral_offset_step), atLeast(0, " (0 disables)"),
                         "spacing of the virtual lateral viewpoints [m]"),
      intSetting<Cfg>("lateral_offset_count", C(lateral_offset_count), closed(1, 10), "virtual viewpoints per side"),
      // exclusion and gate
      intSetting<Cfg>("exclude_recent_frames", C(exclude_recent_frames), atLeast(0, " (0 disables)"),
                      "the most recent keyframes are never candidates"),
      doubleSetting<Cfg>("exclude_recent_seconds", C(exclude_recent_seconds), atLeast(0, " (0 disables)"),
                         "keyframes younger than this are never candidates [s]"),
      doubleSetting<Cfg>("exclude_recent_distance", C(exclude_recent_distance), atLeast(0, " (0 disables)"),
                         "keyframes less than this path behind are never candidates [m]"),
      live(doubleSetting<Cfg>("gate_odometry_distance", C(gate_odometry_distance), atLeast(0, " (0 disables)"),
                              "odometry gate: fixed allowance [m]")),
      live(doubleSetting<Cfg>("gate_odometry_drift", C(gate_odometry_drift), atLeast(0, " (0 disables)"),
                              "odometry gate: allowance per metre of path")),
      // verification
      boolSetting<Cfg>("verify", C(verification.enabled), "verify candidates by registration"),
      live(doubleSetting<Cfg>("verify_threshold", C(verification.threshold), openLow(0, 2),
                              "candidates below this distance are verified")),
      live(intSetting<Cfg>("verify_max_candidates", C(verification.max_candidates), closed(1, 100),
                           "candidates verified per keyframe at most")),
      doubleSetting<Cfg>("verify_max_bytes", C(verification.max_bytes), atLeast(1e6),
                         "memory for the registration data [bytes]"),
      doubleSetting<Cfg>("verify_voxel_leaf", C(verification.voxel_leaf), positive(), "registration voxel edge [m]"),
      doubleSetting<Cfg>("verify_max_range", C(verification.max_range), positive(), "registration crop range [m]"),
      live(doubleSetting<Cfg>("verify_min_inlier_ratio", C(verification.min_inlier_ratio), closed(0, 1),
                              "symmetric structure overlap a loop needs on its own")),
      live(doubleSetting<Cfg>("verify_supported_inlier_ratio", C(verification.supported_inlier_ratio), closed(0, 1),
                              "overlap a loop that needs support must reach")),
      live(doubleSetting<Cfg>("verify_min_column_overlap", C(verification.min_column_overlap), closed(0, 1),
                              "column overlap a loop needs on its own (1: not used)")),
      live(doubleSetting<Cfg>("verify_supported_column_overlap", C(verification.supported_column_overlap),
                              closed(0, 1), "column overlap a loop that needs support must reach (1: not used)")),
      live(doubleSetting<Cfg>("verify_max_fitness", C(verification.max_fitness), positive(),
                              "largest mean squared point-to-plane distance [m^2]")),
      live(doubleSetting<Cfg>("verify_max_violation", C(verification.max_violation), closed(0, 1),
                              "largest free-space violation of a loop on its own")),
      live(doubleSetting<Cfg>("verify_supported_max_violation", C(verification.supported_max_violation), closed(0, 1),
                              "largest free-space violation of a loop that needs support")),
      live(doubleSetting<Cfg>("verify_max_tilt", C(verification.max_tilt), closed(0, 90),
                              "registered tilt above which roll and pitch come from the gravity alignment [deg]")),
      enumSetting<Cfg, RegistrationMethod>(
          "verify_method", C(verification.method), parseRegistrationMethod, registrationMethodName,
          {RegistrationMethod::kVgicp, RegistrationMethod::kGicp, RegistrationMethod::kIcp, RegistrationMethod::kNdt},
          "the fine registration"),
      live(doubleSetting<Cfg>("verify_odometry_rotation", C(verification.odometry_rotation),
                              atLeast(0, " (0 disables)"), "largest disagreement with the odometry's rotation [deg]")),
      live(doubleSetting<Cfg>("verify_odometry_rotation_drift", C(verification.odometry_rotation_drift), atLeast(0),
                              "and per metre of odometry path [deg/m]")),
      intSetting<Cfg>("verify_submap", C(verification.submap), closed(0, 20), "candidate neighbours registered too"),
      boolSetting<Cfg>("verify_allow_degenerate", C(verification.allow_degenerate),
                       "accept loops the scene does not fix along one direction"),
      // consistency
      intSetting<Cfg>("consistency_min_support", C(consistency_min_support), closed(0, 100, " (0 disables)"),
                      "agreeing loops a verified loop needs"),
      intSetting<Cfg>("consistency_window", C(consistency_window), closed(1, 100000),
                      "keyframes a loop waits for support"),
      live(doubleSetting<Cfg>("consistency_translation", C(consistency_translation), positive(),
                              "cycle translation tolerance [m]")),
      live(doubleSetting<Cfg>("consistency_rotation", C(consistency_rotation), positive(),
                              "cycle rotation tolerance [deg]")),
      live(doubleSetting<Cfg>("consistency_drift", C(consistency_drift), atLeast(0), "tolerance per metre of path")),
      // tracking
      live(doubleSetting<Cfg>("track_distance", C(track_distance), atLeast(0),
                              "odometry path a confirmed loop predicts the next keyframes' matches over [m] (0: off)")),
  };
}

std::vector<Setting<NodeOptions>> makeNodeSettings() {
  using O = NodeOptions;
  return {
      enumSetting<O, PoseSource>("pose_source", N(pose_source), parsePoseSource, poseSourceName,
                                 {PoseSource::kOdom, PoseSource::kTf}, "odom: keyframe_odom messages; tf: tf lookups"),
      stringSetting<O>("fixed_frame", N(fixed_frame), {}, "tf mode: the frame poses are looked up in"),
      doubleSetting<O>("tf_timeout", N(tf_timeout), atLeast(0), "tf mode: how long to wait for a transform [s]"),
      stringSetting<O>("sensor_frame", N(sensor_frame), {}, "tf mode: the sensor's frame (empty: the cloud's)"),
      boolSetting<O>("sensor_extrinsic_from_tf", N(sensor_extrinsic_from_tf),
                     "odometry of another frame: extrinsic child <- sensor from tf"),
      boolSetting<O>("approximate_sync", N(approximate_sync), "approximate (true) or exact time synchronisation"),
      intSetting<O>("sync_queue_size", N(sync_queue_size), closed(1, 10000), "message_filters queue per input"),
      intSetting<O>("queue_size", N(queue_size), closed(1, 100000), "keyframes waiting for the worker"),
      intSetting<O>("heap_statistics_interval", N(heap_statistics_interval), closed(0, 100000000),
                    "keyframes between reads of malloc's statistics (0: never)"),
      boolSetting<O>("lio_sam_output", N(lio_sam_output), "also publish LIO-SAM's loop message"),
      live(doubleSetting<O>("lio_sam_min_interval", N(lio_sam_min_interval), atLeast(0),
                       "lio_loop: at most one message per this many seconds")),
      enumSetting<O, NodeMode>("mode", N(mode), parseNodeMode, nodeModeName, {NodeMode::kDetect, NodeMode::kRelocalize},
                               "detect loops, or relocalize in a loaded map"),
      stringSetting<O>("map_frame", N(map_frame), {}, "relocalize: the frame of the loaded map's poses"),
      stringSetting<O>("database_load", N(database_load), {}, "database file loaded at start (empty: none)"),
      stringSetting<O>("database_save", N(database_save), {}, "database file written at shutdown (empty: none)"),
      boolSetting<O>("database_save_overwrite", N(database_save_overwrite),
                     "replace a database_save file this run did not load (false: save beside it)"),
      boolSetting<O>("database_save_clouds", N(database_save_clouds), "saved databases include the registration clouds"),
      doubleSetting<O>("database_autosave_seconds", N(database_autosave_seconds), closed(0, 1e6),
                       "with database_save: also written there this often while it changes [s] (0: at shutdown only)"),
      doubleSetting<O>("database_shutdown_seconds", N(database_shutdown_seconds), closed(0.1, 1e6),
                       "the shutdown save (and the autosave in progress) takes at most this long; the rest is "
                       "cancelled and named in the log [s]"),
      stringSetting<O>("database_directory", N(database_directory), {},
                       "~save_database writes only here (empty: the directory of database_save, else of "
                       "database_load, else $ROS_HOME/scan_context_loop)"),
      stringSetting<O>("robot_id", N(robot_id), {}, "this robot's id in a team: [A-Za-z0-9_], 1-64, the first a letter (empty: no team)"),
      stringSetting<O>("team_namespace", N(team_namespace), {}, "the namespace a team's nodes share"),
      doubleSetting<O>("team_max_bytes_per_second", N(team_max_bytes_per_second), positive(),
                       "what the node sends to its team, on average at most [B/s]"),
      doubleSetting<O>("team_request_timeout", N(team_request_timeout), positive(),
                       "a request to another robot's node fails after this long [s]"),
      doubleSetting<O>("team_max_bytes", N(team_max_bytes), closed(1e6, 1e12),
                       "memory the other robots' keyframe records may take; more are refused [bytes]"),
      doubleSetting<O>("unsynchronised_warning", N(unsynchronised_warning), positive(),
                       "warn when clouds come without poses this long [s]"),
      doubleSetting<O>("no_input_warning", N(no_input_warning), positive(),
                       "warn, naming the topic, when no cloud or odometry came for this long [s]"),
  };
}

#undef N
#undef C

}  // namespace

bool SettingRange::contains(double v) const {
  if (!std::isfinite(v)) return false;
  return (open_low ? v > low : v >= low) && (open_high ? v < high : v <= high);
}

std::string SettingRange::interval() const {
  if (!boundedBelow() && !boundedAbove()) return "any";
  if (!boundedAbove()) return std::string(open_low ? "> " : ">= ") + numberText(low);
  if (!boundedBelow()) return std::string(open_high ? "< " : "<= ") + numberText(high);
  return std::string(open_low ? "(" : "[") + numberText(low) + ", " + numberText(high) + (open_high ? ")" : "]");
}

std::string SettingRange::rule() const {
  std::string r;
  if (!boundedBelow() && !boundedAbove()) {
    r = "must be finite";
  } else if (!boundedBelow() || !boundedAbove()) {
    r = "must be finite and " + interval();
  } else {
    r = "must be in " + interval();
  }
  return r + note;
}

std::string deprecatedKeyWarning(const std::string& old_key, const std::string& key) {
  return old_key + " is deprecated, use " + key;
}

const std::vector<Setting<Config>>& configSettings() {
  static const std::vector<Setting<Config>> table = makeConfigSettings();
  return table;
}

const std::vector<Setting<NodeOptions>>& nodeSettings() {
  static const std::vector<Setting<NodeOptions>> table = makeNodeSettings();
  return table;
}

std::string settingTypeName(SettingType type, const std::vector<std::string>& choices) {
  switch (type) {
    case SettingType::kInt: return "an integer";
    case SettingType::kDouble: return "a number";
    case SettingType::kBool: return "true or false";
    case SettingType::kString: return "a string";
    case SettingType::kChoice: {
      std::string text = "one of";
      for (std::size_t i = 0; i < choices.size(); ++i) text += (i ? ", " : " ") + choices[i];
      return text;
    }
  }
  return "a value";
}

}  // namespace scan_context_loop
