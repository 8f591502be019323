// The loop-closure node's diagnostics: the "loop closure" task of a diagnostic_updater, fed from the
// counters (node_counters.h) once a second on a spinner thread.
#pragma once

#include <memory>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include "loop_closure/node_counters.h"

namespace scan_context_loop {

class NodeDiagnostics {
 public:
  /// Starts the updates. `extrinsic`: report the keyframes held for the tf extrinsic; `lio_sam`: the
  /// loops not sent on lio_loop; `team`: the exchange with the other robots. `counters` must outlive this.
  NodeDiagnostics(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name,
                  const NodeCounters& counters, bool extrinsic, bool lio_sam, bool team);
  /// Stops the updates (a running one completes).
  void stop() { timer_.stop(); }

 private:
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  const NodeCounters& counters_;
  bool extrinsic_, lio_sam_, team_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::Timer timer_;
};

}  // namespace scan_context_loop
