// Several robots: the thread that owns the team's keyframes (TeamMatcher) and matches this robot's new
// keyframes against them, and the thread that asks the other robots' nodes for what is missing (records
// after a gap, a candidate's registration data). Nothing else touches the matcher; service calls, which
// may wait for a slow link, never hold up the matching or the keyframe worker.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <ros/ros.h>

#include "scan_context_loop/KeyframeRecord.h"
#include "scan_context_loop/TeamMember.h"
#include "scan_context_loop/core/task_thread.h"
#include "scan_context_loop/core/team_consistency.h"
#include "scan_context_loop/core/team_matcher.h"
#include "loop_closure/loop_publisher.h"
#include "loop_closure/node_counters.h"
#include "shared/parameters.h"
#include "team/service_deadline.h"

namespace scan_context_loop {

/// The settings a team's keyframes must share, as TeamMember.settings_text says them, and their CRC-32.
std::pair<std::string, std::uint32_t> teamSettings(const Config& config);

/// One of this robot's keyframes, as it was stored, for matching against the team's.
struct OwnKeyframe {
  std::uint32_t index = 0;  ///< its number in this node's database
  std::uint32_t session = 0;
  double path_length = 0.0;  ///< odometry path within its session [m]
  ros::Time stamp;
  std::string frame;  ///< the odometry frame of its pose
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pcl::PointCloud<pcl::PointXYZ> described;  ///< its points as described (sensor frame)
};

/// Thread-safe: every public member posts to the matcher's thread (the matcher, the pending keyframes,
/// the robots bound and the refusals are that thread's alone); the service calls run on the client's,
/// each bounded in time (ServiceDeadline), and a node that let one time out is marked slow (the client's
/// thread's alone) and asked nothing until kSlowPeerSeconds have passed.
///
/// Who is who: a robot id is bound to the node (and the publisher, the ROS node whose messages carried
/// it) of the first valid announcement or record naming it; later claims to that id from another node or
/// publisher are refused and counted, so a peer can neither redirect a robot's fetches nor slip records
/// in under its id. Announcements and records whose node is not a valid ROS name are refused the same way.
class TeamWorker {
 public:
  /// `config`, `options` are copied; `counters` and `loops` must outlive this (their members used here
  /// are thread-safe).
  TeamWorker(const std::string& name, const Config& config, const NodeOptions& options, NodeCounters* counters,
             LoopPublisher* loops);
  /// Stops both threads (the task in hand finishes).
  ~TeamWorker();
  void stop();

  /// Another robot's record from the topic, its size as sent [bytes] and the node that published it.
  void onRecord(const scan_context_loop::KeyframeRecordConstPtr& record, std::size_t bytes,
                const std::string& publisher);
  /// Another robot's announcement (its publisher as onRecord's): its claim and settings are checked and
  /// missing records asked for.
  void onMember(const scan_context_loop::TeamMemberConstPtr& member, std::size_t bytes, const std::string& publisher);
  /// This robot's keyframe, to match.
  void onOwnKeyframe(std::shared_ptr<const OwnKeyframe> keyframe);

 private:
  /// A keyframe of this robot waiting for candidates' registration data.
  struct Pending {
    std::shared_ptr<const OwnKeyframe> keyframe;
    std::set<TeamKeyframeId> waiting_for;
    int rounds = 0;
  };
  using Run = std::pair<std::string, std::uint64_t>;  // robot, run
  /// The node a robot id is bound to.
  struct Peer {
    std::string node;       ///< its private namespace: where its services are
    std::string publisher;  ///< the ROS node that publishes its announcements and records
  };

  // On the matcher's thread.
  /// `publisher` "" for records its bound node served on request.
  void addRecord(const scan_context_loop::KeyframeRecord& record, const std::string& publisher);
  void takeMember(const scan_context_loop::TeamMember& member, const std::string& publisher);
  /// Whether `node` (published by `publisher`, "" when served on request) may speak for `robot`: binds an
  /// unbound id; refuses, counts and logs (throttled) a conflicting claim or an invalid node name.
  bool claim(const std::string& robot, const std::string& node, const std::string& publisher);
  void match(std::shared_ptr<const OwnKeyframe> keyframe, int rounds);
  void publishLoop(const OwnKeyframe& keyframe, const TeamMatch& match);
  void fetch(const TeamKeyframeId& id);
  /// `later`: the node was slow or the request could not be queued; the data may be asked for again.
  void onCloud(const TeamKeyframeId& id, const std::vector<std::uint8_t>& data, const std::string& failure, bool later);
  // On the client's thread: the service calls; results are posted back to the matcher's thread.
  void requestRecords(const std::string& node, const Run& run, std::uint32_t first, std::uint32_t count);
  void requestCloud(const std::string& node, const TeamKeyframeId& id);
  /// Calls `node`'s service `service` within team_request_timeout, or at once kTimedOut while the node is
  /// marked slow; a call that times out marks it slow.
  template <typename Service>
  ServiceDeadline::Outcome callPeer(const std::string& node, const std::string& service, Service* srv);

  std::string name_;
  Config config_;
  NodeOptions options_;
  NodeCounters* counters_;
  LoopPublisher* loops_;
  std::string settings_text_;  // the settings keyframes must share (teamSettings)
  std::uint32_t settings_crc_ = 0;

  // The matcher's thread's alone.
  TeamMatcher matcher_;
  std::vector<Pending> pending_;
  TeamConsistency consistency_;  // loops wait here for another loop of the same frames
  std::map<std::size_t, scan_context_loop::LoopClosure> unconfirmed_;  // their messages, by handle
  std::size_t next_handle_ = 0;
  std::map<std::string, Peer> robots_;               // each robot id's node
  std::set<Run> refused_;                            // runs whose settings differ (forgotten past kMaxRefused)
  std::map<Run, ros::WallTime> asking_;              // runs with a records request under way, since when
  ros::WallTime last_retry_ = ros::WallTime::now();  // when data set aside (fetchLater) were last released
  static constexpr std::size_t kMaxPending = 32;
  static constexpr int kMaxRounds = 3;  // matches of one keyframe as data arrive
  static constexpr std::uint32_t kRecordsPerRequest = 100;
  static constexpr std::size_t kMaxRobots = 256;    // robot ids bound at most
  static constexpr std::size_t kMaxRefused = 1024;  // runs remembered as refused at most

  // The client's thread's alone.
  std::map<std::string, ros::WallTime> slow_until_;  // nodes that let a request time out
  static constexpr double kSlowPeerSeconds = 30.0;

  ServiceDeadline deadline_;   // before client_: its calls use it until client_ has stopped
  TaskThread client_;          // service calls
  TaskThread matcher_thread_;  // last: its tasks use everything above
};

/// Text a peer chose, for a log line: at most 64 characters, anything unprintable as '?'.
std::string peerText(const std::string& text);

}  // namespace scan_context_loop
