#include "scan_context_loop/core/consistency.h"

#include <cmath>

#include "scan_context_loop/core/acceptance_rule.h"
#include "scan_context_loop/core/database.h"

namespace scan_context_loop {

Eigen::Isometry3d Loop::relative() const {
  return verified || verification.needs_support || verification.odometry_contradicted
             ? verification.relative
             : priorPose(alignment.yaw, viewpoint);
}

void Loop::markConfirmed() {
  verified = true;
  verification.accepted = true;
  verification.rejected_by.clear();
  verification.rejection_value = verification.rejection_limit = 0.0;
}

bool loopsAgree(const Loop& a, const Loop& b, const Database& database, double* translation_error,
                double* rotation_error, bool strict) {
  const Keyframe& i = database.keyframe(a.query);
  const Keyframe& j = database.keyframe(a.match);
  const Keyframe& k = database.keyframe(b.query);
  const Keyframe& l = database.keyframe(b.match);
  if (!i.info.pose || !j.info.pose || !k.info.pose || !l.info.pose) return false;
  // The odometry relates the two queries, and the two matches, only within a session.
  if (i.session != k.session || j.session != l.session) return false;
  // Loop b carried to a's keyframes through the odometry, against loop a itself.
  const Eigen::Isometry3d predicted =
      i.info.pose->inverse() * *k.info.pose * b.relative() * l.info.pose->inverse() * *j.info.pose;
  const Eigen::Isometry3d cycle = a.relative().inverse() * predicted;
  const double t = cycle.translation().norm();
  const double r = Eigen::AngleAxisd(cycle.linear()).angle();
  if (translation_error) *translation_error = t;
  if (rotation_error) *rotation_error = r;
  const Config& c = database.config();
  const double path =
      strict ? 0.0 : std::fabs(i.path_length - k.path_length) + std::fabs(j.path_length - l.path_length);
  return t <= c.consistency_translation + c.consistency_drift * path && r <= c.consistency_rotation * M_PI / 180.0;
}

void ConsistencyFilter::advance(std::size_t query, std::vector<Loop>* dropped) {
  const std::size_t window = static_cast<std::size_t>(config_.consistency_window);
  while (!recent_.empty() && recent_.front().loop.query + window < query) {
    if (!recent_.front().confirmed) {
      // Reported as turned down by the consistency check, with the support it had and needed.
      Loop loop = recent_.front().loop;
      loop.verified = false;
      loop.verification.record(unsupportedVerdict(loop.support, loop.verification.odometry_contradicted, config_));
      dropped->push_back(loop);
    }
    recent_.pop_front();
  }
}

bool ConsistencyFilter::near(const Entry& a, const Entry& b) const {
  const std::size_t window = static_cast<std::size_t>(config_.consistency_window);
  return a.loop.query <= b.loop.query + window && b.loop.query <= a.loop.query + window;
}

int ConsistencyFilter::supportNeeded(const Loop& loop) const {
  return requiredSupport(loop.verification.odometry_contradicted, config_);
}

bool ConsistencyFilter::supports(const Loop& giver, const Loop& taker) {
  // A loop the odometry contradicted supports only others like it: while the odometry is broken, the
  // true loops of a revisit all disagree with it and confirm each other; a loop the odometry agrees with
  // is not confirmed by one it contradicts.
  return !giver.verification.odometry_contradicted || taker.verification.odometry_contradicted;
}

bool ConsistencyFilter::outranked(const Entry& entry, const Database& database) const {
  if (!entry.loop.verification.odometry_contradicted) return false;
  for (const Entry& other : recent_) {
    if (&other == &entry || other.loop.verification.needs_support || !near(other, entry)) continue;
    if (other.loop.verification.odometry_excess >= entry.loop.verification.odometry_excess) continue;
    if (!loopsAgree(entry.loop, other.loop, database)) return true;
  }
  return false;
}

void ConsistencyFilter::confirm(Entry* entry, const Database& database, std::vector<Loop>* confirmed) {
  entry->confirmed = true;
  entry->loop.markConfirmed();
  confirmed->push_back(entry->loop);
  confirmWeak(*entry, database, confirmed);
}

void ConsistencyFilter::confirmWeak(const Entry& entry, const Database& database, std::vector<Loop>* confirmed) {
  if (entry.loop.verification.needs_support) return;
  // A confirmed loop that passed in full confirms the waiting loops that need support and agree with it.
  for (Entry& other : recent_) {
    if (other.confirmed || !other.loop.verification.needs_support || !near(other, entry)) continue;
    if (!supports(entry.loop, other.loop) || !loopsAgree(other.loop, entry.loop, database, nullptr, nullptr, true))
      continue;
    ++other.loop.support;
    other.confirmed = true;
    other.loop.markConfirmed();
    confirmed->push_back(other.loop);
  }
}

void ConsistencyFilter::offer(const Loop& loop, const Database& database, std::vector<Loop>* confirmed) {
  Entry entry;
  entry.loop = loop;
  entry.loop.support = 0;
  recent_.push_back(entry);
  Entry& added = recent_.back();  // deque: references stay valid while elements are only appended
  const bool weak = added.loop.verification.needs_support;
  for (std::size_t i = 0; i + 1 < recent_.size(); ++i) {
    Entry& other = recent_[i];
    const bool other_weak = other.loop.verification.needs_support;
    // Loops that need support neither support each other nor count as support for a loop that passed in
    // full: in a street of repeated buildings, a wrong loop that barely passes comes with a run of wrong
    // ones that need support, all consistent with it. They are confirmed by a confirmed loop that passed
    // in full, and only when they agree with it strictly (without the drift allowance).
    if (other_weak || !near(other, added)) continue;
    if (weak && !other.confirmed) continue;  // confirm(other) looks for `added` if other is confirmed later
    if (!loopsAgree(added.loop, other.loop, database, nullptr, nullptr, weak)) continue;
    if (weak) {
      if (!supports(other.loop, added.loop)) continue;
      ++added.loop.support;
      confirm(&added, database, confirmed);
      break;
    }
    if (supports(other.loop, added.loop)) ++added.loop.support;
    if (!supports(added.loop, other.loop)) continue;
    ++other.loop.support;
    if (!other.confirmed && other.loop.support >= supportNeeded(other.loop) && !outranked(other, database)) {
      confirm(&other, database, confirmed);
    }
  }
  if (!weak && !added.confirmed && added.loop.support >= supportNeeded(added.loop) && !outranked(added, database)) {
    confirm(&added, database, confirmed);
  }
}

void ConsistencyFilter::add(const Loop& loop, const Database& database, std::vector<Loop>* confirmed) {
  Entry entry;
  entry.loop = loop;
  entry.confirmed = true;
  recent_.push_back(entry);
  const Entry& added = recent_.back();
  if (added.loop.verification.needs_support) return;  // it supports nothing
  for (std::size_t i = 0; i + 1 < recent_.size(); ++i) {
    Entry& other = recent_[i];
    if (other.confirmed || other.loop.verification.needs_support || !near(other, added)) continue;
    if (!supports(added.loop, other.loop) || !loopsAgree(added.loop, other.loop, database)) continue;
    if (++other.loop.support >= supportNeeded(other.loop) && !outranked(other, database)) {
      confirm(&other, database, confirmed);
    }
  }
  confirmWeak(added, database, confirmed);
}

std::size_t ConsistencyFilter::waiting() const {
  std::size_t n = 0;
  for (const auto& e : recent_) n += !e.confirmed;
  return n;
}

}  // namespace scan_context_loop
