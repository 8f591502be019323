// Several robots, one map (doc/multi_robot.md): the loop node's side of a team. It shares each keyframe
// this robot stores as a record on <team_namespace>/keyframe_records, announces itself once a second on
// <team_namespace>/members, serves its records and its keyframes' registration data on request
// (~team_records, ~team_cloud), and hands the other robots' records and this robot's keyframes to the
// TeamWorker, which finds the loops between them.
//
// Threads and locks: share() runs on the keyframe worker; the topic callbacks, the services and the
// announcement timer run on the team's callback queue and its spinner thread; served_mutex_ guards the run
// and the keyframes served; send_mutex_ guards the rate limit. The TeamWorker has its own threads.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "scan_context_loop/GetKeyframeCloud.h"
#include "scan_context_loop/GetKeyframeRecords.h"
#include "scan_context_loop/KeyframeRecord.h"
#include "scan_context_loop/TeamMember.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/rate_limit.h"
#include "team/team_worker.h"

namespace scan_context_loop {

class TeamExchange {
 public:
  /// `pnh` (the node's private handle) names the node and its services; `config`, `options` are copied;
  /// `counters` and `loops` must outlive this.
  TeamExchange(const ros::NodeHandle& pnh, const std::string& name, const Config& config, const NodeOptions& options,
               NodeCounters* counters, LoopPublisher* loops);
  ~TeamExchange();

  /// Advertises, subscribes and starts the spinner and the announcements.
  void start();
  /// Stops everything that could call into this (idempotent).
  void stop();

  /// Keyframe worker: shares the keyframes that entered `detector`'s database since the last call, their
  /// poses in `frame`; `owner` keeps them alive while they are served. A database smaller than what was
  /// shared begins a new run.
  void share(const LoopDetector& detector, const std::shared_ptr<const void>& owner, const std::string& frame);
  /// Keyframe worker, after ~reset emptied the database: a new run begins, and the next share() shares the
  /// database from its first keyframe (a ~load_database right after the reset as much as new keyframes),
  /// so that no robot keeps the old run's records under the new keyframe numbers.
  void restart();
  /// Keyframe worker: a keyframe just stored, to match against the other robots' keyframes.
  void match(std::shared_ptr<const OwnKeyframe> keyframe) { worker_->onOwnKeyframe(std::move(keyframe)); }

 private:
  /// One of this robot's keyframes as served: its record and what its registration data are made from.
  struct Served {
    scan_context_loop::KeyframeRecordPtr record;
    DatabaseSnapshot data;
  };
  bool onRecords(scan_context_loop::GetKeyframeRecords::Request& request,
                 scan_context_loop::GetKeyframeRecords::Response& response);
  bool onCloud(scan_context_loop::GetKeyframeCloud::Request& request,
               scan_context_loop::GetKeyframeCloud::Response& response);
  void announce();
  /// Whether `bytes` more may go out now (team_max_bytes_per_second).
  bool maySend(std::size_t bytes);
  /// A service's answer of `bytes`: counted and true when it may go out, else false with `message` busy.
  bool answer(std::size_t bytes, std::string* message);

  ros::NodeHandle pnh_, team_nh_;
  std::string name_;
  NodeOptions options_;
  NodeCounters* counters_;
  std::string settings_text_;
  std::uint32_t settings_crc_ = 0;
  std::unique_ptr<TeamWorker> worker_;

  std::mutex served_mutex_;  // guards run_ and served_
  std::uint64_t run_ = 0;
  std::vector<Served> served_;

  std::mutex send_mutex_;  // guards limit_
  RateLimit limit_;

  ros::CallbackQueue queue_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  ros::Publisher record_pub_, member_pub_;
  ros::Subscriber record_sub_, member_sub_;
  ros::ServiceServer records_srv_, cloud_srv_;
  ros::WallTimer announce_timer_;
};

}  // namespace scan_context_loop
