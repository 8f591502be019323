// How far the odometry is trusted between two keyframes, learned from the loops already confirmed.
//
// The odometry checks (the candidate gate, Config::gate_odometry_distance, and the rotation check,
// VerificationConfig::odometry_rotation) compare a loop with what the odometry says of the two keyframes,
// allowing for drift over the odometry path between them. Real odometry can drift far beyond any fixed
// rate or break down (a heading that keeps turning away, a jump); fixed allowances then refuse exactly the
// loops that would repair it. Two things keep the checks useful:
// - Anchors: each confirmed loop relates its two keyframes exactly, so the odometry is relied on only
//   from the query to the nearest confirmed loop and from that loop's match to the candidate. The
//   prediction with the least odometry path is used (the direct one when no loop is nearer).
// - Measured drift: each confirmed loop also says how wrong the direct odometry between its keyframes
//   was. The allowances grow to kMeasuredDriftMargin times the worst drift rate measured so far, so an
//   odometry that proved bad is trusted less.
// Not thread-safe (one owner, like Database).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {

struct Config;
struct Keyframe;
struct VerificationConfig;

/// What the odometry predicts of T_query<-candidate, and the odometry path [m] the prediction relies on.
struct OdometryPrediction {
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  double path = 0.0;
  bool anchored = false;  ///< through a confirmed loop rather than the direct odometry
};

class OdometryTrust {
 public:
  /// Allowances are at least this many times the worst measured drift rate.
  static constexpr double kMeasuredDriftMargin = 1.5;
  /// A loop measures a drift rate only over at least this much odometry path [m] (shorter ones measure
  /// the loop's own error more than the odometry's).
  static constexpr double kMinMeasuredPath = 50.0;

  /// A confirmed loop, T_query<-match = `relative`, between keyframes of one session each (both poses
  /// known). Loops across sessions, or without poses, are ignored.
  void add(const Keyframe& query, const Keyframe& match, const Eigen::Isometry3d& relative);

  /// The odometry's T_query<-candidate for a query at `pose` with odometry path `path` in session
  /// `session`: directly, or through the confirmed loop that leaves the least odometry path. The
  /// candidate must have a pose and be in the query's session.
  OdometryPrediction predict(const Eigen::Isometry3d& pose, double path, std::uint32_t session,
                             const Keyframe& candidate) const;

  /// Worst drift rates measured by confirmed loops: rotation [deg/m] and translation [m/m].
  double rotationRate() const { return rotation_rate_; }
  double translationRate() const { return translation_rate_; }
  std::size_t anchors() const { return anchors_.size(); }

 private:
  struct Anchor {
    Eigen::Isometry3d query_pose, match_pose, relative;
    double query_path = 0.0, match_path = 0.0;
    std::uint32_t query_session = 0, match_session = 0;
  };
  std::vector<Anchor> anchors_;
  double rotation_rate_ = 0.0, translation_rate_ = 0.0;
};

/// The rotation disagreement allowed over `path` metres of odometry [deg]: odometry_rotation plus the
/// larger of odometry_rotation_drift and the measured rate (with its margin) per metre.
double rotationAllowance(const VerificationConfig& config, const OdometryTrust& trust, double path);
/// The candidate gate's radius over `path` metres of odometry [m], likewise from gate_odometry_distance
/// and gate_odometry_drift.
double gateRadius(const Config& config, const OdometryTrust& trust, double path);

}  // namespace scan_context_loop
