#include "loop_closure/node_output.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

LoopClosureOutput::LoopClosureOutput(const std::string& name, const Config& config, const NodeOptions& options,
                                     NodeCounters* counters)
    : markers_(config), loops_(name, config, options, counters, &markers_) {
  markers_.setRobot(options.robot_id);
  if (options.mode != NodeMode::kRelocalize) selected_.reset(new SelectedKeyframePublisher);
}

void LoopClosureOutput::advertise(const ros::NodeHandle& nh, const std::function<void()>& on_marker_subscriber) {
  loops_.advertise(nh);
  if (selected_) selected_->advertise(nh);
  ros::NodeHandle handle(nh);
  timing_pub_ = handle.advertise<scan_context_loop::KeyframeTiming>(topic_names::kKeyframeTiming, 100);
  markers_.advertise(nh, on_marker_subscriber);
}

void LoopClosureOutput::publishKeyframe(const PosedKeyframe& keyframe,
                                        const pcl::PointCloud<pcl::PointXYZ>* described) {
  if (!selected_) return;
  const QueuedKeyframe& queued = keyframe.queued;
  selected_->publish(queued.cloud->header.stamp, queued.pose_frame, keyframe.sensor_frame, queued.pose, described);
}

void LoopClosureOutput::publishLoops(const Detection& detection, const std::string& frame, const Database& database) {
  loops_.publishLoops(detection, frame, database);
  markers_.setFrame(frame);
  if (markers_.listened()) markers_.publish(database);
}

}  // namespace scan_context_loop
