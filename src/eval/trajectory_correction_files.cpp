// The trajectory correction's files: trajectory_error.json and trajectory_corrected.csv.
#include "scan_context_loop/eval/trajectory_correction.h"

#include <cmath>
#include <fstream>

namespace scan_context_loop {
namespace eval {

namespace {

void writeError(std::ostream& out, const char* name, const TrajectoryError& e) {
  out << "  \"" << name << "\": {\"rmse_m\": " << e.rmse << ", \"mean_m\": " << e.mean << ", \"max_m\": " << e.max
      << "}";
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
    out << "{\n  \"computed\": false,\n  \"note\": \"" << c.note << "\"\n}\n";
    return out.good();
  }
  out << "{\n  \"computed\": true,\n  \"keyframes\": " << c.odometry.poses << ",\n";
  writeError(out, "odometry", c.odometry);
  out << ",\n";
  writeError(out, "corrected", c.corrected);
  out << ",\n  \"loops\": " << c.loops << ",\n";
  writeError(out, "plain_scan_context", c.plain);
  out << ",\n  \"plain_loops\": " << c.plain_loops << ",\n  \"plain_false_loops\": " << c.plain_false_loops << ",\n";
  writeError(out, "with_one_false_loop", c.with_false_loop);
  out << ",\n  \"false_loop_gap_m\": " << c.false_loop_gap << "\n}\n";
  return out.good();
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
