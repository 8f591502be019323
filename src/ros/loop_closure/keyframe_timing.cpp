#include "loop_closure/keyframe_timing.h"

#include <algorithm>

#include <ros/console.h>
#include <sys/resource.h>
#include <time.h>

namespace scan_context_loop {

namespace {

/// A keyframe longer than this on the worker [ms] brings a throttled warning saying where the time went
/// (at the 10 Hz of a LiDAR, a keyframe stream has 100 ms a scan; the node takes a few).
constexpr double kSlowKeyframeMs = 50.0;

/// The parts of LoopDetector::process that Detection times [ms].
double coreMs(const Detection& d) {
  return (d.descriptor_seconds + d.query_seconds + d.verify_seconds + d.ground_check_seconds + d.choose_seconds) * 1e3;
}

double ms(std::chrono::steady_clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

}  // namespace

ThreadUsage ThreadUsage::now() {
  ThreadUsage u;
  timespec cpu{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu) == 0) u.cpu_ms = cpu.tv_sec * 1e3 + cpu.tv_nsec * 1e-6;
  rusage r{};
  if (getrusage(RUSAGE_THREAD, &r) == 0) {
    u.preemptions = r.ru_nivcsw;
    u.page_faults = r.ru_minflt + r.ru_majflt;
  }
  return u;
}

void KeyframeClock::finish(const Detection& detection, const PosedKeyframe& keyframe, const std::string& name,
                           NodeCounters* counters, scan_context_loop::KeyframeTiming* timing) const {
  // The CPU time is read before the wall clock, as it was read after it at the start, so that the
  // CPU interval lies within the wall one (read after the timing message was built, it also counted
  // that, and came out above the wall time now and then).
  const ThreadUsage usage = ThreadUsage::now();
  const double processing_ms = ms(Clock::now() - started_);
  counters->last_keyframe_ms = processing_ms;
  if (processing_ms > counters->max_keyframe_ms.load()) counters->max_keyframe_ms = processing_ms;
  const double cpu_ms = usage.cpu_ms - usage_at_start_.cpu_ms;
  const long preemptions = std::max(0L, usage.preemptions - usage_at_start_.preemptions);
  const double detect_ms = ms(detect_end_ - detect_start_), publish_ms = ms(publishing_);
  if (processing_ms > kSlowKeyframeMs) {
    ROS_WARN_THROTTLE_NAMED(
        10.0, name,
        "keyframe %zu took %.1f ms on the worker (%.1f ms of its CPU, preempted %ld times): describe %.1f, "
        "query and add %.1f, verify %.1f, ground check %.1f, choose loops %.1f, rest of the core %.1f, "
        "publishing %.1f, other %.1f ms",
        detection.index, processing_ms, cpu_ms, preemptions, detection.descriptor_seconds * 1e3,
        detection.query_seconds * 1e3, detection.verify_seconds * 1e3, detection.ground_check_seconds * 1e3,
        detection.choose_seconds * 1e3, detect_ms - coreMs(detection), publish_ms,
        processing_ms - detect_ms - publish_ms);
  }
  if (!timing) return;
  const QueuedKeyframe& queued = keyframe.queued;
  timing->header.stamp = queued.cloud->header.stamp;
  timing->header.frame_id = queued.pose_frame;
  timing->keyframe_id = static_cast<std::uint32_t>(detection.index);
  timing->database_size = static_cast<std::uint32_t>(counters->database_size.load());
  timing->queue_ms = ms(started_ - queued.queued);
  timing->processing_ms = processing_ms;
  timing->describe_query_ms = (detection.descriptor_seconds + detection.query_seconds) * 1e3;
  timing->verify_ms = detection.verify_seconds * 1e3;
  timing->ground_check_ms = detection.ground_check_seconds * 1e3;
  timing->choose_ms = detection.choose_seconds * 1e3;
  timing->detect_ms = detect_ms;
  timing->publish_ms = publish_ms;
  timing->queue_length = static_cast<std::uint32_t>(queued.queue_length);
  timing->cpu_ms = cpu_ms;
  timing->preemptions = static_cast<std::uint32_t>(preemptions);
  timing->page_faults = static_cast<std::uint32_t>(std::max(0L, usage.page_faults - usage_at_start_.page_faults));
}

}  // namespace scan_context_loop
