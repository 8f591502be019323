#include "scan_context_loop/core/team_consistency.h"

#include <cmath>
#include <limits>

namespace scan_context_loop {

bool TeamConsistency::agree(const TeamLoopOffer& a, const TeamLoopOffer& b) const {
  // Where loop a's frame puts b's own keyframe, against where the odometry has it.
  const Eigen::Isometry3d frame_a = a.own_pose * a.relative * a.other_pose.inverse();  // T_own_odom<-other_odom
  const Eigen::Isometry3d predicted = frame_a * b.other_pose * b.relative.inverse();
  const Eigen::Isometry3d error = b.own_pose.inverse() * predicted;
  const double path = std::fabs(b.own_path - a.own_path) + std::fabs(b.other_path - a.other_path);
  const double translation = config_.consistency_translation + config_.consistency_drift * path;
  const double rotation = (config_.consistency_rotation + config_.consistency_drift * path) * M_PI / 180.0;
  return error.translation().norm() <= translation && Eigen::AngleAxisd(error.linear()).angle() <= rotation;
}

TeamRelease TeamConsistency::offer(const TeamLoopOffer& loop) {
  TeamRelease out;
  if (config_.consistency_min_support <= 0) {
    out.report.push_back(loop.handle);
    return out;
  }
  Loops& loops = pairs_[Pair{loop.robot, loop.run, loop.session, loop.own_session}];
  // The nearest confirmed loop (by odometry path) speaks for the frames where this one lies.
  const TeamLoopOffer* nearest = nullptr;
  double best = std::numeric_limits<double>::infinity();
  for (const TeamLoopOffer& c : loops.confirmed) {
    const double path = std::fabs(c.own_path - loop.own_path) + std::fabs(c.other_path - loop.other_path);
    if (path < best) {
      best = path;
      nearest = &c;
    }
  }
  if (nearest && agree(*nearest, loop)) {
    out.report.push_back(loop.handle);
    loops.confirmed.push_back(loop);
    return out;
  }
  // Otherwise a waiting loop that agrees confirms both; else it waits.
  for (auto it = loops.waiting.begin(); it != loops.waiting.end(); ++it) {
    if (!agree(*it, loop)) continue;
    out.report.push_back(it->handle);
    out.report.push_back(loop.handle);
    loops.confirmed.push_back(*it);
    loops.confirmed.push_back(loop);
    loops.waiting.erase(it);
    return out;
  }
  loops.waiting.push_back(loop);
  while (loops.waiting.size() > static_cast<std::size_t>(std::max(1, config_.consistency_window))) {
    out.dropped.push_back(loops.waiting.front().handle);
    loops.waiting.pop_front();
  }
  return out;
}

std::size_t TeamConsistency::waiting() const {
  std::size_t n = 0;
  for (const auto& [pair, loops] : pairs_) n += loops.waiting.size();
  return n;
}

}  // namespace scan_context_loop
