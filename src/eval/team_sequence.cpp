#include "scan_context_loop/eval/team_sequence.h"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "scan_context_loop/core/team_matcher.h"
#include "scan_context_loop/eval/kitti_io.h"

namespace scan_context_loop {
namespace eval {

namespace {

/// One line of team.txt (comment stripped, not blank); false with what is wrong.
bool parseRobot(const std::string& line, TeamStart* robot, std::string* why) {
  std::istringstream in(line);
  in >> robot->id;
  if (!validRobotId(robot->id)) {
    *why = "robot id '" + robot->id.substr(0, 64) + "' is not " + kRobotIdRule;
    return false;
  }
  if (!(in >> robot->start_seconds) || !std::isfinite(robot->start_seconds) || robot->start_seconds < 0.0) {
    *why = "expected a start in seconds (finite, not negative) after the robot id";
    return false;
  }
  std::string rest;
  std::getline(in, rest);
  if (!kitti::parsePoseRow(rest, &robot->world_from_start)) {
    *why = "expected exactly 12 finite numbers (T_world<-robot_start) after the start";
    return false;
  }
  const Eigen::Matrix3d r = robot->world_from_start.linear();
  if (!(r.transpose() * r).isIdentity(1e-6) || r.determinant() < 0.0) {
    *why = "T_world<-robot_start's rotation is not one";
    return false;
  }
  return true;
}

}  // namespace

bool readTeamFile(const std::string& path, std::vector<TeamStart>* team, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open " + path;
    return false;
  }
  std::vector<TeamStart> read;
  std::set<std::string> ids;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    TeamStart robot;
    std::string why;
    if (!parseRobot(line, &robot, &why)) {
      *error = path + ":" + std::to_string(number) + ": " + why;
      return false;
    }
    if (!ids.insert(robot.id).second) {
      *error = path + ":" + std::to_string(number) + ": robot " + robot.id + " is there twice";
      return false;
    }
    read.push_back(std::move(robot));
  }
  if (read.empty()) {
    *error = path + ": no robot";
    return false;
  }
  *team = std::move(read);
  return true;
}

bool loadTeam(const std::string& dir, const SequenceOptions& options, TeamSequence* team, std::string* error) {
  const std::string path = dir + "/team.txt";
  std::vector<TeamStart> starts;
  if (!readTeamFile(path, &starts, error)) {
    if (error->rfind("cannot open", 0) == 0) *error += " (a team sequence: team.txt and one folder per robot)";
    return false;
  }
  TeamSequence t;
  t.dir = dir;
  for (TeamStart& start : starts) {
    TeamRobot robot;
    static_cast<TeamStart&>(robot) = std::move(start);
    if (!loadSequence(dir + "/" + robot.id, options, &robot.sequence, error)) return false;
    t.robots.push_back(std::move(robot));
  }
  *team = std::move(t);
  return true;
}

}  // namespace eval
}  // namespace scan_context_loop
