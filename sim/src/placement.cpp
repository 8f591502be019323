#include "placement.h"

#include <algorithm>
#include <cmath>

namespace scan_context_loop {
namespace sim {

namespace {

Eigen::Vector2d axis(double yaw) { return {std::cos(yaw), std::sin(yaw)}; }

/// Half the rectangle's extent along the unit vector n.
double radiusAlong(const Footprint& f, const Eigen::Vector2d& n) {
  const Eigen::Vector2d u = axis(f.yaw), v(-u.y(), u.x());
  return f.half.x() * std::fabs(u.dot(n)) + f.half.y() * std::fabs(v.dot(n));
}

}  // namespace

double Footprint::distanceTo(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d u = axis(yaw), d = p - center;
  const Eigen::Vector2d local(u.dot(d), -u.y() * d.x() + u.x() * d.y());
  return (local.cwiseAbs() - half).cwiseMax(0.0).norm();
}

void Footprint::bounds(double margin, Eigen::Vector2d* lo, Eigen::Vector2d* hi) const {
  const Eigen::Vector2d extent(radiusAlong(*this, Eigen::Vector2d::UnitX()) + margin,
                               radiusAlong(*this, Eigen::Vector2d::UnitY()) + margin);
  *lo = center - extent;
  *hi = center + extent;
}

bool Footprint::overlaps(const Footprint& other, double margin) const {
  Footprint grown = *this;
  grown.half = (half.array() + margin).cwiseMax(0.0);
  const Eigen::Vector2d d = other.center - center;
  for (double yaw_axis : {yaw, yaw + M_PI / 2, other.yaw, other.yaw + M_PI / 2}) {
    const Eigen::Vector2d n = axis(yaw_axis);
    // Touching (within a millimetre) is not overlapping: terraced houses share walls.
    if (std::fabs(d.dot(n)) >= radiusAlong(grown, n) + radiusAlong(other, n) - 1e-3) return false;
  }
  return true;
}

int CellHash::index(double v) const { return static_cast<int>(std::floor(v / cell_)); }

void CellHash::insert(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, std::uint32_t item) {
  for (int i = index(lo.x()); i <= index(hi.x()); ++i) {
    for (int j = index(lo.y()); j <= index(hi.y()); ++j) cells_[key(i, j)].push_back(item);
  }
}

RoadMap::RoadMap(const std::vector<PathPoint>& dense) : grid_(8.0) {
  for (const auto& p : dense) {
    const Eigen::Vector2d q(p.x, p.y);
    grid_.insert(q, q, static_cast<std::uint32_t>(points_.size()));
    points_.push_back(q);
  }
}

bool RoadMap::clear(const Footprint& f, double clearance) const {
  Eigen::Vector2d lo, hi;
  f.bounds(clearance, &lo, &hi);
  return grid_.forEach(lo, hi, [&](std::uint32_t k) { return f.distanceTo(points_[k]) >= clearance; });
}

bool Occupancy::free(const Footprint& f, double margin) const {
  Eigen::Vector2d lo, hi;
  f.bounds(std::max(margin, 0.0), &lo, &hi);
  return grid_.forEach(lo, hi, [&](std::uint32_t k) { return !f.overlaps(placed_[k], margin); });
}

void Occupancy::mark(const Footprint& f) {
  Eigen::Vector2d lo, hi;
  f.bounds(0.0, &lo, &hi);
  grid_.insert(lo, hi, static_cast<std::uint32_t>(placed_.size()));
  placed_.push_back(f);
}

std::vector<PathPoint> densify(const std::vector<PathPoint>& path, double spacing) {
  std::vector<PathPoint> out;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const double dx = path[k + 1].x - path[k].x, dy = path[k + 1].y - path[k].y;
    const int n = std::max(1, static_cast<int>(std::hypot(dx, dy) / spacing));
    // The path's own headings: a vehicle standing still has no direction of travel to derive one from.
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / n;
      out.push_back({path[k].x + t * dx, path[k].y + t * dy, path[k].heading});
    }
  }
  if (!path.empty()) out.push_back(path.back());
  return out;
}

}  // namespace sim
}  // namespace scan_context_loop
