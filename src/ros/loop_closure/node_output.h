// Everything the loop-closure node publishes, in one object: the keyframes as selected
// (selected_keyframe_odom, selected_keyframe_cloud), the loops and rejected candidates with their
// standard-type copies, LIO-SAM's hook and relocalization (loop_publisher.h), the RViz markers
// (marker_publisher.h) and each keyframe's timing (keyframe_timing). The worker hands it what a keyframe
// produced; nothing else publishes.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <ros/ros.h>

#include "loop_closure/keyframe_publisher.h"
#include "loop_closure/keyframe_source.h"
#include "loop_closure/loop_publisher.h"
#include "loop_closure/marker_publisher.h"
#include "loop_closure/node_counters.h"
#include "scan_context_loop/KeyframeTiming.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

/// Worker-only, but advertise(), shutdown() and loops().publishTeamLoop() (see LoopPublisher): the
/// markers' and loops' state has no lock; ROS publishers are thread-safe.
class LoopClosureOutput {
 public:
  /// `config` and `options` are the worker's settings; `name` prefixes the logs. All must outlive this.
  LoopClosureOutput(const std::string& name, const Config& config, const NodeOptions& options, NodeCounters* counters);

  /// Advertises every topic the settings ask for; `on_marker_subscriber` runs on a spinner thread when
  /// someone subscribes to the markers.
  void advertise(const ros::NodeHandle& nh, const std::function<void()>& on_marker_subscriber);
  /// Ends the markers' publisher and its subscriber callback.
  void shutdown() { markers_.shutdown(); }

  /// Whether a stored keyframe's points as described are wanted (selected_keyframe_cloud has a subscriber).
  bool cloudWanted() const { return selected_ && selected_->cloudListened(); }
  /// The keyframe as stored, before its loops, so a backend knows it when they come; `described`, its
  /// points (when cloudWanted() said so before it was processed), unless it is null.
  void publishKeyframe(const PosedKeyframe& keyframe, const pcl::PointCloud<pcl::PointXYZ>* described);
  /// A detection's loops and the candidates it rejected or dropped in `frame`, the pose frame of the
  /// keyframes in `database`: published, logged, and drawn when someone looks at the markers.
  void publishLoops(const Detection& detection, const std::string& frame, const Database& database);
  /// Whether keyframe_timing has a subscriber (the message is built only then).
  bool timingWanted() const { return timing_pub_.getNumSubscribers() > 0; }
  void publishTiming(const scan_context_loop::KeyframeTiming& timing) { timing_pub_.publish(timing); }

  /// The markers: every one again (a subscriber connected); all drawn afresh at the next keyframe
  /// (keyframes entered the database beside the worker's own); none (reset).
  void redrawMarkers(const Database& database) { markers_.redraw(database); }
  void forgetShownMarkers() { markers_.forgetShown(); }
  void clearMarkers() { markers_.clear(); }

  /// The loops' publishers, which the team's thread uses too (LoopPublisher::publishTeamLoop).
  LoopPublisher& loops() { return loops_; }

 private:
  MarkerPublisher markers_;
  LoopPublisher loops_;                                  // draws on markers_
  std::unique_ptr<SelectedKeyframePublisher> selected_;  // none in relocalize mode
  ros::Publisher timing_pub_;
};

}  // namespace scan_context_loop
