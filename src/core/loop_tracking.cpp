#include "scan_context_loop/core/loop_tracking.h"

#include <algorithm>
#include <cmath>

namespace scan_context_loop {

void LoopTracker::anchor(const Loop& loop) {
  if (!loop.verified || loop.verification.needs_support) return;
  if (anchor_ && anchor_->query > loop.query) return;
  anchor_ = loop;
}

bool LoopTracker::reaches(const Database& database, std::size_t query) const {
  const double reach_path = database.config().track_distance;
  if (!anchor_ || !(reach_path > 0.0) || query >= database.size() || anchor_->query >= query) return false;
  const Keyframe& q = database.keyframe(query);
  const Keyframe& a = database.keyframe(anchor_->query);
  return q.info.pose && a.info.pose && database.keyframe(anchor_->match).info.pose && q.session == a.session &&
         q.path_length - a.path_length <= reach_path;
}

std::optional<TrackedCandidate> LoopTracker::predict(const Database& database, std::size_t query, std::size_t eligible,
                                                     const std::function<bool(std::size_t)>& usable) const {
  if (!reaches(database, query)) return std::nullopt;
  const Keyframe& q = database.keyframe(query);
  const Keyframe& a = database.keyframe(anchor_->query);
  const Keyframe& m = database.keyframe(anchor_->match);
  // The query's pose in the match session's odometry frame: through the anchor loop, then along the
  // query session's odometry.
  const Eigen::Isometry3d predicted =
      *m.info.pose * anchor_->relative().inverse() * a.info.pose->inverse() * *q.info.pose;
  // Only keyframes within `reach` of path from the anchor's match qualify (nearAnchorMatch). Sessions are
  // contiguous runs of keyframes along which the path length never decreases, so those form one run
  // around the match: walk out from it to the run's ends rather than scan the whole session, which on a
  // long single-session drive (scripts/measure/soak) cost every tracked keyframe time in proportion to the
  // database.
  const double reach = q.path_length - a.path_length + kReach;
  std::size_t begin = anchor_->match;
  while (begin > 0) {
    const Keyframe& k = database.keyframe(begin - 1);
    if (k.session != m.session || m.path_length - k.path_length > reach) break;
    --begin;
  }
  const std::size_t end = std::min(eligible, database.size());
  std::optional<TrackedCandidate> best;
  double best_gap = kReach;
  for (std::size_t i = begin; i < end; ++i) {
    const Keyframe& k = database.keyframe(i);
    if (k.session != m.session || k.path_length - m.path_length > reach) break;
    if (!k.info.pose || !nearAnchorMatch(database, query, i) || (usable && !usable(i))) continue;
    const double gap = (k.info.pose->translation() - predicted.translation()).norm();
    if (gap > best_gap) continue;
    best_gap = gap;
    best = TrackedCandidate{i, predicted.inverse() * *k.info.pose, gap};
  }
  return best;
}

bool LoopTracker::nearAnchorMatch(const Database& database, std::size_t query, std::size_t index) const {
  const Keyframe& m = database.keyframe(anchor_->match);
  const Keyframe& k = database.keyframe(index);
  const double travelled = database.keyframe(query).path_length - database.keyframe(anchor_->query).path_length;
  return k.session == m.session && std::fabs(k.path_length - m.path_length) <= travelled + kReach;
}

bool LoopTracker::agrees(const Loop& loop, const Database& database, bool strict) const {
  return reaches(database, loop.query) && nearAnchorMatch(database, loop.query, loop.match) &&
         loopsAgree(loop, *anchor_, database, nullptr, nullptr, strict);
}

}  // namespace scan_context_loop
