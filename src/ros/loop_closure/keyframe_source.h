// Where a keyframe's pose comes from: the odometry message (odom mode, moved to the sensor with the
// extrinsic from tf when the odometry's child frame is not the sensor's) or tf (tf mode, looked up at the
// cloud's stamp). Keyframes wait here, in order, while the extrinsic they need is missing from tf.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <tf2_ros/buffer.h>

#include "loop_closure/keyframe_queue.h"
#include "loop_closure/node_counters.h"
#include "loop_closure/sensor_extrinsic.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

/// A keyframe ready for the pipeline: `queued.pose` is T_pose_frame<-sensor (finite), `sensor_frame` the
/// sensor's tf frame.
struct PosedKeyframe {
  QueuedKeyframe queued;
  std::string sensor_frame;
};

/// Worker-only: the held keyframes and the extrinsic's state have no lock.
class KeyframeSource {
 public:
  /// `config` and `options` are the worker's settings; `name` prefixes the logs. All must outlive this.
  KeyframeSource(const std::string& name, const Config& config, const NodeOptions& options, NodeCounters* counters);
  ~KeyframeSource();

  /// Poses from tf (pose_source tf), and the sensor extrinsic when sensor_extrinsic_from_tf asks for it
  /// in odom mode. `tf` must outlive this.
  void useTf(const tf2_ros::Buffer& tf);
  /// Whether keyframes may wait for the extrinsic from tf.
  bool hasExtrinsic() const { return extrinsic_ != nullptr; }
  /// Whether keyframes wait for the extrinsic (the worker then looks at tf again every 50 ms).
  bool holding() const { return !held_.empty(); }

  /// Takes `keyframe`: appends to `ready`, in order, the keyframes whose pose is now known (those held
  /// before it first). One whose extrinsic is missing is held (at most queue_size; the oldest held is
  /// dropped first); one without a usable pose is counted as rejected and logged.
  void offer(QueuedKeyframe keyframe, std::vector<PosedKeyframe>* ready);
  /// Appends the held keyframes to `ready` once the extrinsic is known or given up on.
  void release(std::vector<PosedKeyframe>* ready);

 private:
  /// The extrinsic `keyframe` needs, from tf without waiting: known (the identity when none is needed),
  /// waiting, or given up.
  SensorExtrinsic::State resolveExtrinsic(const QueuedKeyframe& keyframe);
  /// The sensor's frame: sensor_frame when named; else a registered cloud's sensor is the odometry's
  /// child, and a sensor-frame cloud's the cloud's own frame.
  const std::string& sensorFrame(const QueuedKeyframe& keyframe) const;
  /// tf mode: T_fixed_frame<-sensor at the cloud's stamp; false (counted, logged) when tf has none.
  bool lookUpPose(QueuedKeyframe* keyframe);
  /// A cloud labelled with the odometry's world frame, taken as in the sensor frame (cloud_in_world_frame
  /// false, no sensor_frame): the "extrinsic" would be the moving pose itself. Such keyframes are refused.
  bool worldLabelledAsSensor(const QueuedKeyframe& keyframe) const;
  /// The pose (looked up, the extrinsic applied), appended to `ready` when it is usable; refused once the
  /// extrinsic turned out to move.
  void pose(QueuedKeyframe keyframe, std::vector<PosedKeyframe>* ready);

  std::string name_;
  const Config& config_;
  const NodeOptions& options_;
  NodeCounters* counters_;
  const tf2_ros::Buffer* tf_ = nullptr;
  std::unique_ptr<SensorExtrinsic> extrinsic_;  // child <- sensor (odom mode with sensor_extrinsic_from_tf)
  std::deque<QueuedKeyframe> held_;             // keyframes waiting for the extrinsic, in order
};

}  // namespace scan_context_loop
