#include "loop_closure/keyframe_worker.h"

#include <cstdio>
#include <utility>

#include <pthread.h>
#include <ros/console.h>

#include "shared/exception_barrier.h"

namespace scan_context_loop {

namespace {

/// How the logs name a keyframe: "keyframe at STAMP".
std::string contextOf(const QueuedKeyframe& keyframe) {
  char context[64];
  std::snprintf(context, sizeof context, "keyframe at %.3f", keyframe.cloud->header.stamp.toSec());
  return context;
}

}  // namespace

KeyframeWorker::KeyframeWorker(const std::string& name, const WorkerParts& parts, int heap_statistics_interval,
                               std::function<void()> between_jobs)
    : name_(name), parts_(parts), between_jobs_(std::move(between_jobs)), heap_(heap_statistics_interval) {}

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
    const std::chrono::milliseconds poll(parts_.source->holding() ? 50 : 0);
    if (!parts_.queue->take(poll, &job)) return;
    // Everything the worker runs is behind the exception barrier: a throw is logged and counted, and
    // the worker goes on with the next job (a service's task reports its own failure: runOnWorker).
    runGuarded("taking the reconfigured settings", between_jobs_);
    if (job.task) runGuarded("a task", job.task);
    if (job.redraw_markers) {
      runGuarded("redrawing the markers", [&] { parts_.output->redrawMarkers(parts_.processor->database()); });
    }
    runGuarded("releasing the keyframes held for the extrinsic", [&] { parts_.source->release(&ready_); });
    processReady();
    if (job.has_keyframe) {
      const std::string context = contextOf(job.keyframe);
      runGuarded(context, [&] { parts_.source->offer(std::move(job.keyframe), &ready_); });
      processReady();
    }
  }
}

void KeyframeWorker::processReady() {
  for (const PosedKeyframe& keyframe : ready_) {
    runGuarded(contextOf(keyframe.queued), [&] { process(keyframe); });
    if (heap_.afterKeyframe(parts_.counters->queue_length.load() == 0)) {
      parts_.counters->heap_allocated = heap_.allocatedBytes();
      parts_.counters->heap_free = heap_.freeBytes();
      parts_.counters->heap_statistics_ms = heap_.lastMs();
    }
  }
  ready_.clear();
}

void KeyframeWorker::process(const PosedKeyframe& keyframe) {
  KeyframeClock clock;
  const bool want_cloud = parts_.output->cloudWanted();
  KeyframeResult result = parts_.processor->process(keyframe, want_cloud, &clock);
  if (!result.stored) return;
  const Database& database = parts_.processor->database();
  clock.publishing();
  parts_.output->publishKeyframe(keyframe, want_cloud ? &result.described : nullptr);
  parts_.processor->shareWithTeam(keyframe, &result);
  parts_.output->publishLoops(result.detection, keyframe.queued.pose_frame, database);
  clock.published();
  // The keyframe's whole time on the worker, markers included.
  scan_context_loop::KeyframeTiming timing;
  const bool timed = parts_.output->timingWanted();
  clock.finish(result.detection, keyframe, name_, parts_.counters, timed ? &timing : nullptr);
  if (timed) parts_.output->publishTiming(timing);
}

bool KeyframeWorker::runGuarded(const std::string& context, const std::function<void()>& work, std::string* what) {
  std::string why;
  if (runCatching(work, &why)) return true;
  ++parts_.counters->failures;
  ROS_ERROR_THROTTLE_NAMED(5.0, name_, "%s dropped: it threw: %s (the database is kept; %zu failures so far)",
                           context.c_str(), why.c_str(), parts_.counters->failures.load());
  parts_.processor->followDatabase();
  parts_.output->forgetShownMarkers();  // redraw everything with the keyframes it may have stored
  if (what) *what = why;
  return false;
}

}  // namespace scan_context_loop
