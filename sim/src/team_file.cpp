#include "scan_context_sim/team_file.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace scan_context_loop {
namespace sim {

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

}  // namespace sim
}  // namespace scan_context_loop
