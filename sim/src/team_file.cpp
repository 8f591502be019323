#include "scan_context_sim/team_file.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace scan_context_loop {
namespace sim {

bool validRobotId(const std::string& id) {
  if (id.empty()) return false;
  for (char c : id) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return true;
}

bool writeTeamFile(const std::string& path, const std::vector<TeamMember>& team, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "# robot_id start_seconds T_world<-robot_start (rows 0-2, row-major)\n";
  out.precision(9);
  for (const TeamMember& m : team) {
    out << m.id << ' ' << m.start_seconds;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) out << ' ' << m.world_from_start.matrix()(r, c);
    }
    out << '\n';
  }
  if (!out.good()) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

bool readTeamFile(const std::string& path, std::vector<TeamMember>* team, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open " + path;
    return false;
  }
  team->clear();
  std::set<std::string> ids;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    TeamMember m;
    if (!(fields >> m.id)) continue;  // blank or a comment
    const auto bad = [&](const std::string& why) {
      *error = path + ":" + std::to_string(number) + ": " + why;
      return false;
    };
    if (!validRobotId(m.id)) return bad("robot id '" + m.id + "' is not [A-Za-z0-9_]+");
    if (!ids.insert(m.id).second) return bad("robot '" + m.id + "' comes twice");
    if (!(fields >> m.start_seconds) || !std::isfinite(m.start_seconds) || m.start_seconds < 0.0) {
      return bad("start_seconds must be a number >= 0");
    }
    Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (!(fields >> matrix(r, c))) return bad("T_world<-robot_start needs 12 numbers");
      }
    }
    std::string extra;
    if (fields >> extra) return bad("more than 14 fields");
    if (!matrix.allFinite()) return bad("T_world<-robot_start is not finite");
    const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
    const bool orthonormal = (rotation.transpose() * rotation).isApprox(Eigen::Matrix3d::Identity(), 1e-6);
    if (!orthonormal || rotation.determinant() < 0.0) {
      return bad("T_world<-robot_start's rotation is not a rotation");
    }
    m.world_from_start.matrix() = matrix;
    team->push_back(m);
  }
  if (team->empty()) {
    *error = path + ": no robot";
    return false;
  }
  return true;
}

}  // namespace sim
}  // namespace scan_context_loop
