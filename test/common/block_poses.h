// Poses around a rectangular block, for pose-graph tests that need no scans.
#pragma once

#include <cmath>
#include <cstddef>

#include <Eigen/Geometry>

#include "planar.h"

namespace scan_context_loop {
namespace test {

/// Keyframes a lap of the block: a keyframe every 2 m.
constexpr std::size_t kPerLap = 180;

/// The covariance of a verified loop (10 cm, 0.5 deg standard deviations).
inline Eigen::Matrix<double, 6, 6> verifiedCovariance() {
  Eigen::Matrix<double, 6, 1> d;
  d << 0.01, 0.01, 0.01, 7.6e-5, 7.6e-5, 7.6e-5;
  return d.asDiagonal();
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
