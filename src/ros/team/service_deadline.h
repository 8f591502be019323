// Service calls to another robot's node with a time limit. roscpp's ServiceClient::call has none once
// connected: a node that takes the request and never answers (hung, or hostile) would hold the calling
// thread for good, every later request behind it, and an unload joining that thread.
//
// How the limit works: each call goes through a persistent ServiceClient, whose connection this class's
// watchdog thread drops when the call outlives its deadline; roscpp then ends the waiting call with a
// failure. stop() drops the connection of a call in progress at once (unload, SIGINT) and refuses later
// calls. Locks: mutex_ guards everything below it; the call itself runs without it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include <ros/ros.h>

namespace scan_context_loop {

class ServiceDeadline {
 public:
  enum class Outcome {
    kAnswered,   ///< the service answered (its response may still say it refused)
    kNoService,  ///< the service did not appear within the timeout
    kFailed,     ///< the call failed at once (connection refused or closed by the other side)
    kTimedOut,   ///< no answer within the timeout: the connection was dropped
    kStopped,    ///< stop() was called before or during the call
  };
  static const char* describe(Outcome outcome);

  ServiceDeadline();
  ~ServiceDeadline();
  ServiceDeadline(const ServiceDeadline&) = delete;
  ServiceDeadline& operator=(const ServiceDeadline&) = delete;

  /// Calls `service` with `*srv`: waits at most `timeout` seconds for the service to exist, then at most
  /// `timeout` seconds for its answer. One call at a time (the caller's thread).
  template <typename Service>
  Outcome call(const std::string& service, Service* srv, double timeout) {
    if (stopped()) return Outcome::kStopped;
    if (!ros::service::waitForService(service, ros::Duration(timeout))) {
      return stopped() ? Outcome::kStopped : Outcome::kNoService;
    }
    // Persistent: its connection is one the watchdog can drop (a non-persistent call's is its own).
    ros::ServiceClient client = ros::NodeHandle().serviceClient<Service>(service, true);
    if (!arm(client, timeout)) return Outcome::kStopped;
    const bool answered = client.call(*srv);
    const Outcome dropped = disarm();
    client.shutdown();
    if (dropped != Outcome::kAnswered) return dropped;
    return answered ? Outcome::kAnswered : Outcome::kFailed;
  }

  /// Ends a call in progress now and refuses every later one. Idempotent.
  void stop();
  bool stopped() const;

 private:
  /// Starts the deadline of `client`'s call; false when stopped.
  bool arm(const ros::ServiceClient& client, double timeout);
  /// Ends it: kTimedOut or kStopped when the watchdog dropped the call, else kAnswered.
  Outcome disarm();
  void watch();

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  ros::ServiceClient client_;  // the call under way, when armed_
  bool armed_ = false;
  Outcome dropped_ = Outcome::kAnswered;  // set by the watchdog when it dropped the call
  bool dropping_ = false;                 // the watchdog is shutting client_ down (outside the lock)
  bool stop_ = false;
  std::chrono::steady_clock::time_point deadline_;
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace scan_context_loop
