// How the odometry's world frame is tilted from gravity, estimated from the ground under the keyframes.
//
// Gravity-aligning by the pose (gravityAlignmentFromOrientation) assumes the odometry's world frame is z up. LiDAR-only
// odometry (A-LOAM, LeGO-LOAM) and FAST-LIO start their world frame at the first scan's (or IMU's) frame,
// as tilted as the sensor was then; LeGO-LOAM's is y up. Each ground fit says where up is in the sensor
// frame; turned into the world frame with the pose, it says where up is in the odometry's world. Their
// mean over many keyframes is accurate where one fit is not (road camber, slopes and a sparse sensor's
// ground make single fits a degree or two off).
//
// Gravity alignment uses two things of it: the axis of the world frame that points up (z for most stacks, y for
// LeGO-LOAM's camera axes), known exactly from the first fit, so poses in a y-up world are turned into a
// z-up one from the first keyframe on; and the remaining tilt, only to warn about it (within a session it
// is the same for every keyframe, and correcting it by an estimate would add the estimate's error).
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {

class WorldTilt {
 public:
  /// Ground fits needed before the estimate is used, and how far (median) they may scatter around it.
  static constexpr std::size_t kMinFits = 9;
  static constexpr double kMaxScatterDeg = 5.0;
  /// A tilt below this is taken for a gravity-aligned world (the correction stays the identity) [deg].
  static constexpr double kAlignedDeg = 1.0;

  /// A ground fit: `up` in the sensor frame (unit), the pose's orientation world_R_sensor.
  void add(const Eigen::Matrix3d& world_R_sensor, const Eigen::Vector3d& up);
  /// Forgets every fit (a new session: another odometry frame).
  void reset();

  /// The world axis that points up is known (from the first fit within kAxisDeg of one).
  bool axisKnown() const { return axis_known_; }
  /// gravity-ish_R_world: the exact rotation turning that axis onto z (the identity for a z-up world and
  /// until known).
  const Eigen::Matrix3d& axisCorrection() const { return axis_correction_; }
  static constexpr double kAxisDeg = 35.0;

  bool established() const { return established_; }
  /// gravity_R_world: turns the world's estimated up onto z (identity until established, or when the
  /// world is gravity-aligned within kAlignedDeg).
  const Eigen::Matrix3d& correction() const { return correction_; }
  /// The angle between the world's estimated up and its up axis [deg] (0 until established).
  double tiltDeg() const { return established_ ? tilt_deg_ : 0.0; }
  std::size_t fits() const { return count_; }

 private:
  static constexpr std::size_t kRecent = 64;  // fits kept for the scatter
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> recent_;  // a ring of the last kRecent ups in the world frame
  std::size_t count_ = 0;
  bool established_ = false;
  double tilt_deg_ = 0.0;
  Eigen::Matrix3d correction_ = Eigen::Matrix3d::Identity();
  bool axis_known_ = false;
  Eigen::Matrix3d axis_correction_ = Eigen::Matrix3d::Identity();
};

}  // namespace scan_context_loop
