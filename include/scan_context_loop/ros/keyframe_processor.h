// One keyframe on the worker: its pose (from tf in tf mode; the sensor extrinsic applied in odom mode),
// the core's pipeline (selection, description, query, verification, the database), then the keyframe
// as selected, the counters, the loops, the markers and the keyframe's timing.
#pragma once

#include <memory>
#include <string>

#include <tf2_ros/buffer.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/ros/keyframe_publisher.h"
#include "scan_context_loop/ros/keyframe_queue.h"
#include "scan_context_loop/ros/loop_publisher.h"
#include "scan_context_loop/ros/marker_publisher.h"
#include "scan_context_loop/ros/node_counters.h"
#include "scan_context_loop/ros/parameters.h"
#include "scan_context_loop/ros/sensor_extrinsic.h"
#include "scan_context_loop/ros/team_exchange.h"

namespace scan_context_loop {

/// Worker-only: it owns the pipeline and with it the database, which only the worker thread touches
/// (start() and the destructor too, before the worker starts and after it ended). No lock.
class KeyframeProcessor {
 public:
  /// `config` and `options` are the worker's settings; `name` prefixes the logs. All must outlive this.
  /// `selected` publishes each keyframe that entered the database; null: none is published (relocalize mode).
  KeyframeProcessor(const std::string& name, const Config& config, const RosOptions& options, NodeCounters* counters,
                    LoopPublisher* loops, MarkerPublisher* markers, SelectedKeyframePublisher* selected);
  ~KeyframeProcessor();

  /// Poses from tf (pose_source tf), and the sensor extrinsic when sensor_extrinsic_from_tf asks for it
  /// in odom mode. `tf` must outlive this.
  void useTf(const tf2_ros::Buffer& tf);
  /// Several robots: every keyframe stored is shared with the team and matched against its keyframes.
  /// `team` must outlive this.
  void useTeam(TeamExchange* team) { team_ = team; }
  /// Whether keyframes may wait for the extrinsic from tf.
  bool hasExtrinsic() const { return extrinsic_ != nullptr; }

  KeyframePipeline& pipeline() { return *pipeline_; }
  const Database& database() const { return pipeline_->detector().database(); }
  /// What a save writes, taken now (DatabaseSnapshot); it keeps this pipeline's keyframes alive until
  /// it is released, even past a resetPipeline(), so it may be written on another thread.
  DatabaseSnapshot snapshot(bool include_clouds) const {
    return DatabaseSnapshot(pipeline_->detector(), include_clouds, pipeline_);
  }
  /// An empty pipeline with the settings in force (reset); the old one lives on while a snapshot of it does.
  void resetPipeline();
  /// Keyframes entered the database beside process() (a load, or one whose processing threw): the
  /// counters follow the database and the markers are drawn afresh.
  void followDatabase();

  /// The extrinsic `keyframe` needs (odometry of another frame than the sensor's: LeGO-LOAM's camera
  /// axes, an IMU body), from tf without waiting: known (the identity when none is needed), waiting, or
  /// given up.
  SensorExtrinsic::State resolveExtrinsic(const QueuedKeyframe& keyframe);
  /// Processes one keyframe (an unusable one is counted as rejected and logged).
  void process(QueuedKeyframe keyframe);

 private:
  bool lookUpPose(QueuedKeyframe* keyframe);
  /// The cloud store's counters; warns when it halved its density since the last call.
  void followCloudStore();
  /// Turns the pose into the sensor's with the extrinsic from tf (child <- sensor), once it is known.
  void applyExtrinsic(QueuedKeyframe* keyframe);
  /// The sensor's frame: sensor_frame when named; else a registered cloud's sensor is the odometry's
  /// child, and a sensor-frame cloud's the cloud's own frame.
  const std::string& sensorFrame(const QueuedKeyframe& keyframe) const;
  /// Shares the keyframe stored as `index` (and any loaded before it) and hands it to the team's matching.
  void shareWithTeam(std::size_t index, const QueuedKeyframe& queued, pcl::PointCloud<pcl::PointXYZ> described);
  /// Warns (throttled) while gravity alignment finds the odometry's world frame tilted from gravity (world_tilt.h).
  void reportWorldTilt(const Detection& detection);

  std::string name_;
  const Config& config_;
  const RosOptions& options_;
  NodeCounters* counters_;
  LoopPublisher* loops_;
  MarkerPublisher* markers_;
  SelectedKeyframePublisher* selected_;
  std::shared_ptr<KeyframePipeline> pipeline_;  // shared with the snapshots being written
  const tf2_ros::Buffer* tf_ = nullptr;
  std::unique_ptr<SensorExtrinsic> extrinsic_;  // child <- sensor (odom mode with sensor_extrinsic_from_tf)
  TeamExchange* team_ = nullptr;
  std::string team_frame_;  // the pose frame of the keyframes shared last
};

}  // namespace scan_context_loop
