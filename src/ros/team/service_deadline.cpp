#include "team/service_deadline.h"

namespace scan_context_loop {

const char* ServiceDeadline::describe(Outcome outcome) {
  switch (outcome) {
    case Outcome::kAnswered:
      return "answered";
    case Outcome::kNoService:
      return "the service is not there";
    case Outcome::kFailed:
      return "the call failed";
    case Outcome::kTimedOut:
      return "no answer in time";
    case Outcome::kStopped:
      return "the node is stopping";
  }
  return "";
}

ServiceDeadline::ServiceDeadline() : thread_([this] { watch(); }) {}

ServiceDeadline::~ServiceDeadline() {
  stop();
  if (thread_.joinable()) thread_.join();
}

bool ServiceDeadline::stopped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stop_;
}

void ServiceDeadline::stop() {
  std::lock_guard<std::mutex> lock(mutex_);
  stop_ = true;
  cv_.notify_all();
}

bool ServiceDeadline::arm(const ros::ServiceClient& client, double timeout) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (stop_) return false;
  client_ = client;
  armed_ = true;
  dropped_ = Outcome::kAnswered;
  deadline_ = std::chrono::steady_clock::now() +
              std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout));
  cv_.notify_all();
  return true;
}

ServiceDeadline::Outcome ServiceDeadline::disarm() {
  std::unique_lock<std::mutex> lock(mutex_);
  // The caller shuts its client down next: never while the watchdog's shutdown of it is under way
  // (roscpp's ServiceClient::shutdown is not safe to run twice at once: both would release its link).
  cv_.wait(lock, [this] { return !dropping_; });
  armed_ = false;
  client_ = ros::ServiceClient();
  cv_.notify_all();
  return dropped_;
}

void ServiceDeadline::watch() {
  // Dropped again this often while the call has not returned: a drop that raced with the start of the
  // call (roscpp then connects afresh) is caught by the next.
  constexpr std::chrono::milliseconds kRedrop(200);
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    if (stop_ && !armed_) return;
    if (!armed_) {
      cv_.wait(lock);
      continue;
    }
    const auto now = std::chrono::steady_clock::now();
    if (!stop_ && now < deadline_) {
      cv_.wait_until(lock, deadline_);
      continue;
    }
    // Past its deadline, or stopping: the call loses its connection, and the caller's call() returns
    // false; disarm() says why.
    if (dropped_ == Outcome::kAnswered) dropped_ = stop_ ? Outcome::kStopped : Outcome::kTimedOut;
    {
      ros::ServiceClient client = client_;
      dropping_ = true;  // disarm() waits for the end of this shutdown
      lock.unlock();
      client.shutdown();  // drops the connection: roscpp ends the waiting call
      lock.lock();
      dropping_ = false;
    }
    cv_.notify_all();
    cv_.wait_for(lock, kRedrop);
  }
}

}  // namespace scan_context_loop
