#include "polyline.h"

#include <algorithm>
#include <cmath>

#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {

std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& raw, double step, std::size_t* mark) {
  std::vector<Eigen::Vector2d> out(1, raw.front());
  double carried = 0.0;  // distance from the last sample to raw[k]
  std::size_t marked = 0;
  for (std::size_t k = 1; k < raw.size(); ++k) {
    if (k == *mark) marked = out.size();
    const Eigen::Vector2d d = raw[k] - raw[k - 1];
    const double length = d.norm();
    double s = step - carried;
    for (; s <= length; s += step) out.push_back(raw[k - 1] + d * (s / length));
    carried = length - (s - step);
  }
  *mark = marked;
  return out;
}

std::vector<PathPoint> smoothPath(const std::vector<Eigen::Vector2d>& points, int window) {
  std::vector<Eigen::Vector2d> smooth(points.size());
  const int n = static_cast<int>(points.size());
  for (int k = 0; k < n; ++k) {
    const int w = std::min({window, k, n - 1 - k});
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int d = -w; d <= w; ++d) sum += points[k + d];
    smooth[k] = sum / (2 * w + 1);
  }
  std::vector<PathPoint> path;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d d = smooth[std::min(k + 1, n - 1)] - smooth[std::max(k - 1, 0)];
    path.push_back({smooth[k].x(), smooth[k].y(), std::atan2(d.y(), d.x())});
  }
  return path;
}

/// Straight legs through the waypoints, corners rounded with arcs of `radius`, sampled every `step`.
std::vector<PathPoint> roundedPolyline(const std::vector<Eigen::Vector2d>& w, double radius, double step) {
  std::vector<PathPoint> out;
  if (w.size() < 2) return out;
  Eigen::Vector2d cursor = w[0];
  for (std::size_t k = 0; k + 1 < w.size(); ++k) {
    const Eigen::Vector2d dir = (w[k + 1] - w[k]).normalized();
    const double heading = std::atan2(dir.y(), dir.x());
    // Stop short of the corner to leave room for the arc (not at the last waypoint).
    double cut = 0.0;
    Eigen::Vector2d next_dir = dir;
    if (k + 2 < w.size()) {
      next_dir = (w[k + 2] - w[k + 1]).normalized();
      const double turn = std::atan2(dir.x() * next_dir.y() - dir.y() * next_dir.x(), dir.dot(next_dir));
      cut = std::fabs(turn) > 1e-6 ? radius * std::tan(std::fabs(turn) / 2) : 0.0;
    }
    const Eigen::Vector2d end = w[k + 1] - dir * cut;
    const double length = (end - cursor).norm();
    for (double s = 0.0; s < length; s += step) {
      const Eigen::Vector2d p = cursor + dir * s;
      out.push_back({p.x(), p.y(), heading});
    }
    cursor = end;
    if (cut > 0.0) {
      const double turn = std::atan2(dir.x() * next_dir.y() - dir.y() * next_dir.x(), dir.dot(next_dir));
      const double arc = std::fabs(turn) * radius;
      const double side = turn > 0 ? 1.0 : -1.0;
      const Eigen::Vector2d centre = cursor + side * radius * Eigen::Vector2d(-dir.y(), dir.x());
      for (double s = 0.0; s < arc; s += step) {
        const double h = heading + side * s / radius;
        const Eigen::Vector2d p = centre + side * radius * Eigen::Vector2d(std::sin(h), -std::cos(h));
        out.push_back({p.x(), p.y(), h});
      }
      cursor = w[k + 1] + next_dir * cut;
    }
  }
  out.push_back({w.back().x(), w.back().y(), out.empty() ? 0.0 : out.back().heading});
  return out;
}

TimedPath timedDrive(const std::vector<Eigen::Vector2d>& raw, std::size_t mark, double speed, double pause) {
  const std::vector<Eigen::Vector2d> points = resample(raw, 0.5, &mark);
  TimedPath drive;
  drive.path = smoothPath(points, 16);
  drive.times = distanceAlong(drive.path);
  for (std::size_t k = 0; k < drive.times.size(); ++k) {
    drive.times[k] = drive.times[k] / speed + (k >= mark ? pause : 0.0);
  }
  return drive;
}

}  // namespace sim
}  // namespace scan_context_loop
