// A team in one process: one KeyframePipeline and one TeamMatcher per robot, and the exchange the loop
// nodes run over ROS (src/ros/team/team_worker.cpp), synchronous: each keyframe a robot stores is matched
// against the records that robot holds then (the registration data of the candidates fetched from their
// robots, and matched again), and its record is shared with every other robot. ROS-free.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/team_consistency.h"
#include "scan_context_loop/core/team_matcher.h"

namespace scan_context_loop {
namespace eval {

/// A verified loop between two robots' keyframes, found by the query's robot.
struct TeamLoop {
  std::size_t query_robot = 0, match_robot = 0;                ///< robot indices in the session
  std::size_t query = 0, match = 0;                            ///< keyframe numbers at each robot (database indices)
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  ///< T_query<-match, sensor frames
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();  ///< loopCovariance
};

/// What one stored keyframe did in the team.
struct TeamStep {
  std::size_t record_bytes = 0;  ///< its record, sent once (every other robot receives it)
  std::size_t fetched = 0;       ///< registration data its robot fetched to verify it
  std::size_t fetched_bytes = 0;
  std::size_t fetch_failures = 0;   ///< data that did not come or did not fit
  std::size_t records_refused = 0;  ///< by another robot (none when every robot runs one configuration)
  std::size_t held = 0;             ///< the other robots' records its robot held when matching it
  int matches = 0;                  ///< TeamMatcher::match calls (one, plus one per round of fetches)
  bool found = false;               ///< a loop into another robot's keyframe was verified
  /// Loops between robots reported now: this keyframe's, once another loop between the same two frames
  /// agrees with it (TeamConsistency), and an earlier one it confirmed; possibly none.
  std::vector<TeamLoop> loops;
  std::size_t dropped = 0;  ///< verified loops that no other loop ever agreed with
};

class TeamSession {
 public:
  /// Every robot runs `config`; `robots` are their ids ([A-Za-z0-9_]+, distinct).
  TeamSession(const Config& config, const std::vector<std::string>& robots);

  std::size_t size() const { return robots_.size(); }
  const std::string& id(std::size_t robot) const { return robots_.at(robot); }
  /// Robot `robot`'s pipeline: its keyframes go through it (process(..., &described)), then share().
  KeyframePipeline& pipeline(std::size_t robot) { return *pipelines_.at(robot); }
  const TeamMatcher& matcher(std::size_t robot) const { return *matchers_.at(robot); }

  /// After robot `robot`'s pipeline stored a keyframe (`detection` accepted; `described` its points as
  /// described): matches it against the records the robot holds, as the node's team worker does (the
  /// candidates' registration data fetched from their robots, at most Config::verification.max_candidates
  /// a round, then matched again, a few rounds at most), then shares its record with every other robot.
  TeamStep share(std::size_t robot, const Detection& detection, const pcl::PointCloud<pcl::PointXYZ>& described);

  /// Rounds of fetches for one keyframe, as the node's team worker allows.
  static constexpr int kMaxRounds = 3;

 private:
  /// The registration data of `id` from its robot into robot `robot`'s matcher; false when they did not
  /// come or did not fit.
  bool fetch(std::size_t robot, const TeamKeyframeId& id, std::size_t* bytes);
  long robotOf(const std::string& id) const;

  Config config_;
  std::vector<std::string> robots_;
  std::vector<std::unique_ptr<KeyframePipeline>> pipelines_;
  std::vector<std::unique_ptr<TeamMatcher>> matchers_;
  std::vector<std::unique_ptr<TeamConsistency>> consistency_;  // per robot, as each node has its own
  std::map<std::size_t, TeamLoop> unconfirmed_;                // loops waiting for support, by handle
  std::size_t next_handle_ = 0;
};

}  // namespace eval
}  // namespace scan_context_loop
