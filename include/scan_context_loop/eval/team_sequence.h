// A simulated team's sequence as the evaluator reads it (scan_context_simulate --team writes it):
// DIR/team.txt, one line per robot ('#' starts a comment),
//   <robot_id> <start_seconds> <T_world<-robot_start: rows 0-2 of the 4 x 4, row-major, 12 numbers>
// and DIR/<robot_id>/, the robot's own KITTI-layout sequence relative to its first keyframe.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/eval/sequence.h"

namespace scan_context_loop {
namespace eval {

/// A robot's line of team.txt.
struct TeamStart {
  std::string id;
  double start_seconds = 0.0;  ///< the world's clock at the robot's first keyframe
  /// The true LiDAR pose of its first keyframe in the world: the origin of its odometry frame.
  Eigen::Isometry3d world_from_start = Eigen::Isometry3d::Identity();
};

/// Reads a team.txt (the simulator writes it: sim::writeTeamFile). False with the reason, naming the file
/// and line: a robot id that is not 1-64 characters of [A-Za-z0-9_] or is repeated, a start that is negative
/// or not finite, not exactly 12 finite numbers after it, a rotation that is not one, or no robot.
bool readTeamFile(const std::string& path, std::vector<TeamStart>* team, std::string* error);

struct TeamRobot : TeamStart {
  Sequence sequence;  ///< DIR/<id>, its poses relative to world_from_start

  /// The world's clock at keyframe k (times.txt counts from the robot's first keyframe).
  double clock(std::size_t k) const { return start_seconds + sequence.stamps[k]; }
  /// The true pose of keyframe k in the world.
  Eigen::Isometry3d worldPose(std::size_t k) const { return world_from_start * sequence.truth[k]; }
};

struct TeamSequence {
  std::string dir;
  std::vector<TeamRobot> robots;  ///< in team.txt's order; the first anchors the map
};

/// Reads DIR/team.txt (readTeamFile) and each robot's sequence (loadSequence with `options`). False with
/// the reason: what readTeamFile refuses, or a robot's sequence that does not load.
bool loadTeam(const std::string& dir, const SequenceOptions& options, TeamSequence* team, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
