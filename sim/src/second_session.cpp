#include "scan_context_sim/second_session.h"

#include <cmath>

#include <Eigen/Core>

namespace scan_context_loop {
namespace sim {

namespace {

/// Whether q lies nearer than `offset` to the path within `window` metres of travel either side of
/// point k: on the inside of a corner sharper than the offset, where the lane's offset line folds back.
bool insideCorner(const std::vector<PathPoint>& path, const std::vector<double>& along, std::size_t k,
                  const Eigen::Vector2d& q, double offset, double window) {
  for (std::size_t i = k; i-- > 0 && along[k] - along[i] <= window;) {
    if (std::hypot(path[i].x - q.x(), path[i].y - q.y()) < offset - 1e-6) return true;
  }
  for (std::size_t i = k + 1; i < path.size() && along[i] - along[k] <= window; ++i) {
    if (std::hypot(path[i].x - q.x(), path[i].y - q.y()) < offset - 1e-6) return true;
  }
  return false;
}

}  // namespace

TimedPath secondSessionDrive(const std::vector<PathPoint>& path, const std::vector<double>& times,
                             const SecondSessionOptions& options) {
  TimedPath drive;
  if (path.empty() || times.size() != path.size()) return drive;
  std::vector<double> along(path.size(), 0.0);
  for (std::size_t k = 1; k < path.size(); ++k) {
    along[k] = along[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y);
  }
  const double offset = std::fabs(options.lane_offset);
  for (std::size_t k = path.size(); k-- > 0;) {
    const double heading = std::remainder(path[k].heading + M_PI, 2.0 * M_PI);
    // The right of the direction of travel is (sin h, -cos h).
    const Eigen::Vector2d q(path[k].x + options.lane_offset * std::sin(heading),
                            path[k].y - options.lane_offset * std::cos(heading));
    if (insideCorner(path, along, k, q, offset, 4.0 * offset)) continue;
    drive.path.push_back({q.x(), q.y(), heading});
    drive.times.push_back(times.back() - times[k]);
  }
  for (double& t : drive.times) t -= drive.times.front();
  return drive;
}

LaterDrive laterDrive(const TimedPath& second, double first_duration, const SecondSessionOptions& options) {
  LaterDrive later;
  later.path = second.path;
  later.changed = options.changed;
  const double start = first_duration + options.days_later * 86400.0;
  for (double t : second.times) later.times.push_back(start + t);
  return later;
}

}  // namespace sim
}  // namespace scan_context_loop
