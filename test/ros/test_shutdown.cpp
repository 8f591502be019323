// rostest: unloading the nodelet and stopping its process while a burst of keyframes keeps its queue
// full. (a) The nodelet is unloaded from a running manager (its unload service, as `rosrun nodelet
// nodelet unload` calls it) in the middle of a burst: the call must return within a few seconds and
// the manager must keep serving. (b) SIGINT to a standalone node, and to a manager with the nodelet
// loaded, in the middle of a burst: the process must exit with status 0 within a few seconds. Under
// `scripts/dev/test --sanitize` the processes run with AddressSanitizer and LeakSanitizer, whose report at
// exit changes that status.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>

#include "child_process.h"
#include "harness.h"

namespace scan_context_loop {
namespace test {
namespace {

// How long an unload or a SIGINT exit may take: the worker finishes the keyframe in hand (one
// verification, well under a second in Release; several times that under the sanitizers).
double shutdownLimit() {
  double limit = 5.0;
  ros::NodeHandle("~").param("shutdown_limit", limit, limit);
  return limit;
}

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Keyframes made once, then published back to back as fast as the connection takes them.
class Burst {
 public:
  Burst(ros::NodeHandle nh, std::size_t count) : harness_(nh) {
    const Drive drive = blockDrive(false, 3);
    for (std::size_t k = 0; k < count && k < drive.truth.size(); ++k) {
      clouds_.push_back(harness_.cloud(drive, k));
      odoms_.push_back(harness_.odom(drive, k));
    }
  }
  Harness& harness() { return harness_; }

