// Poses around a rectangular block, for pose-graph tests that need no scans.
#pragma once

#include <cmath>
#include <cstddef>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace test {

inline Eigen::Isometry3d planar(double x, double y, double yaw) {
  return Eigen::Translation3d(x, y, 0.0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
}

/// Keyframe k of a 120 m x 60 m block's perimeter, counter-clockwise, `in` metres inside the outer lane,
/// `per_lap` keyframes a lap (k modulo a lap).
inline Eigen::Isometry3d blockPose(std::size_t k, double in, std::size_t per_lap) {
  const double w = 120.0 - 2 * in, h = 60.0 - 2 * in;
  double s = (w + h) * 2.0 * static_cast<double>(k % per_lap) / static_cast<double>(per_lap);
  if (s < w) return planar(in + s, in, 0.0);
  if ((s -= w) < h) return planar(in + w, in + s, M_PI / 2);
  if ((s -= h) < w) return planar(in + w - s, in + h, M_PI);
  return planar(in, in + h - (s - w), -M_PI / 2);
}

}  // namespace test
}  // namespace scan_context_loop
