// Loops between robots checked against each other before they are reported. Within one robot the odometry
// rules out a registration that slid along a straight street; between two robots nothing relates the two
// keyframes but the loops themselves. Every loop between this robot's odometry frame and another's implies
// where that frame lies in ours (F = own_pose * T_own<-other * other_pose^-1); two true loops imply nearly
// the same F, apart by what the odometry drifted between them. A loop is reported once another loop of
// the same two frames agrees with it (Config::consistency_min_support > 0; with 0 every loop at once).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"

namespace scan_context_loop {

/// A verified loop from one of this robot's keyframes to another robot's.
struct TeamLoopOffer {
  std::string robot;                                             ///< the other robot
  std::uint64_t run = 0;                                         ///< its node's run
  std::uint32_t session = 0;                                     ///< its keyframe's session there
  std::uint32_t own_session = 0;                                 ///< this robot's keyframe's session
  Eigen::Isometry3d own_pose = Eigen::Isometry3d::Identity();    ///< odometry pose of this robot's keyframe
  Eigen::Isometry3d other_pose = Eigen::Isometry3d::Identity();  ///< the other's, in its odometry frame
  double own_path = 0.0, other_path = 0.0;                       ///< odometry path lengths within their sessions [m]
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();    ///< T_own<-other (sensor frames)
  std::size_t handle = 0;  ///< the caller's, returned as the loop is released or dropped
};

/// What one offer released: loops to report now (handles; an earlier waiting one first), and loops that
/// waited for support in vain (too many waiting for one pair of frames).
struct TeamRelease {
  std::vector<std::size_t> report, dropped;
};

/// Not thread-safe: one owner.
class TeamConsistency {
 public:
  explicit TeamConsistency(const Config& config) : config_(config) {}
  TeamRelease offer(const TeamLoopOffer& loop);
  /// Whether two loops of the same two frames agree (within consistency_translation / rotation plus
  /// consistency_drift per metre of odometry path between their keyframes, on both robots).
  bool agree(const TeamLoopOffer& a, const TeamLoopOffer& b) const;
  std::size_t waiting() const;

 private:
  using Pair = std::tuple<std::string, std::uint64_t, std::uint32_t, std::uint32_t>;  // robot, run, sessions
  struct Loops {
    std::vector<TeamLoopOffer> confirmed;
    std::deque<TeamLoopOffer> waiting;
  };
  Config config_;
  std::map<Pair, Loops> pairs_;
};

}  // namespace scan_context_loop
