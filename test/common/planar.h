// Angles and planar poses for tests: degrees, yaw, the gap between two headings, a pose on the ground.
#pragma once

#include <cmath>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace test {

constexpr double kDeg = M_PI / 180.0;

inline double yawOf(const Eigen::Isometry3d& t) { return std::atan2(t(1, 0), t(0, 0)); }

/// |a - b| wrapped to [0, pi].
inline double headingGap(double a, double b) { return std::fabs(std::remainder(a - b, 2.0 * M_PI)); }

inline Eigen::Isometry3d planar(double x, double y, double yaw) {
  return Eigen::Translation3d(x, y, 0.0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
}

}  // namespace test
}  // namespace scan_context_loop
