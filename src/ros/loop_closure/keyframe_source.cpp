#include "loop_closure/keyframe_source.h"

#include <utility>

#include <ros/console.h>

#include "shared/pose_input.h"

namespace scan_context_loop {

namespace {

// A fixed extrinsic comes from a static tf publisher started with the stack: latched on /tf_static, it
// arrives as soon as the listener connects; tf1's static_transform_publisher resends it every period
// (10 ms in LeGO-LOAM's launch). Keyframes wait for it at most this long [s] (and at most queue_size of
// them): processed with poses in the odometry's axes they would stay in the database with the wrong
// poses, so waiting a little loses nothing. After it, tf is looked at again every kExtrinsicRecheck s.
constexpr double kExtrinsicWait = 5.0;
constexpr double kExtrinsicRecheck = 1.0;

}  // namespace

KeyframeSource::KeyframeSource(const std::string& name, const Config& config, const NodeOptions& options,
                               NodeCounters* counters)
    : name_(name), config_(config), options_(options), counters_(counters) {}

KeyframeSource::~KeyframeSource() = default;

void KeyframeSource::useTf(const tf2_ros::Buffer& tf) {
  tf_ = &tf;
  if (options_.pose_source == PoseSource::kOdom && options_.sensor_extrinsic_from_tf) {
    extrinsic_.reset(new SensorExtrinsic(tf, name_, kExtrinsicWait, kExtrinsicRecheck));
  }
}

bool KeyframeSource::worldLabelledAsSensor(const QueuedKeyframe& keyframe) const {
  return extrinsic_ && !config_.cloud_in_world_frame && options_.sensor_frame.empty() &&
         !keyframe.child_frame.empty() && keyframe.cloud_frame == keyframe.pose_frame &&
         keyframe.cloud_frame != keyframe.child_frame;
}

void KeyframeSource::offer(QueuedKeyframe keyframe, std::vector<PosedKeyframe>* ready) {
  if (worldLabelledAsSensor(keyframe)) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(
        10.0, name_,
        "keyframe at %.3f refused: its cloud is labelled %s, the odometry's own world frame, and "
        "cloud_in_world_frame is false, so the extrinsic %s <- %s would be the vehicle's moving pose. Points "
        "registered in %s (A-LOAM's /velodyne_cloud_registered): set cloud_in_world_frame: true. Sensor-frame "
        "points under the world's name (SC-A-LOAM's /velodyne_cloud_registered_local): set sensor_frame: %s "
        "(launch/sc_aloam.launch does)",
        keyframe.cloud->header.stamp.toSec(), keyframe.cloud_frame.c_str(), keyframe.child_frame.c_str(),
        keyframe.cloud_frame.c_str(), keyframe.cloud_frame.c_str(), keyframe.child_frame.c_str());
    return;
  }
  if (held_.empty() && resolveExtrinsic(keyframe) != SensorExtrinsic::State::kWaiting) {
    pose(std::move(keyframe), ready);
    return;
  }
  if (held_.size() >= static_cast<std::size_t>(options_.queue_size)) {
    held_.pop_front();
    ++counters_->dropped;
    ROS_WARN_THROTTLE_NAMED(5.0, name_,
                            "%zu keyframes held for the tf extrinsic: the oldest dropped (%zu dropped so far)",
                            held_.size(), counters_->dropped.load());
  }
  held_.push_back(std::move(keyframe));
  counters_->held = held_.size();
}

void KeyframeSource::release(std::vector<PosedKeyframe>* ready) {
  if (held_.empty() || resolveExtrinsic(held_.front()) == SensorExtrinsic::State::kWaiting) return;
  while (!held_.empty()) {
    QueuedKeyframe keyframe = std::move(held_.front());
    held_.pop_front();
    counters_->held = held_.size();
    pose(std::move(keyframe), ready);
  }
}

SensorExtrinsic::State KeyframeSource::resolveExtrinsic(const QueuedKeyframe& keyframe) {
  if (!extrinsic_ || keyframe.child_frame.empty()) return SensorExtrinsic::State::kKnown;  // none needed
  return extrinsic_->resolve(keyframe.child_frame, sensorFrame(keyframe), ros::WallTime::now().toSec());
}

const std::string& KeyframeSource::sensorFrame(const QueuedKeyframe& keyframe) const {
  // A registered cloud's own frame is the world's: only a named sensor_frame, or the odometry's child,
  // says where the sensor is (in tf mode the cloud's frame, as lookUpPose takes it, when none is named).
  if (!options_.sensor_frame.empty()) return options_.sensor_frame;
  return config_.cloud_in_world_frame && !keyframe.child_frame.empty() ? keyframe.child_frame : keyframe.cloud_frame;
}

bool KeyframeSource::lookUpPose(QueuedKeyframe* keyframe) {
  // A registered cloud's frame is the fixed frame: the sensor's own frame must be named.
  const std::string& sensor = sensorFrame(*keyframe);
  try {
    const auto t = tf_->lookupTransform(options_.fixed_frame, sensor, keyframe->cloud->header.stamp,
                                        ros::Duration(options_.tf_timeout));
    std::string why;
    if (!poseFromMsg(t.transform, &keyframe->pose, &why)) {
      ++counters_->rejected;
      ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: the transform %s <- %s is unusable: %s",
                               keyframe->cloud->header.stamp.toSec(), options_.fixed_frame.c_str(), sensor.c_str(),
                               why.c_str());
      return false;
    }
    keyframe->has_pose = true;
    return true;
  } catch (const tf2::TransformException& e) {
    ++counters_->rejected;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "keyframe skipped: no transform %s <- %s at its stamp: %s",
                            options_.fixed_frame.c_str(), sensor.c_str(), e.what());
    return false;
  }
}

void KeyframeSource::pose(QueuedKeyframe keyframe, std::vector<PosedKeyframe>* ready) {
  if (!keyframe.has_pose && !lookUpPose(&keyframe)) return;
  const SensorExtrinsic::State extrinsic = resolveExtrinsic(keyframe);
  if (extrinsic == SensorExtrinsic::State::kMoving) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(10.0, name_,
                             "keyframe at %.3f refused: the tf between the odometry's child frame and the clouds' "
                             "frame %s moves, so it is no extrinsic (the error above says what to set)",
                             keyframe.cloud->header.stamp.toSec(), sensorFrame(keyframe).c_str());
    return;
  }
  // Turns the pose into the sensor's with the extrinsic from tf (child <- sensor), once it is known.
  if (extrinsic == SensorExtrinsic::State::kKnown && extrinsic_) {
    keyframe.pose = keyframe.pose * extrinsic_->pose();
  }
  if (!keyframe.pose.matrix().allFinite()) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its pose is not finite",
                             keyframe.cloud->header.stamp.toSec());
    return;
  }
  PosedKeyframe posed;
  posed.sensor_frame = sensorFrame(keyframe);
  posed.queued = std::move(keyframe);
  ready->push_back(std::move(posed));
}

}  // namespace scan_context_loop
