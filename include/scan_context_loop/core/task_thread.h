// A thread that runs the tasks posted to it one at a time, in order: the owner of state no other thread
// touches (a team's matcher), or the one that waits on slow calls so that nothing else does.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace scan_context_loop {

/// Thread-safe: mutex_ guards the queue and stop_; the thread runs tasks without holding it.
class TaskThread {
 public:
  /// `capacity`: tasks waiting at most; post() refuses more.
  explicit TaskThread(std::size_t capacity = 10000);
  /// stop(): the task in hand finishes, the ones waiting are dropped.
  ~TaskThread();
  TaskThread(const TaskThread&) = delete;
  TaskThread& operator=(const TaskThread&) = delete;

  /// Queues `task`; false (dropped) when the queue is full or the thread stopped. With `beyond_capacity`
  /// a full queue takes it all the same: for the replies to requests this thread made, which are as many as
  /// those requests, and which must not be lost to a flood of other tasks.
  bool post(std::function<void()> task, bool beyond_capacity = false);
  /// Ends the thread after the task in hand; later posts are refused. Idempotent.
  void stop();
  /// Tasks waiting.
  std::size_t waiting() const;
  /// Tasks that threw (the thread goes on with the next).
  std::size_t failures() const { return failures_; }

 private:
  void run();

  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> tasks_;
  bool stop_ = false;
  std::atomic<std::size_t> failures_{0};
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace scan_context_loop
