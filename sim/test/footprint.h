// Geometry helpers shared by the simulator tests.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {
namespace test {

/// The same solid: kind, material, place, size and heading (its times may differ).
inline bool sameShape(const Primitive& a, const Primitive& b) {
  return a.kind == b.kind && a.material == b.material && a.center == b.center && a.half == b.half && a.yaw == b.yaw &&
         a.z0 == b.z0 && a.z1 == b.z1 && a.free_path == b.free_path;
}

/// A solid there at every time, and one there at time t.
inline bool always(const Primitive& p) { return p.present_from < -1e299 && p.present_to > 1e299; }
inline bool present(const Primitive& p, double t) { return t >= p.present_from && t < p.present_to; }

/// Horizontal distance from q to the solid's footprint (0 inside it); an ellipsoid or a cylinder counts
/// as the circle of its larger radius.
inline double distanceTo(const Primitive& p, const Eigen::Vector2d& q) {
  const Eigen::Vector2d d = q - Eigen::Vector2d(p.center.x(), p.center.y());
  if (p.kind != Primitive::Kind::kBox) return std::max(0.0, d.norm() - std::max(p.half.x(), p.half.y()));
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  const Eigen::Vector2d local(std::fabs(c * d.x() + s * d.y()) - p.half.x(),
                              std::fabs(-s * d.x() + c * d.y()) - p.half.y());
  return local.cwiseMax(0.0).norm();
}

}  // namespace test
}  // namespace sim
}  // namespace scan_context_loop
