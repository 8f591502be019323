#include "scan_context_loop/consistency.h"

#include <cmath>

#include "scan_context_loop/database.h"

namespace scan_context_loop {

Eigen::Isometry3d Loop::relative() const {
  return verified ? verification.relative : priorPose(alignment.yaw, viewpoint);
}

bool loopsAgree(const Loop& a, const Loop& b, const Database& database, double* translation_error,
                double* rotation_error) {
  const Keyframe& i = database.keyframe(a.query);
  const Keyframe& j = database.keyframe(a.match);
  const Keyframe& k = database.keyframe(b.query);
  const Keyframe& l = database.keyframe(b.match);
  if (!i.info.pose || !j.info.pose || !k.info.pose || !l.info.pose) return false;
  // Loop b carried to a's keyframes through the odometry, against loop a itself.
  const Eigen::Isometry3d predicted = i.info.pose->inverse() * *k.info.pose * b.relative() *
                                      l.info.pose->inverse() * *j.info.pose;
  const Eigen::Isometry3d cycle = a.relative().inverse() * predicted;
  const double t = cycle.translation().norm();
  const double r = Eigen::AngleAxisd(cycle.linear()).angle();
  if (translation_error) *translation_error = t;
  if (rotation_error) *rotation_error = r;
  const Config& c = database.config();
  const double path = std::fabs(i.path_length - k.path_length) + std::fabs(j.path_length - l.path_length);
  return t <= c.consistency_translation + c.consistency_drift * path &&
         r <= c.consistency_rotation * M_PI / 180.0;
}

void ConsistencyFilter::advance(std::size_t query, std::vector<Loop>* dropped) {
  const std::size_t window = static_cast<std::size_t>(config_.consistency_window);
  while (!recent_.empty() && recent_.front().loop.query + window < query) {
    if (!recent_.front().confirmed) dropped->push_back(recent_.front().loop);
    recent_.pop_front();
  }
}

void ConsistencyFilter::offer(const Loop& loop, const Database& database, std::vector<Loop>* confirmed) {
  Entry entry;
  entry.loop = loop;
  entry.loop.support = 0;
  for (Entry& other : recent_) {
    if (other.loop.query + static_cast<std::size_t>(config_.consistency_window) < loop.query) continue;
    if (!loopsAgree(entry.loop, other.loop, database)) continue;
    ++entry.loop.support;
    ++other.loop.support;
    if (!other.confirmed && other.loop.support >= config_.consistency_min_support) {
      other.confirmed = true;
      confirmed->push_back(other.loop);
    }
  }
  if (entry.loop.support >= config_.consistency_min_support) {
    entry.confirmed = true;
    confirmed->push_back(entry.loop);
  }
  recent_.push_back(entry);
}

std::size_t ConsistencyFilter::waiting() const {
  std::size_t n = 0;
  for (const auto& e : recent_) n += !e.confirmed;
  return n;
}

}  // namespace scan_context_loop
