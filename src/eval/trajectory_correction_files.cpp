// The trajectory correction's files: trajectory_error.json and trajectory_corrected.csv.
#include "scan_context_loop/eval/trajectory_correction.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace scan_context_loop {
namespace eval {

namespace {

void writeError(std::ostream& out, const char* name, const TrajectoryError& e, const char* indent = "  ") {
  out << indent << "\"" << name << "\": {\"rmse_m\": " << e.rmse << ", \"mean_m\": " << e.mean
      << ", \"max_m\": " << e.max << "}";
}

/// A note or a path as a JSON string's contents (quotes and backslashes, which they do not hold, replaced).
std::string jsonText(std::string text) {
  std::replace(text.begin(), text.end(), '"', '\'');
  std::replace(text.begin(), text.end(), '\\', '/');
  return text;
}

}  // namespace

bool writeTrajectoryErrorJson(const std::string& path, const TrajectoryCorrection& c, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out.precision(6);
  if (!c.computed) {
    out << "{\n  \"computed\": false,\n  \"note\": \"" << jsonText(c.note) << "\"\n}\n";
    return out.good();
  }
  out << "{\n  \"computed\": true,\n  \"odometry_source\": \"" << (c.own_odometry ? "odom_poses.txt" : "truth")
      << "\",\n";
  if (!c.note.empty()) out << "  \"note\": \"" << jsonText(c.note) << "\",\n";
  out << "  \"keyframes\": " << c.odometry.poses << ",\n";
  writeError(out, "odometry", c.odometry);
  out << ",\n";
  writeError(out, "corrected", c.corrected);
  out << ",\n  \"loops\": " << c.loops << ",\n  \"sequence_loops\": " << (c.loops - c.prior_loops)
      << ",\n  \"prior_loops\": " << c.prior_loops << ",\n";
  if (c.in_prior) {
    out << "  \"prior\": {\"source\": \"" << jsonText(c.prior_source) << "\", \"keyframes\": " << c.prior_keyframes
        << ", \"held_fixed\": true, \"moved_m\": " << c.prior_moved << ", ";
    writeError(out, "odometry", c.prior_odometry, "");
    out << "},\n";
  }
  writeError(out, "plain_scan_context", c.plain);
  out << ",\n  \"plain_loops\": " << c.plain_loops << ",\n  \"plain_false_loops\": " << c.plain_false_loops << ",\n";
  writeError(out, "with_one_false_loop", c.with_false_loop);
  out << ",\n  \"false_loop_gap_m\": " << c.false_loop_gap << ",\n";
  out << "  \"corrected_by_part\": {\"revisited\": {\"rmse_m\": " << c.corrected_revisited.rmse
      << ", \"keyframes\": " << c.corrected_revisited.keyframes << "}, \"rest\": {\"rmse_m\": " << c.corrected_rest.rmse
      << ", \"keyframes\": " << c.corrected_rest.keyframes << "}},\n";
  writeError(out, "reported_loops_true_poses", c.reported_true);
  out << ",\n";
  writeError(out, "oracle", c.oracle);
  out << ",\n  \"oracle_loops\": " << c.oracle_loops << "\n}\n";
  return out.good();
}

std::string trajectoryErrorLine(const TrajectoryCorrection& c) {
  char line[1024];
  if (!c.computed) {
    std::snprintf(line, sizeof(line), "trajectory error: not computed (%s)", c.note.c_str());
    return line;
  }
  std::string loops = std::to_string(c.loops) + " loops";
  if (c.in_prior) {
    loops += " (" + std::to_string(c.loops - c.prior_loops) + " within the sequence, " + std::to_string(c.prior_loops) +
             " into the prior's " + std::to_string(c.prior_keyframes) + " keyframes, held fixed)";
  }
  // Millimetres where the truth is the odometry: what is left is the loops' registration error.
  const int digits = c.own_odometry ? 2 : 3;
  std::snprintf(line, sizeof(line),
                "trajectory error (ATE RMSE / max): odometry%s %.*f / %.*f m; corrected with the %s %.*f / %.*f m; "
                "plain Scan Context (%zu loops, %zu false) %.*f / %.*f m; with one false loop added %.*f / %.*f m; "
                "the same loops at their true poses %.*f / %.*f m; oracle (%zu revisits, true poses) %.*f / %.*f m",
                c.own_odometry ? "" : " (the truth: no odometry of its own)", digits, c.odometry.rmse, digits,
                c.odometry.max, loops.c_str(), digits, c.corrected.rmse, digits, c.corrected.max, c.plain_loops,
                c.plain_false_loops, digits, c.plain.rmse, digits, c.plain.max, digits, c.with_false_loop.rmse, digits,
                c.with_false_loop.max, digits, c.reported_true.rmse, digits, c.reported_true.max, c.oracle_loops, digits,
                c.oracle.rmse, digits, c.oracle.max);
  std::string text = line;
  if (c.in_prior) {
    std::snprintf(line, sizeof(line), "; the prior's stored poses %.2f / %.2f m off its truth, moved %.3f m",
                  c.prior_odometry.rmse, c.prior_odometry.max, c.prior_moved);
    text += line;
  }
  return text;
}

bool writeCorrectedTrajectoryCsv(const std::string& path, const Sequence& s, const TrajectoryCorrection& c,
                                 std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "frame,odom_x,odom_y,odom_z,odom_yaw,corrected_x,corrected_y,corrected_z,corrected_yaw\n";
  // Heading [rad] of a pose's x axis in the truth frame, for top-down drawings.
  const auto yaw = [](const Eigen::Isometry3d& pose) {
    const Eigen::Matrix3d r = pose.rotation();
    return std::atan2(r(1, 0), r(0, 0));
  };
  for (std::size_t k = 0; k < s.frames.size() && k < c.corrected_poses.size(); ++k) {
    // In the truth's frame: the alignment the trajectory error found for each.
    const Eigen::Vector3d o = c.odometry.alignment * s.odometry[k].translation();
    const Eigen::Vector3d r = c.corrected.alignment * c.corrected_poses[k].translation();
    out << s.frames[k] << ',' << o.x() << ',' << o.y() << ',' << o.z() << ','
        << yaw(c.odometry.alignment * s.odometry[k]) << ',' << r.x() << ',' << r.y() << ',' << r.z() << ','
        << yaw(c.corrected.alignment * c.corrected_poses[k]) << '\n';
  }
  return out.good();
}

}  // namespace eval
}  // namespace scan_context_loop
