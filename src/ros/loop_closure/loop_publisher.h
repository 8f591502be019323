// What the node publishes of the loops it finds: LoopClosure messages (loop_closures, and the rejected
// candidates on loop_candidates_rejected), the standard-type copies (loop_closure_pairs,
// loop_closure_array), LIO-SAM's loop hook (lio_loop) and relocalization into a map. A part of the
// node's output (node_output.h).
#pragma once

#include <cstddef>
#include <string>

#include <ros/ros.h>

#include "scan_context_loop/LoopClosure.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/rate_limit.h"
#include "loop_closure/marker_publisher.h"
#include "loop_closure/node_counters.h"
#include "shared/parameters.h"

namespace scan_context_loop {

/// Loop `loop` between keyframes `query` and `match` as a message in `frame` (their stamps and sessions;
/// no robots), its covariance under `config`.
scan_context_loop::LoopClosure loopMessage(const Loop& loop, const std::string& frame, const Keyframe& query,
                                           const Keyframe& match, const Config& config);

/// Worker-only but advertise() and publishTeamLoop(): its state (the publishers, lio_loop's last message) has no lock.
class LoopPublisher {
 public:
  /// `config` and `options` are the worker's settings; `name` prefixes the logs. All must outlive this.
  LoopPublisher(const std::string& name, const Config& config, const NodeOptions& options, NodeCounters* counters,
                MarkerPublisher* markers);

  /// Advertises the topics the settings ask for.
  void advertise(const ros::NodeHandle& nh);

  /// A detection's loops (and the candidates it rejected or dropped) in `frame`, the pose frame of
  /// the keyframes in `database`: published, drawn and logged.
  void publishLoops(const Detection& detection, const std::string& frame, const Database& database);
  /// A loop as a message; its stamps and sessions are those `database` holds.
  scan_context_loop::LoopClosure makeLoop(const Loop& loop, const std::string& frame, const Database& database) const;

  /// A loop into another robot's keyframe (team_worker.h), from the team's thread: published on
  /// loop_closures and loop_closure_array and counted (publishers and counters are thread-safe).
  void publishTeamLoop(const scan_context_loop::LoopClosure& loop);

 private:
  void publishRejected(const Loop& rejected, const std::string& frame, const Database& database);
  /// lio_sam_output: the loop on lio_loop if it is verified, new and due (lio_sam_min_interval).
  void sendToLioSam(const scan_context_loop::LoopClosure& loop);
  /// mode relocalize: a loop into the map as T_map<-sensor on `relocalization`.
  void publishRelocalization(const scan_context_loop::LoopClosure& loop, const Database& database);

  std::string name_;
  const Config& config_;
  const NodeOptions& options_;
  NodeCounters* counters_;
  MarkerPublisher* markers_;
  ros::Publisher loop_pub_, rejected_pub_, lio_pub_, pair_pub_, array_pub_, relocalization_pub_;
  bool lio_unheard_warned_ = false;  // lio_loop had no subscriber when a loop was due (warned once)
  MinInterval lio_interval_;  // lio_loop: when the last message went out (ROS time), and its query keyframe
  std::size_t lio_last_query_ = static_cast<std::size_t>(-1);
};

}  // namespace scan_context_loop
