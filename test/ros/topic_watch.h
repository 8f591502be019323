// What a test hears on one topic: the latest message (Latest, for latched state such as a path), every
// message in arrival order (Collected), or the log lines on /rosout (RosoutWatch).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

namespace scan_context_loop {
namespace test {

/// The latest message of a topic that passes `accept` (every message when none is given). On a topic with
/// several publishers, `accept` picks one: otherwise another's message may replace it before a wait sees it.
template <typename M>
class Latest {
 public:
  Latest(ros::NodeHandle nh, const std::string& topic, std::function<bool(const M&)> accept = nullptr)
      : accept_(std::move(accept)), sub_(nh.subscribe(topic, 100, &Latest::on, this)) {}
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
  /// The same once no message came for `quiet` seconds as well: the publisher's final state.
  bool waitForFinal(const std::function<bool(const M&)>& ready, double quiet, double seconds, M* out) const {
    return waitFor([&](const M& m) { return (ros::WallTime::now() - arrived_).toSec() >= quiet && ready(m); }, seconds,
                   out);
  }

 private:
  void on(const M& msg) {
    if (accept_ && !accept_(msg)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = msg;
    have_ = true;
    arrived_ = ros::WallTime::now();
  }
  mutable std::mutex mutex_;  // guards latest_, have_ and arrived_ (callback thread vs. test thread)
  M latest_;
  bool have_ = false;
  ros::WallTime arrived_;
  const std::function<bool(const M&)> accept_;
  // Last: subscribed once the data its callback writes exists (a message may come at once).
  ros::Subscriber sub_;
};

/// The first `keep` messages of a topic, in arrival order, and how many came in all.
template <typename M>
class Collected {
 public:
  Collected(ros::NodeHandle nh, const std::string& topic, std::size_t keep = 100000)
      : keep_(keep), sub_(nh.subscribe(topic, 1000, &Collected::on, this)) {}
  /// Unsubscribes first (waiting for a callback in progress), as ~Latest does.
  ~Collected() { sub_.shutdown(); }

  std::vector<M> messages() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_;
  }
  std::size_t count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }
  /// Waits until the topic has a publisher; false after `seconds`.
  bool waitForPublisher(double seconds) const {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end) {
      if (sub_.getNumPublishers() > 0) return true;
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }

 private:
  void on(const M& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (messages_.size() < keep_) messages_.push_back(msg);
    ++count_;
  }
  const std::size_t keep_;
  mutable std::mutex mutex_;  // guards messages_ and count_ (callback threads vs. test thread)
  std::vector<M> messages_;
  std::size_t count_ = 0;
  // Last, as in Latest.
  ros::Subscriber sub_;
};

/// Every /rosout message from the moment it subscribes.
class RosoutWatch {
 public:
  explicit RosoutWatch(ros::NodeHandle nh)
      : sub_(nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000, [this](const rosgraph_msgs::Log::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          logs_.push_back(*m);
        })) {}
  ~RosoutWatch() { sub_.shutdown(); }

  /// The messages of `level` from node `name` that contain `text`.
  std::size_t count(std::uint8_t level, const std::string& name, const std::string& text) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::count_if(logs_.begin(), logs_.end(), [&](const rosgraph_msgs::Log& m) {
      return m.level == level && m.name == name && m.msg.find(text) != std::string::npos;
    });
  }
  /// Waits until count() is at least one; false after `seconds`.
  bool waitFor(std::uint8_t level, const std::string& name, const std::string& text, double seconds) const {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end) {
      if (count(level, name, text) > 0) return true;
      ros::WallDuration(0.1).sleep();
    }
    return false;
  }
  std::size_t publishers() const { return sub_.getNumPublishers(); }

 private:
  mutable std::mutex mutex_;  // guards logs_ (callback vs. test thread)
  std::vector<rosgraph_msgs::Log> logs_;
  // Last: subscribed once logs_ exists (a message may come at once).
  ros::Subscriber sub_;
};

}  // namespace test
}  // namespace scan_context_loop
