// malloc's statistics (what the process holds allocated, what malloc holds free), read on the worker.
#pragma once

#include <cstddef>

namespace scan_context_loop {

/// glibc's mallinfo2 walks every free chunk of every malloc arena, each under the arena's lock: on a
/// heap of a few GB with freed memory scattered through it that takes tens of ms, while every thread
/// that allocates in that arena waits (doc/testing.md, the soak). So the worker reads them itself, every `interval`
/// keyframes once its queue is empty (a read never delays a waiting keyframe), and the diagnostics report the last
/// values. Only the worker thread calls it.
class HeapStatistics {
 public:
  /// interval: keyframes between reads; 0 never reads.
  explicit HeapStatistics(int interval) : interval_(interval) {}
  /// Called after each keyframe; reads when `interval` keyframes have passed since the last read and
  /// the queue is empty. Returns true when it read.
  bool afterKeyframe(bool queue_empty);
  std::size_t reads() const { return reads_; }
  /// The last read's wall time [ms].
  double lastMs() const { return last_ms_; }
  /// At the last read: bytes allocated through malloc (mmapped blocks included) and bytes malloc holds
  /// free; -1 before the first read.
  long long allocatedBytes() const { return allocated_; }
  long long freeBytes() const { return free_; }
  /// Whether this platform's malloc reports them (glibc 2.33 or later, not under ASan or TSan, whose
  /// allocator glibc does not see); elsewhere nothing is read and the diagnostics leave them out.
  static bool available();

 private:
  int interval_;
  int since_ = 0;
  std::size_t reads_ = 0;
  double last_ms_ = 0.0;
  long long allocated_ = -1, free_ = -1;
};

}  // namespace scan_context_loop
