// Keyframe input shared by the node and the evaluator: selection by odometry motion, registered clouds
// moved back into the sensor frame, the voxel filter, and the covariance reported for a loop. Both call
// KeyframePipeline, so an A-LOAM- or LIO-SAM-style input (registered clouds, a voxel filter) evaluates
// offline with the same settings file as the node runs.
#pragma once

#include <deque>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/detector.h"

namespace scan_context_loop {

/// Covariance of loop `loop` in (x, y, z, roll, pitch, yaw): the registration's when it was registered
/// (verified, waiting for support, or rejected with a reason), else diagonal for the descriptor's prior:
/// Config::covariance_translation for x, y, z, covariance_rotation for roll and pitch, and (half a
/// sector)^2 for yaw.
Eigen::Matrix<double, 6, 6> loopCovariance(const Loop& loop, const Config& config);

/// The points of `points` a keyframe's cloud keeps for a map: the finite ones whose horizontal range lies
/// within [Config::min_range, Config::max_radius], the band the descriptor reads, in their order.
pcl::PointCloud<pcl::PointXYZ> keyframeCloud(const PointView& points, const Config& config);

/// Selects, prepares and processes keyframes (Config::keyframe_min_distance / keyframe_min_angle,
/// cloud_in_world_frame, accumulate_seconds / accumulate_distance, voxel_leaf), then runs the
/// LoopDetector. Not thread-safe (one owner).
class KeyframePipeline {
 public:
  explicit KeyframePipeline(const Config& config);
  ~KeyframePipeline();

  /// Processes one keyframe cloud with its info (a registered cloud needs info.pose). A keyframe that
  /// keyframe selection passes over comes back with `selected` false and nothing else changed.
  /// `described`, when given, receives the points of a keyframe that entered the database as they were
  /// described (keyframeCloud): in the sensor frame, voxel-filtered, before gravity alignment.
  Detection process(const PointView& cloud, const KeyframeInfo& info,
                    pcl::PointCloud<pcl::PointXYZ>* described = nullptr);

  /// Applies `config` from the next keyframe on when it differs from the current one in live settings
  /// only (Setting::live: thresholds, gates, keyframe selection, tolerances) and is valid; the database
  /// is kept. Otherwise nothing changes and the result names the problem (the keys that cannot change
  /// while running, or the rules broken).
  std::string reconfigure(const Config& config);

  /// Adds keyframes of earlier runs (a saved database: loadDatabase in database_file.h) as earlier
  /// sessions (LoopDetector::appendSessions). The next keyframe begins a new session, so nothing of the
  /// odometry so far carries over to keyframe selection or scan accumulation, as after a jump back in
  /// time. Returns false and changes nothing when they do not fit (`error` says why).
  bool appendSessions(PriorSessions sessions, std::string* error = nullptr);

  /// LoopDetector::locate: where a cloud is among the stored keyframes, without storing it.
  Detection locate(const PointView& cloud) { return detector_.locate(cloud); }

  /// Keyframes from the next one on form a new session, as when a stamp jumps back
  /// (Config::new_session_jump), for a caller that knows another run begins. Nothing changes while the
  /// current session is empty.
  void startSession();

  const LoopDetector& detector() const { return detector_; }
  const Config& config() const { return detector_.config(); }

 private:
  /// What a keyframe's stamp says about the session (Config::new_session_jump, max_stamp_step).
  enum class StampStep { kGoesOn, kNewSession, kRefused };
  /// A stamp Config::new_session_jump or more before the session's last keyframe, or more than
  /// Config::max_stamp_step after the last cloud's, is believed only on evidence: with a step back,
  /// an odometry pose far from the last cloud's (another odometry run) starts a new session at once;
  /// otherwise kStampJumpEvidence keyframes in a row, in order among themselves, must agree (a bag
  /// played again, a clock back after an outage). The ones before are refused (`why` says why), so a
  /// single bad stamp neither splits the session nor leaves a far-future stamp for the next ones to trip
  /// over.
  StampStep checkStamp(const KeyframeInfo& info, std::string* why);
  /// A new session begins: forgets the last keyframe's pose, the remembered scans and the path.
  void forgetOdometry();
  /// Keyframe selection against the pose of the last keyframe that was processed.
  bool selected(const KeyframeInfo& info) const;

  /// Config::accumulate_*: keeps the scan (in the world frame) and forgets those out of the window.
  void remember(const PointView& cloud, const KeyframeInfo& info);

  LoopDetector detector_;
  // The last cloud whose stamp was believed (selected or not), and the stamp jump waiting for evidence:
  // its direction (-1 back, +1 ahead, 0 none), how many keyframes in a row showed it, the latest stamp.
  bool has_seen_ = false;
  double seen_stamp_ = 0.0;
  std::optional<Eigen::Isometry3d> seen_pose_;
  int jump_direction_ = 0;
  std::size_t jump_count_ = 0;
  double jump_stamp_ = 0.0;
  bool has_last_ = false;
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  // Scan accumulation: the scans of the window, and the odometry path length so far.
  struct Scan;  // keyframes.cpp
  std::deque<std::unique_ptr<Scan>> recent_;
  double path_ = 0.0;
  bool has_previous_ = false;
  Eigen::Isometry3d previous_pose_ = Eigen::Isometry3d::Identity();
};

}  // namespace scan_context_loop
