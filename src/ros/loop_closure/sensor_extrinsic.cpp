#include "loop_closure/sensor_extrinsic.h"

#include <cmath>
#include <utility>

#include <ros/console.h>
#include <tf2/exceptions.h>

#include "shared/pose_input.h"

namespace scan_context_loop {

SensorExtrinsic::SensorExtrinsic(const tf2::BufferCore& tf, std::string name, double wait_seconds,
                                 double recheck_seconds)
    : tf_(tf), name_(std::move(name)), wait_seconds_(wait_seconds), recheck_seconds_(recheck_seconds) {}

bool SensorExtrinsic::lookUp(const std::string& child, const std::string& sensor, std::string* why) {
  // Neither call waits: canTransform without a timeout answers from what tf holds, and the latest
  // transform (time 0) of a fixed extrinsic is the one to use, whether it came once on /tf_static or
  // keeps coming on /tf as tf1's static_transform_publisher sends it.
  if (!tf_.canTransform(child, sensor, ros::Time(0), why)) return false;
  try {
    const geometry_msgs::TransformStamped t = tf_.lookupTransform(child, sensor, ros::Time(0));
    if (poseFromMsg(t.transform, &pose_, why)) return true;
    ROS_ERROR_THROTTLE_NAMED(10.0, name_, "the tf extrinsic %s <- %s is unusable (%s): waiting for a good one",
                             child.c_str(), sensor.c_str(), why->c_str());
  } catch (const tf2::TransformException& e) {
    *why = e.what();
  }
  pose_ = Eigen::Isometry3d::Identity();
  return false;
}

SensorExtrinsic::State SensorExtrinsic::resolve(const std::string& child, const std::string& sensor, double now) {
  if (state_ == State::kMoving) return state_;
  if (state_ == State::kKnown) {
    if (!from_tf_ || now < next_check_) return state_;
    next_check_ = now + recheck_seconds_;
    const Eigen::Isometry3d found = pose_;
    std::string why;
    if (lookUp(child, sensor, &why)) {
      const Eigen::Isometry3d change = found.inverse() * pose_;
      const double meters = change.translation().norm();
      const double radians = Eigen::AngleAxisd(change.linear()).angle();
      if (meters > kMovedMeters || radians > kMovedRadians) {
        ROS_ERROR_NAMED(name_,
                        "the tf %s <- %s moved by %.3f m and %.2f deg since it was read as the extrinsic: it is "
                        "not one (the clouds' frame %s moves with the vehicle). Keyframes are refused from now on. "
                        "Name the frame the points are really in with sensor_frame (SC-A-LOAM's "
                        "/velodyne_cloud_registered_local: the odometry's child frame), or set "
                        "cloud_in_world_frame: true if they are registered in the world",
                        child.c_str(), sensor.c_str(), meters, radians * 180.0 / M_PI, sensor.c_str());
        state_ = State::kMoving;
      }
    }
    pose_ = found;
    return state_;
  }
  if (sensor.empty() || sensor == child) {
    pose_ = Eigen::Isometry3d::Identity();  // the odometry is the sensor's own
    return state_ = State::kKnown;
  }
  if (state_ == State::kFallback && now < next_check_) return state_;
  if (waiting_since_ < 0.0) waiting_since_ = now;
  std::string why;
  if (lookUp(child, sensor, &why)) {
    const Eigen::Vector3d t = pose_.translation();
    const Eigen::Quaterniond q(pose_.linear());
    ROS_INFO_NAMED(name_,
                   "tf extrinsic %s <- %s after %.1f s: translation (%.3f, %.3f, %.3f) m, rotation (x y z w) "
                   "(%.4f, %.4f, %.4f, %.4f); odometry of %s is moved to the sensor %s",
                   child.c_str(), sensor.c_str(), now - waiting_since_, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(),
                   child.c_str(), sensor.c_str());
    from_tf_ = true;
    next_check_ = now + recheck_seconds_;
    if (state_ == State::kFallback) {
      ROS_WARN_NAMED(name_,
                     "the keyframes before it took the odometry's poses as the sensor's: their loops to "
                     "later keyframes may be rejected");
    }
    return state_ = State::kKnown;
  }
  if (state_ == State::kWaiting && now - waiting_since_ >= wait_seconds_) {
    ROS_WARN_NAMED(name_,
                   "the odometry's child frame %s is not the clouds' frame %s and tf has had no transform between "
                   "them for %.0f s (%s): poses are used as the sensor's, which is wrong if the axes differ "
                   "(publish the extrinsic as a static tf)",
                   child.c_str(), sensor.c_str(), now - waiting_since_, why.c_str());
    state_ = State::kFallback;
  }
  if (state_ == State::kFallback) next_check_ = now + recheck_seconds_;
  return state_;
}

}  // namespace scan_context_loop
