// The latest message of a (latched) topic, for the rostests.
#pragma once

#include <functional>
#include <mutex>
#include <string>

#include <ros/ros.h>

namespace scan_context_loop {
namespace test {

template <typename M>
class Latest {
 public:
  Latest(ros::NodeHandle nh, const std::string& topic)
      : sub_(nh.subscribe(topic, 2, &Latest::on, this)) {}
  /// Unsubscribes first (waiting for a callback in progress): the message it writes is declared after.
  ~Latest() { sub_.shutdown(); }
  /// The latest message once `ready` holds for it; false after `seconds` (with the latest in `out`).
  bool waitFor(const std::function<bool(const M&)>& ready, double seconds, M* out) const {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (have_ && ready(latest_)) {
          *out = latest_;
          return true;
        }
      }
      ros::WallDuration(0.1).sleep();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (have_) *out = latest_;  // for the failure message
    return false;
  }

 private:
  void on(const M& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = msg;
    have_ = true;
  }
  ros::Subscriber sub_;
  mutable std::mutex mutex_;  // guards latest_ and have_ (callback thread vs. test thread)
  M latest_;
  bool have_ = false;
};

}  // namespace test
}  // namespace scan_context_loop
