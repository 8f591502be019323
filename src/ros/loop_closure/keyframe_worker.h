// The node's worker thread: it takes the queue's jobs in order (a service's task, the live settings, a
// marker redraw, a keyframe) and runs each behind the exception barrier. A keyframe's path, straight:
// the source gives it a pose (or holds it for the extrinsic), the processor runs it through the core's
// pipeline, the output publishes what came of it.
#pragma once

#include <functional>
#include <string>
#include <thread>

#include "loop_closure/heap_statistics.h"
#include "loop_closure/keyframe_processor.h"
#include "loop_closure/keyframe_queue.h"
#include "loop_closure/keyframe_source.h"
#include "loop_closure/node_counters.h"
#include "loop_closure/node_output.h"

namespace scan_context_loop {

/// The parts a worker drives; all must outlive it.
struct WorkerParts {
  KeyframeQueue* queue;
  KeyframeSource* source;
  KeyframeProcessor* processor;
  LoopClosureOutput* output;
  NodeCounters* counters;
};

/// Its state is the worker thread's alone: no lock.
class KeyframeWorker {
 public:
  /// `between_jobs` runs on the worker before each job (it takes the settings dynamic_reconfigure
  /// accepted); `heap_statistics_interval` as NodeOptions says.
  KeyframeWorker(const std::string& name, const WorkerParts& parts, int heap_statistics_interval,
                 std::function<void()> between_jobs);
  /// Joins the thread (stop the queue first).
  ~KeyframeWorker() { join(); }

  void start();
  /// Waits for the thread to end: it does once the queue is stopped, after the job in hand.
  void join();

  /// Worker: runs `work` (one keyframe, one service task) behind the exception barrier: what it throws is
  /// logged with `context`, counted, and the counters and markers follow the database, which is kept.
  /// Returns false, with the exception's what() in `what`, when it threw.
  bool runGuarded(const std::string& context, const std::function<void()>& work, std::string* what = nullptr);

 private:
  void work();
  /// The keyframes the source made ready, each through process() behind the barrier.
  void processReady();
  /// One keyframe with its pose: processed, published, shared with the team, timed.
  void process(const PosedKeyframe& keyframe);

  std::string name_;
  WorkerParts parts_;
  std::function<void()> between_jobs_;
  HeapStatistics heap_;
  std::vector<PosedKeyframe> ready_;  // keyframes the source gave a pose, in order
  std::thread thread_;
};

}  // namespace scan_context_loop
