#include "polyline.h"

#include <algorithm>
#include <cmath>

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

}  // namespace sim
}  // namespace scan_context_loop
