// A rate limit for what a node sends (team_max_bytes_per_second).
#pragma once

#include <algorithm>

namespace scan_context_loop {

/// A token bucket: on average at most `rate` bytes a second, bursts up to `burst` bytes. Not thread-safe.
class RateLimit {
 public:
  RateLimit(double rate, double burst) : rate_(rate), burst_(burst), tokens_(burst) {}
  /// Takes `bytes` at time `now` [s] if the budget allows; false (nothing taken) when not.
  bool take(double bytes, double now) {
    if (last_ >= 0.0 && now > last_) tokens_ = std::min(burst_, tokens_ + (now - last_) * rate_);
    if (last_ < 0.0 || now > last_) last_ = now;
    if (bytes > tokens_) return false;
    tokens_ -= bytes;
    return true;
  }

 private:
  double rate_, burst_, tokens_;
  double last_ = -1.0;
};

/// At most one event per interval of a clock that may jump back (ROS time when `rosbag play --loop` starts
/// the bag again): a time before the last event starts afresh instead of waiting for that time to come
/// round again. Not thread-safe.
class MinInterval {
 public:
  /// Whether an event at `now` [s] is `interval` [s] or more after the last one (or there was none).
  bool due(double now, double interval) const { return !any_ || now < last_ || now - last_ >= interval; }
  void record(double now) {
    any_ = true;
    last_ = now;
  }

 private:
  bool any_ = false;
  double last_ = 0.0;
};

}  // namespace scan_context_loop
