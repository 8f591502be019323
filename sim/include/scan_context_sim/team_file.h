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

#include "scan_context_loop/eval/team_sequence.h"

namespace scan_context_loop {
namespace sim {

/// A robot's line of team.txt: the evaluator's (eval/team_sequence.h), which reads the file back.
using TeamMember = eval::TeamStart;
using eval::readTeamFile;

bool writeTeamFile(const std::string& path, const std::vector<TeamMember>& team, std::string* error);

}  // namespace sim
}  // namespace scan_context_loop
