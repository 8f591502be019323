#include "scan_context_loop/ros/keyframe_worker.h"

#include <cstdio>
#include <utility>

#include <pthread.h>
#include <ros/console.h>

#include "scan_context_loop/ros/exception_barrier.h"

namespace scan_context_loop {

namespace {

/// How the logs name a keyframe: "keyframe at STAMP".
std::string contextOf(const QueuedKeyframe& keyframe) {
  char context[64];
  std::snprintf(context, sizeof context, "keyframe at %.3f", keyframe.cloud->header.stamp.toSec());
  return context;
}

}  // namespace

KeyframeWorker::KeyframeWorker(const std::string& name, const RosOptions& options, KeyframeQueue* queue,
                               KeyframeProcessor* processor, MarkerPublisher* markers, NodeCounters* counters,
                               std::function<void()> between_jobs)
    : name_(name),
      options_(options),
      queue_(queue),
      processor_(processor),
      markers_(markers),
      counters_(counters),
      between_jobs_(std::move(between_jobs)),
      heap_(options.heap_statistics_interval) {}

void KeyframeWorker::start() { thread_ = std::thread(&KeyframeWorker::work, this); }

void KeyframeWorker::join() {
  if (thread_.joinable()) thread_.join();
}

void KeyframeWorker::work() {
  // Named for top -H, perf and the soak's per-thread CPU accounting (/proc/PID/task/TID/comm).
  pthread_setname_np(pthread_self(), "scl_loop_worker");
  while (true) {
    WorkerJob job;
    // Keyframes held for the extrinsic: look at tf again every 50 ms (never waiting on it).
    const std::chrono::milliseconds poll(held_.empty() ? 0 : 50);
    if (!queue_->take(poll, &job)) return;
    // Everything the worker runs is behind the exception barrier: a throw is logged and counted, and
    // the worker goes on with the next job (a service's task reports its own failure: runOnWorker).
    runGuarded("taking the reconfigured settings", between_jobs_);
    if (job.task) runGuarded("a task", job.task);
    if (job.redraw_markers) runGuarded("redrawing the markers", [&] { markers_->redraw(processor_->database()); });
    runGuarded("releasing the keyframes held for the extrinsic", [&] { releaseHeld(); });
    if (job.has_keyframe) {
      const std::string context = contextOf(job.keyframe);
      runGuarded(context, [&] { processOrHold(std::move(job.keyframe)); });
    }
  }
}

void KeyframeWorker::processGuarded(QueuedKeyframe keyframe) {
  const std::string context = contextOf(keyframe);
  runGuarded(context, [&] { processor_->process(std::move(keyframe)); });
  if (heap_.afterKeyframe(counters_->queue_length.load() == 0)) {
    counters_->heap_allocated = heap_.allocatedBytes();
    counters_->heap_free = heap_.freeBytes();
    counters_->heap_statistics_ms = heap_.lastMs();
  }
}

void KeyframeWorker::processOrHold(QueuedKeyframe keyframe) {
  if (held_.empty() && processor_->resolveExtrinsic(keyframe) != SensorExtrinsic::State::kWaiting) {
    processGuarded(std::move(keyframe));
    return;
  }
  if (held_.size() >= static_cast<std::size_t>(options_.queue_size)) {
    held_.pop_front();
    ++counters_->dropped;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "%zu keyframes held for the tf extrinsic: the oldest dropped (%zu dropped so far)",
                            held_.size(), counters_->dropped.load());
  }
  held_.push_back(std::move(keyframe));
  counters_->held = held_.size();
}

void KeyframeWorker::releaseHeld() {
  if (held_.empty() || processor_->resolveExtrinsic(held_.front()) == SensorExtrinsic::State::kWaiting) return;
  while (!held_.empty()) {
    QueuedKeyframe keyframe = std::move(held_.front());
    held_.pop_front();
    counters_->held = held_.size();
    processGuarded(std::move(keyframe));
  }
}

bool KeyframeWorker::runGuarded(const std::string& context, const std::function<void()>& work, std::string* what) {
  std::string why;
  if (runCatching(work, &why)) return true;
  ++counters_->failures;
  ROS_ERROR_THROTTLE_NAMED(5.0, name_, "%s dropped: it threw: %s (the database is kept; %zu failures so far)",
                           context.c_str(), why.c_str(), counters_->failures.load());
  processor_->followDatabase();
  if (what) *what = why;
  return false;
}

}  // namespace scan_context_loop
