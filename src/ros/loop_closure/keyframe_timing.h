// Where a keyframe's time on the worker went: wall and CPU time, preemptions and page faults from when
// the worker took it, the core's share (Detection's parts) and publishing; the counters, a throttled
// warning for a slow keyframe, and the keyframe_timing message.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

#include "loop_closure/keyframe_source.h"
#include "loop_closure/node_counters.h"
#include "scan_context_loop/KeyframeTiming.h"
#include "scan_context_loop/core/detector.h"

namespace scan_context_loop {

/// The calling thread's CPU time [ms], involuntary context switches and page faults so far.
struct ThreadUsage {
  double cpu_ms = 0.0;
  long preemptions = 0, page_faults = 0;
  static ThreadUsage now();
};

/// One keyframe's clock, started when the worker takes it; worker-only.
class KeyframeClock {
 public:
  using Clock = std::chrono::steady_clock;

  KeyframeClock() : started_(Clock::now()), usage_at_start_(ThreadUsage::now()) {}

  /// Brackets the core's pipeline.
  void detecting() { detect_start_ = Clock::now(); }
  void detected() { detect_end_ = Clock::now(); }
  /// Brackets publishing (called around each part; the times add up).
  void publishing() { publish_start_ = Clock::now(); }
  void published() { publishing_ += Clock::now() - publish_start_; }

  /// Ends the keyframe `detection` stored: the counters' last and longest keyframe, a throttled warning
  /// (named `name`) when it was slow, and, when `timing` is given, its message.
  void finish(const Detection& detection, const PosedKeyframe& keyframe, const std::string& name,
              NodeCounters* counters, scan_context_loop::KeyframeTiming* timing) const;

 private:
  Clock::time_point started_, detect_start_, detect_end_, publish_start_;
  Clock::duration publishing_{0};
  ThreadUsage usage_at_start_;
};

}  // namespace scan_context_loop
