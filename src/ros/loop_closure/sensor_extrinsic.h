// The extrinsic child <- sensor that moves odometry of another frame than the sensor's (LeGO-LOAM's camera
// axes, an IMU body) to the sensor, from tf, looked up by the worker without waiting: tf2's canTransform
// with no timeout, once per keyframe at most while it is missing. Each outcome is logged once. Once found,
// it is read again every recheck: a transform that moves is no extrinsic (clouds labelled with a frame
// whose tf moves with the vehicle's pose) and is refused for good.
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <tf2/buffer_core.h>

namespace scan_context_loop {

class SensorExtrinsic {
 public:
  enum class State {
    kKnown,     ///< pose() is child <- sensor (the identity when they are one frame)
    kWaiting,   ///< tf has none yet: hold the keyframe (its pose in the wrong axes would poison the database)
    kFallback,  ///< none came within the wait: the odometry's pose is taken as the sensor's
    kMoving,    ///< tf's child <- sensor changed after it was found: no extrinsic; keyframes are refused
  };
  /// What counts as a change of a fixed transform [m], [rad].
  static constexpr double kMovedMeters = 0.01;
  static constexpr double kMovedRadians = 0.002;

  /// `tf` is read, never waited on; `name` prefixes the logs. The first request starts a wait of
  /// `wait_seconds`; after it, tf is looked at again every `recheck_seconds`.
  SensorExtrinsic(const tf2::BufferCore& tf, std::string name, double wait_seconds, double recheck_seconds);

  /// The extrinsic between normalised frame names at wall time `now` [s]. Found after the fallback, it
  /// applies from then on (a warning says the keyframes before it used the odometry's poses).
  State resolve(const std::string& child, const std::string& sensor, double now);
  const Eigen::Isometry3d& pose() const { return pose_; }
  State state() const { return state_; }

 private:
  /// True, with pose_ set, when tf holds a usable child <- sensor now; else `why` says what is missing.
  bool lookUp(const std::string& child, const std::string& sensor, std::string* why);

  const tf2::BufferCore& tf_;
  std::string name_;
  double wait_seconds_, recheck_seconds_;
  State state_ = State::kWaiting;
  double waiting_since_ = -1.0;  // wall time of the first request; -1 before it
  double next_check_ = 0.0;      // fallback, or found in tf: when tf is looked at again
  bool from_tf_ = false;         // pose_ was read from tf (not the identity of one frame)
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
};

}  // namespace scan_context_loop
