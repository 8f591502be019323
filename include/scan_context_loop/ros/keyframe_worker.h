// The node's worker thread: it takes the queue's jobs in order (a service's task, the live settings, a
// marker redraw, a keyframe), holds keyframes while the sensor extrinsic they need is missing from tf,
// and runs each keyframe and task behind the exception barrier.
#pragma once

#include <deque>
#include <functional>
#include <string>
#include <thread>

#include "scan_context_loop/ros/heap_statistics.h"
#include "scan_context_loop/ros/keyframe_processor.h"
#include "scan_context_loop/ros/keyframe_queue.h"
#include "scan_context_loop/ros/marker_publisher.h"
#include "scan_context_loop/ros/node_counters.h"
#include "scan_context_loop/ros/parameters.h"

namespace scan_context_loop {

/// Its state (the held keyframes) is the worker thread's alone: no lock.
class KeyframeWorker {
 public:
  /// `between_jobs` runs on the worker before each job (it takes the settings dynamic_reconfigure
  /// accepted). The pointers and `options` must outlive this.
  KeyframeWorker(const std::string& name, const RosOptions& options, KeyframeQueue* queue,
                 KeyframeProcessor* processor, MarkerPublisher* markers, NodeCounters* counters,
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
  /// Processes `keyframe` behind the exception barrier (runGuarded), and the heap statistics after it.
  void processGuarded(QueuedKeyframe keyframe);
  /// Holds `keyframe` while the extrinsic it needs is missing (at most queue_size keyframes; the oldest
  /// held is dropped first), else processes it with those held before it.
  void processOrHold(QueuedKeyframe keyframe);
  /// Processes the held keyframes, in order, once the extrinsic is known or given up on.
  void releaseHeld();

  std::string name_;
  const RosOptions& options_;
  KeyframeQueue* queue_;
  KeyframeProcessor* processor_;
  MarkerPublisher* markers_;
  NodeCounters* counters_;
  std::function<void()> between_jobs_;
  HeapStatistics heap_;
  std::deque<QueuedKeyframe> held_;  // keyframes waiting for the extrinsic, in order
  std::thread thread_;
};

}  // namespace scan_context_loop
