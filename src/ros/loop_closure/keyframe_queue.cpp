#include "loop_closure/keyframe_queue.h"

#include <utility>

namespace scan_context_loop {

bool KeyframeQueue::push(QueuedKeyframe keyframe) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (keyframes_.size() >= capacity_) return false;
    keyframes_.push_back(std::move(keyframe));
    *length_ = keyframes_.size();
  }
  cv_.notify_one();
  return true;
}

bool KeyframeQueue::pushTask(std::function<void()> task) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return false;
    tasks_.push_back(std::move(task));
  }
  cv_.notify_all();
  return true;
}

void KeyframeQueue::requestRedraw() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    redraw_ = true;
  }
  cv_.notify_all();
}

void KeyframeQueue::wake() {
  std::lock_guard<std::mutex> lock(mutex_);
  woken_ = true;
  cv_.notify_one();
}

std::size_t KeyframeQueue::stop() {
  std::size_t discarded = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    discarded = keyframes_.size();
  }
  cv_.notify_all();
  return discarded;
}

bool KeyframeQueue::take(std::chrono::milliseconds poll, WorkerJob* job) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto ready = [this] { return stop_ || !keyframes_.empty() || redraw_ || woken_ || !tasks_.empty(); };
  if (poll.count() == 0) {
    cv_.wait(lock, ready);
  } else {
    cv_.wait_for(lock, poll, ready);
  }
  if (stop_) return false;
  woken_ = false;
  if (!tasks_.empty()) {
    job->task = std::move(tasks_.front());
    tasks_.pop_front();
  }
  std::swap(job->redraw_markers, redraw_);
  if (!job->task && !keyframes_.empty()) {
    job->keyframe = std::move(keyframes_.front());
    keyframes_.pop_front();
    *length_ = keyframes_.size();
    job->keyframe.queue_length = keyframes_.size();
    job->has_keyframe = true;
  }
  return true;
}

}  // namespace scan_context_loop
