// OUT/team.txt of a simulated team: which robots there are, when each started and where, in the
// shared world frame. One line per robot ('#' starts a comment):
//   <robot_id> <start_seconds> <T_world<-robot_start: rows 0-2 of the 4 x 4, row-major, 12 numbers>
// start_seconds is the world's clock at the robot's first keyframe (0 for the earliest);
// T_world<-robot_start is the true LiDAR pose of its first keyframe, the origin of its odometry frame.
// The robot's own folder OUT/<robot_id> holds its sequence relative to that origin.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace sim {

struct TeamMember {
  std::string id;  ///< [A-Za-z0-9_]+
  double start_seconds = 0.0;
  Eigen::Isometry3d world_from_start = Eigen::Isometry3d::Identity();
};

/// Whether `id` is a usable robot id: one or more of [A-Za-z0-9_].
bool validRobotId(const std::string& id);

bool writeTeamFile(const std::string& path, const std::vector<TeamMember>& team, std::string* error);

/// Reads a team file; false with the line and what is wrong there on a bad line (a robot id that is not
/// [A-Za-z0-9_]+, a repeated id, a negative or non-finite start, not exactly 12 finite numbers after
/// it, a rotation that is not one) or no robot at all.
bool readTeamFile(const std::string& path, std::vector<TeamMember>* team, std::string* error);

}  // namespace sim
}  // namespace scan_context_loop
