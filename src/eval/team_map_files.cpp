// What scan_context_evaluate --team prints and writes about the team's map (team_map.h), with or
// without the backend.
#include <cstdio>
#include <fstream>

#include "scan_context_loop/eval/team_map.h"

namespace scan_context_loop {
namespace eval {

namespace {

void writeErrorWithPoses(std::ostream& out, const char* name, const TrajectoryError& e) {
  out << "\"" << name << "\": {\"poses\": " << e.poses << ", \"rmse_m\": " << e.rmse << ", \"mean_m\": " << e.mean
      << ", \"max_m\": " << e.max << "}";
}

}  // namespace

std::vector<std::string> teamMapSummary(const TeamSequence& team, const TeamMap& map) {
  std::vector<std::string> lines;
  if (!map.computed) {
    lines.push_back("no map of the team: " + map.note);
    return lines;
  }
  char line[512];
  std::snprintf(line, sizeof line,
                "merged map in %s's frame (%zu loops refused by the graph): ATE of the joined robots' keyframes "
                "%.3f m RMSE / %.3f m max (their odometry alone from the true starts: %.3f / %.3f)",
                team.robots.front().id.c_str(), map.loops_rejected, map.corrected.rmse, map.corrected.max,
                map.odometry.rmse, map.odometry.max);
  lines.push_back(line);
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const TeamMapRobot& x = map.robots[r];
    if (!x.joined) {
      std::snprintf(line, sizeof line, "  %s: not joined to %s's map (%zu own loops; odometry alone %.3f m RMSE)",
                    team.robots[r].id.c_str(), team.robots.front().id.c_str(), x.own_loops, x.odometry.rmse);
    } else {
      std::snprintf(line, sizeof line,
                    "  %s: frame error %.3f m, %.3f deg; ATE corrected %.3f m RMSE / %.3f max, odometry alone %.3f / "
                    "%.3f (%zu own loops, %zu loops into the others')",
                    team.robots[r].id.c_str(), x.frame_translation_error, x.frame_rotation_error, x.corrected.rmse,
                    x.corrected.max, x.odometry.rmse, x.odometry.max, x.own_loops, x.team_loops);
    }
    lines.push_back(line);
  }
  return lines;
}

bool writeTeamJson(const std::string& path, const TeamSequence& team, const TeamEvaluation& e, const TeamMap& map,
                   std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out.precision(6);
  out << "{\n  \"team\": \"" << team.dir << "\",\n  \"anchor\": \"" << team.robots.front().id << "\",\n"
      << "  \"revisit_radius_m\": " << e.revisit_radius << ",\n"
      << "  \"inter_robot\": {\"loops\": " << e.loops.size() << ", \"true_positives\": " << e.true_positives
      << ", \"false_positives\": " << e.false_positives << ", \"precision\": " << e.precision
      << ", \"recall\": " << e.recall << ", \"queries\": " << e.queries << ", \"revisits\": " << e.revisits
      << ", \"revisits_found\": " << e.revisits_found << ", \"repeated_pairs\": " << e.repeated_pairs
      << ", \"translation_error_m\": {\"median\": " << e.translation_error_median
      << ", \"p90\": " << e.translation_error_p90
      << "}, \"rotation_error_deg\": {\"median\": " << e.rotation_error_median << ", \"p90\": " << e.rotation_error_p90
      << "}},\n"
      << "  \"exchange\": {\"keyframes\": " << e.keyframes << ", \"record_bytes\": " << e.record_bytes
      << ", \"record_bytes_per_keyframe\": " << e.record_bytes_mean << ", \"record_bytes_max\": " << e.record_bytes_max
      << ", \"fetched\": " << e.fetched << ", \"fetched_bytes\": " << e.fetched_bytes
      << ", \"fetched_bytes_mean\": " << e.fetched_bytes_mean
      << ", \"sent_bytes_per_keyframe\": " << e.sent_bytes_per_keyframe << "},\n"
      << "  \"map\": {\"computed\": " << (map.computed ? "true" : "false") << ", \"note\": \"" << map.note << "\"";
  if (map.computed) {
    out << ", \"loops_refused\": " << map.loops_rejected << ", ";
    writeErrorWithPoses(out, "corrected", map.corrected);
    out << ", ";
    writeErrorWithPoses(out, "odometry", map.odometry);
  }
  out << "},\n  \"robots\": [";
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const TeamRobotEvaluation& x = e.robots[r];
    out << (r ? "," : "") << "\n    {\"id\": \"" << team.robots[r].id
        << "\", \"start_seconds\": " << team.robots[r].start_seconds << ", \"keyframes\": " << x.keyframes
        << ", \"record_bytes\": " << x.record_bytes << ", \"received_bytes\": " << x.received_bytes
        << ", \"fetched\": " << x.fetched << ", \"fetched_bytes\": " << x.fetched_bytes
        << ", \"fetch_failures\": " << x.fetch_failures << ", \"queries\": " << x.queries
        << ", \"revisits\": " << x.revisits << ", \"revisits_found\": " << x.revisits_found
        << ", \"true_positives\": " << x.true_positives << ", \"false_positives\": " << x.false_positives;
    if (map.computed) {
      const TeamMapRobot& m = map.robots[r];
      out << ", \"joined\": " << (m.joined ? "true" : "false") << ", \"frame_error_m\": " << m.frame_translation_error
          << ", \"frame_error_deg\": " << m.frame_rotation_error << ", \"own_loops\": " << m.own_loops
          << ", \"team_loops\": " << m.team_loops << ", ";
      writeErrorWithPoses(out, "corrected", m.corrected);
      out << ", ";
      writeErrorWithPoses(out, "odometry", m.odometry);
    }
    out << "}";
  }
  out << "\n  ]\n}\n";
  return out.good();
}

}  // namespace eval
}  // namespace scan_context_loop
