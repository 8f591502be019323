// The worker's inbox: keyframes from the input callbacks, tasks from the services, marker redraws and
// wake-ups from the spinner threads, and the stop from the destructor.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>

#include <Eigen/Geometry>
#include <sensor_msgs/PointCloud2.h>

namespace scan_context_loop {

/// A keyframe waiting for the worker.
struct QueuedKeyframe {
  sensor_msgs::PointCloud2ConstPtr cloud;
  bool has_pose = false;  ///< false in tf mode: the worker looks it up
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // Frame ids as tf2 names them (frame_ids.h), normalised by the callback.
  std::string pose_frame;
  std::string child_frame;                       ///< the odometry's child_frame_id (odom mode)
  std::string cloud_frame;                       ///< the cloud's frame_id
  std::chrono::steady_clock::time_point queued;  ///< when the callback queued it
  std::size_t queue_length = 0;                  ///< keyframes left in the queue when the worker took it
};

/// What the worker takes from the queue at once: a task comes before a keyframe, one at a time.
struct WorkerJob {
  std::function<void()> task;  ///< a service's work, or empty
  bool has_keyframe = false;   ///< `keyframe` was taken (never with a task)
  QueuedKeyframe keyframe;
  bool redraw_markers = false;  ///< a marker subscriber connected since the last take
};

/// Thread-safe: every member locks mutex_, which guards all the state below (the keyframes, the tasks,
/// the redraw and wake-up flags, stop); cv_ wakes the worker. Callbacks push, the worker takes.
class KeyframeQueue {
 public:
  /// `capacity`: keyframes it holds at most (queue_size). `length` (the diagnostics' queue length) is
  /// set, under the lock, whenever a keyframe enters or leaves; it must outlive this.
  KeyframeQueue(std::size_t capacity, std::atomic<std::size_t>* length) : capacity_(capacity), length_(length) {}

  /// Input callbacks: queues `keyframe`; false (and nothing queued) when it is full.
  bool push(QueuedKeyframe keyframe);
  /// Services: queues `task` for the worker; false once stop() was called.
  bool pushTask(std::function<void()> task);
  /// A marker subscriber connected: the worker publishes every marker once.
  void requestRedraw();
  /// Wakes the worker for work it finds elsewhere (settings dynamic_reconfigure accepted).
  void wake();
  /// The worker's next take() returns false; tasks queued before are never run. Returns how many keyframes
  /// were still queued: they will not be processed.
  std::size_t stop();

  /// Worker: waits for work (at most `poll` when it is not zero) and takes it. False once stop() was
  /// called.
  bool take(std::chrono::milliseconds poll, WorkerJob* job);

 private:
  const std::size_t capacity_;
  std::atomic<std::size_t>* const length_;
  std::mutex mutex_;            // guards every member below, and the writes to *length_
  std::condition_variable cv_;  // the worker waits on it in take()
  std::deque<QueuedKeyframe> keyframes_;
  std::deque<std::function<void()>> tasks_;  // service work for the worker, in order
  bool redraw_ = false;
  bool woken_ = false;
  bool stop_ = false;
};

}  // namespace scan_context_loop
