// The node's RViz markers (loop_markers): the keyframes of the database, the loops and the rejected
// candidates, published incrementally (markers.h) when someone listens.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/database.h"
#include "loop_closure/markers.h"

namespace scan_context_loop {

/// Worker-only: every member but advertise() and shutdown() is called on the worker thread, and its
/// state (the edges, what is shown, the frame) has no lock.
class MarkerPublisher {
 public:
  /// `config`: the worker's settings (distance_threshold colours the loops); it must outlive this.
  explicit MarkerPublisher(const Config& config) : config_(config) {}

  /// Advertises loop_markers (latched); `on_subscriber` runs on a spinner thread when one connects.
  void advertise(const ros::NodeHandle& nh, const std::function<void()>& on_subscriber);
  /// Ends the publisher and its subscriber callback.
  void shutdown() { pub_.shutdown(); }
  bool listened() const { return pub_.getNumSubscribers() > 0; }

  /// A loop published, and a candidate rejected, to draw.
  void addLoop(const LoopEdge& edge) { loops_.push_back(edge); }
  void addRejected(const LoopEdge& edge) { rejected_.push_back(edge); }
  /// The pose frame of the newest keyframe: the markers' frame.
  void setFrame(const std::string& frame) { frame_ = frame; }
  /// A team's robot id (robot_id): every marker's namespace begins with "<robot>/" (set before advertise()).
  /// Loops into other robots' keyframes are not drawn: those keyframes have no pose in this robot's frame
  /// (the backend's graph_markers draw them in the map).
  void setRobot(const std::string& robot) { robot_ = robot; }
  /// Publishes what changed since the last time, stamped with the newest keyframe's stamp; the
  /// database must hold keyframes.
  void publish(const Database& database);
  /// Publishes every marker again (a subscriber connected) when the database holds keyframes.
  void redraw(const Database& database);
  /// Draws everything again at the next publish (keyframes entered the database beside the worker's
  /// own: a load, or one whose processing threw).
  void forgetShown() { shown_ = MarkerState(); }
  /// Forgets every loop and rejected candidate (reset) and clears RViz's markers when someone listens.
  void clear();

 private:
  const Config& config_;
  ros::Publisher pub_;
  std::vector<LoopEdge> loops_, rejected_;
  MarkerState shown_;  // what the published markers already show
  std::string robot_;
  std::string frame_;  // the pose frame of the newest keyframe
};

}  // namespace scan_context_loop
