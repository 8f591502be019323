#include "scan_context_loop/core/task_thread.h"

namespace scan_context_loop {

TaskThread::TaskThread(std::size_t capacity) : capacity_(capacity), thread_([this] { run(); }) {}

TaskThread::~TaskThread() { stop(); }

bool TaskThread::post(std::function<void()> task, bool beyond_capacity) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_ || (tasks_.size() >= capacity_ && !beyond_capacity)) return false;
    tasks_.push_back(std::move(task));
  }
  cv_.notify_one();
  return true;
}

void TaskThread::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    tasks_.clear();
  }
  cv_.notify_one();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

std::size_t TaskThread::waiting() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tasks_.size();
}

void TaskThread::run() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return stop_ || !tasks_.empty(); });
      if (stop_) return;
      task = std::move(tasks_.front());
      tasks_.pop_front();
    }
    try {
      task();
    } catch (...) {
      ++failures_;  // the caller's tasks report their own errors; this one is only counted
    }
  }
}

}  // namespace scan_context_loop