  /// Publishes the keyframes on a thread, again and again with later stamps, until stop().
  void start() {
    running_ = true;
    thread_ = std::thread([this] {
      double offset = 0.0;
      while (running_ && ros::ok()) {
        for (std::size_t k = 0; k < clouds_.size() && running_; ++k) {
          auto cloud = clouds_[k];
          auto odom = odoms_[k];
          cloud.header.stamp += ros::Duration(offset);
          odom.header.stamp = cloud.header.stamp;
          harness_.cloud_pub.publish(cloud);
          harness_.odom_pub.publish(odom);
          ++published_;
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        offset += 1000.0;
      }
    });
  }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  std::size_t published() const { return published_; }
  ~Burst() { stop(); }

 private:
  Harness harness_;
  std::vector<sensor_msgs::PointCloud2> clouds_;
  std::vector<nav_msgs::Odometry> odoms_;
  std::atomic<bool> running_{false};
  std::atomic<std::size_t> published_{0};
  std::thread thread_;
};

/// Waits until the node's queue has overflowed at least once (its diagnostics count dropped
/// keyframes); false after `seconds`.
bool waitForFullQueue(const DiagnosticsWatch& watch, double seconds) {
  const double end = wallSeconds() + seconds;
  while (ros::ok() && wallSeconds() < end) {
    if (watch.value("keyframes dropped", ros::WallTime(), 0.2) > 0) return true;
  }
  return false;
}

bool waitForService(const std::string& name, double seconds) {
  return ros::service::waitForService(name, ros::Duration(seconds));
}

bool listNodelets(const std::string& manager, std::vector<std::string>* names) {
  nodelet::NodeletList list;
  if (!ros::service::call(manager + "/list", list)) return false;
  *names = list.response.nodelets;
  return true;
}

// The launch file's manager with the nodelet loaded (queue_size 3): unloaded through the manager's
// service in the middle of a burst.
TEST(Shutdown, UnloadDuringABurstIsPromptAndTheManagerStaysUp) {
  DiagnosticsWatch watch(ros::NodeHandle(), "loop_closure");
  Burst burst(ros::NodeHandle(), 40);
  ASSERT_TRUE(burst.harness().waitForNode(60.0)) << "the nodelet never subscribed";
  burst.start();
  EXPECT_TRUE(waitForFullQueue(watch, 30.0)) << "the burst never filled the queue";
  ros::WallDuration(1.0).sleep();

  nodelet::NodeletUnload unload;
  unload.request.name = "/loop_closure";
  const double start = wallSeconds();
  ASSERT_TRUE(ros::service::call("/manager/unload_nodelet", unload)) << "the manager's unload service failed";
  const double took = wallSeconds() - start;
  std::printf("unload during a burst (%zu keyframes published): %.3f s\n", burst.published(), took);
  RecordProperty("unload_seconds", std::to_string(took));
  EXPECT_TRUE(unload.response.success);
  EXPECT_LT(took, shutdownLimit());
  burst.stop();

  // The manager still serves: it lists no nodelet now, and loads one again.
  std::vector<std::string> names;
  ASSERT_TRUE(listNodelets("/manager", &names)) << "the manager stopped answering";
  EXPECT_TRUE(names.empty());
  nodelet::NodeletLoad load;
  load.request.name = "/loop_closure_again";
  load.request.type = "scan_context_loop/LoopClosureNodelet";
  ASSERT_TRUE(ros::service::call("/manager/load_nodelet", load));
  EXPECT_TRUE(load.response.success);
  ASSERT_TRUE(listNodelets("/manager", &names));
  EXPECT_EQ(names, std::vector<std::string>{"/loop_closure_again"});
  unload.request.name = "/loop_closure_again";
  ASSERT_TRUE(ros::service::call("/manager/unload_nodelet", unload));
  EXPECT_TRUE(unload.response.success);
}

/// Starts the burst, waits until the queue is full, then sends SIGINT to `process` and expects a clean,
/// prompt exit; records the time as `property`.
void expectSigintStopsItUnderLoad(Burst* burst, const DiagnosticsWatch& watch, Child* process, const char* what,
                                  const char* property) {
  burst->start();
  EXPECT_TRUE(waitForFullQueue(watch, 30.0)) << "the burst never filled the queue";
  ros::WallDuration(1.0).sleep();
  ASSERT_TRUE(process->running());
  double took = 0.0;
  const bool exited = process->stop(SIGINT, shutdownLimit(), &took);
  std::printf("SIGINT to %s during a burst: %s after %.3f s\n", what, process->how().c_str(), took);
  ::testing::Test::RecordProperty(property, std::to_string(took));
  EXPECT_TRUE(exited) << "no exit within " << shutdownLimit() << " s";
  EXPECT_TRUE(process->exitedCleanly()) << process->how();
}

TEST(Shutdown, SigintStopsAStandaloneNodeUnderLoad) {
  DiagnosticsWatch watch(ros::NodeHandle(), "standalone/loop_closure");
  Burst burst(ros::NodeHandle("standalone"), 40);
  Child node({"scan_context_loop", "loop_closure_node", "__ns:=standalone", "__name:=loop_closure", "_queue_size:=3",
              "_exclude_recent_frames:=30"});
  ASSERT_GT(node.pid(), 0);
  ASSERT_TRUE(burst.harness().waitForNode(60.0)) << "the node never subscribed";
  expectSigintStopsItUnderLoad(&burst, watch, &node, "the standalone node", "node_sigint_seconds");
}

TEST(Shutdown, SigintStopsAManagerWithTheNodeletUnderLoad) {
  DiagnosticsWatch watch(ros::NodeHandle(), "managed/loop_closure");
  Burst burst(ros::NodeHandle("managed"), 40);
  Child manager({"nodelet", "nodelet", "manager", "__ns:=managed", "__name:=manager"});
  ASSERT_GT(manager.pid(), 0);
  ASSERT_TRUE(waitForService("/managed/manager/load_nodelet", 60.0));
  ros::param::set("/managed/loop_closure/queue_size", 3);
  ros::param::set("/managed/loop_closure/exclude_recent_frames", 30);
  nodelet::NodeletLoad load;
  load.request.name = "/managed/loop_closure";
  load.request.type = "scan_context_loop/LoopClosureNodelet";
  ASSERT_TRUE(ros::service::call("/managed/manager/load_nodelet", load));
  ASSERT_TRUE(load.response.success);
  ASSERT_TRUE(burst.harness().waitForNode(60.0)) << "the nodelet never subscribed";
  expectSigintStopsItUnderLoad(&burst, watch, &manager, "a manager with the nodelet", "manager_sigint_seconds");
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "shutdown_test"); }
