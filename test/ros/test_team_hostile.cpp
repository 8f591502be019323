// A team with a hostile peer (test/ros/team_hostile.test). The test is the peer: it floods the team with
// records (real ones copied under its own robot id), announces a node whose services take requests and
// never answer, announces a node name that is no ROS name, and claims robot1's id and run from another
// node. The real nodes must keep finding their loops into each other's keyframes, all true and all into
// the robot that made them; robot2's records stay within team_max_bytes; and robot3, a nodelet in the
// middle of a request that never returns, unloads within the shutdown limit, as robot4, a standalone node,
// stops on SIGINT.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <set>

#include <gtest/gtest.h>
#include <nodelet/NodeletUnload.h>
#include <ros/callback_queue.h>

#include "child_process.h"
#include "harness.h"
#include "scan_context_loop/GetKeyframeCloud.h"
#include "scan_context_loop/GetKeyframeRecords.h"
#include "scan_context_loop/KeyframeRecord.h"
#include "scan_context_loop/TeamMember.h"
#include "topic_watch.h"

namespace scan_context_loop {
namespace test {
namespace {

/// Services at `node` that take every request and answer none until destroyed (or `hold` seconds), and
/// who called them.
class HungNode {
 public:
  HungNode(const std::string& node, double hold) : hold_(hold) {
    ros::NodeHandle nh(node);
    nh.setCallbackQueue(&queue_);
    records_ = nh.advertiseService("team_records", &HungNode::onRecords, this);
    cloud_ = nh.advertiseService("team_cloud", &HungNode::onCloud, this);
    spinner_.reset(new ros::AsyncSpinner(4, &queue_));
    spinner_->start();
  }
  ~HungNode() {
    release_ = true;
    spinner_->stop();
  }
  /// Whether a call from `caller` (a node name) has come in.
  bool calledBy(const std::string& caller) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return callers_.count(caller) != 0;
  }

 private:
  using RecordsEvent = ros::ServiceEvent<scan_context_loop::GetKeyframeRecords::Request,
                                         scan_context_loop::GetKeyframeRecords::Response>;
  using CloudEvent =
      ros::ServiceEvent<scan_context_loop::GetKeyframeCloud::Request, scan_context_loop::GetKeyframeCloud::Response>;
  bool onRecords(RecordsEvent& event) { return hang(event.getCallerName()); }
  bool onCloud(CloudEvent& event) { return hang(event.getCallerName()); }
  bool hang(const std::string& caller) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      callers_.insert(caller);
    }
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(hold_);
    while (!release_ && ros::WallTime::now() < end) ros::WallDuration(0.05).sleep();
    return false;  // never an answer
  }
  double hold_;
  std::atomic<bool> release_{false};
  mutable std::mutex mutex_;  // guards callers_
  std::set<std::string> callers_;
  ros::CallbackQueue queue_;
  ros::ServiceServer records_, cloud_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
};

/// `record` as robot `robot`'s keyframe `keyframe` of run `run`, served (it claims) by `node`.
scan_context_loop::KeyframeRecord copyAs(scan_context_loop::KeyframeRecord record, const std::string& robot,
                                         std::uint64_t run, std::uint32_t keyframe, const std::string& node) {
  record.robot = robot;
  record.run = run;
  record.keyframe = keyframe;
  record.node = node;
  return record;
}

TEST(TeamHostile, TheRealRobotsKeepFindingTheirLoopsAndAHungPeerDoesNotHoldUpAnUnload) {
  ros::NodeHandle nh, one_nh("robot1"), two_nh("robot2"), three_nh("robot3");
  double shutdown_limit = 5.0;
  ros::NodeHandle("~").getParam("shutdown_limit", shutdown_limit);
  ros::NodeHandle four_nh("robot4");
  Harness one(one_nh), two(two_nh), three(three_nh), four(four_nh);
  // Robot4: a standalone node whose requests wait a minute, stopped with SIGINT while one of them hangs.
  Child robot4({"scan_context_loop", "loop_closure_node", "__ns:=robot4", "__name:=loop_closure", "_robot_id:=robot4",
                "_team_request_timeout:=60.0", "_exclude_recent_frames:=30", "_queue_size:=2000"});
  ASSERT_GT(robot4.pid(), 0);
  ASSERT_TRUE(one.waitForNode(30.0));
  ASSERT_TRUE(two.waitForNode(30.0));
  ASSERT_TRUE(three.waitForNode(30.0));
  ASSERT_TRUE(four.waitForNode(60.0));
  DiagnosticsWatch two_diagnostics(nh, "robot2/loop_closure");
  Collected<scan_context_loop::KeyframeRecord> shared(nh, "/team/keyframe_records");
  // Four robots announce on this topic each second: only robot1's announcements are kept.
  Latest<scan_context_loop::TeamMember> members(
      nh, "/team/members", [](const scan_context_loop::TeamMember& m) { return m.robot == "robot1"; });
  ros::Publisher records = nh.advertise<scan_context_loop::KeyframeRecord>("/team/keyframe_records", 10000);
  ros::Publisher announce = nh.advertise<scan_context_loop::TeamMember>("/team/members", 100);
  const HungNode hung("/hung", 200.0);

  // Robot1 drives a lap of a block; robot2 and robot3 will drive it again.
  const Drive drive = blockDrive(false, 7);
  const std::size_t n = drive.truth.size() / 2;
  one.publish(drive, 0, n, 15.0);
  ASSERT_TRUE(one.waitForKeyframes(n, 60.0));
  scan_context_loop::TeamMember robot1;
  ASSERT_TRUE(members.waitFor([&](const scan_context_loop::TeamMember& m) { return m.keyframes >= n; }, 30.0, &robot1));
  std::vector<scan_context_loop::KeyframeRecord> own;
  for (const auto& r : shared.messages()) {
    if (r.robot == "robot1") own.push_back(r);
  }
  ASSERT_GE(own.size(), n / 2) << "robot1's records seen on the topic";

  // The hostile peer, once its publishers are connected.
  ros::WallDuration(1.0).sleep();
  scan_context_loop::TeamMember peer = robot1;
  peer.robot = "hung";  // takes requests, never answers; its records are robot1's, so candidates point at it
  peer.run = 77;
  peer.node = "/hung";
  peer.keyframes = 1000;
  announce.publish(peer);
  scan_context_loop::TeamMember badname = peer;
  badname.robot = "badname";
  badname.node = "/not a name!";
  announce.publish(badname);
  scan_context_loop::TeamMember impostor = robot1;  // robot1's id and run, from another node
  impostor.node = "/impostor";
  announce.publish(impostor);
  for (std::uint32_t k = 0; k < own.size(); ++k) records.publish(copyAs(own[k], "hung", 77, k, "/hung"));
  // robot1's id and run, for keyframes robot1 has not made, from this node: once naming robot1's real
  // node (a forged publisher), once naming another.
  for (std::uint32_t k = 0; k < 20; ++k) {
    records.publish(copyAs(own[k % own.size()], "robot1", robot1.run, 5000 + k, robot1.node));
    records.publish(copyAs(own[k % own.size()], "robot1", robot1.run, 6000 + k, "/impostor"));
  }
  // A flood: 3,000 copies under the peer's own id, from a node without services.
  for (std::uint32_t k = 0; k < 3000; ++k) {
    records.publish(copyAs(own[k % own.size()], "flood", 88, k, "/flood"));
    if (k % 500 == 499) ros::WallDuration(0.2).sleep();
  }

  // Robot3, whose requests wait a minute, drives; it asks the hung node and waits. Unloaded meanwhile.
  three.publish(drive, 0, 20, 15.0);
  const ros::WallTime asked_by = ros::WallTime::now() + ros::WallDuration(60.0);
  while (!hung.calledBy("/robot3/manager") && ros::WallTime::now() < asked_by) ros::WallDuration(0.1).sleep();
  ASSERT_TRUE(hung.calledBy("/robot3/manager")) << "robot3 never asked the hung node";
  ros::WallDuration(0.5).sleep();  // well inside the call
  nodelet::NodeletUnload unload;
  unload.request.name = "/robot3/loop_closure";
  const ros::WallTime unload_start = ros::WallTime::now();
  ASSERT_TRUE(ros::service::call("/robot3/manager/unload_nodelet", unload));
  const double unload_seconds = (ros::WallTime::now() - unload_start).toSec();
  EXPECT_TRUE(unload.response.success);
  EXPECT_LT(unload_seconds, shutdown_limit) << "unloading with a request hung in a peer";

  // Robot4 the same, stopped with SIGINT as roslaunch stops a node.
  four.publish(drive, 0, 20, 15.0);
  while (!hung.calledBy("/robot4/loop_closure") && ros::WallTime::now() < asked_by + ros::WallDuration(60.0)) {
    ros::WallDuration(0.1).sleep();
  }
  ASSERT_TRUE(hung.calledBy("/robot4/loop_closure")) << "robot4 never asked the hung node";
  ros::WallDuration(0.5).sleep();
  double sigint_seconds = 0.0;
  EXPECT_TRUE(robot4.stop(SIGINT, 30.0, &sigint_seconds)) << "no exit after SIGINT";
  EXPECT_LT(sigint_seconds, shutdown_limit) << "SIGINT with a request hung in a peer";
  EXPECT_TRUE(robot4.exitedCleanly()) << robot4.how();

  // Robot2 drives the lap: its loops go into robot1's keyframes, each true, none into another robot's.
  two.publish(drive, 0, n, 15.0);
  ASSERT_TRUE(two.waitForKeyframes(n, 60.0));
  two.settle(5.0, 40.0);
  std::size_t into_robot1 = 0;
  for (const auto& loop : two.loops()) {
    if (loop.match_robot == "robot2") continue;  // robot2's own loops
    EXPECT_EQ(loop.match_robot, "robot1") << "a loop into " << loop.match_robot;
    if (loop.match_robot != "robot1") continue;
    ++into_robot1;
    ASSERT_LT(loop.match_id, n) << "a loop into a keyframe robot1 never made";
    expectTrueLoop(drive, static_cast<int>(loop.query_id), static_cast<int>(loop.match_id), loop);
  }
  EXPECT_GE(into_robot1, n / 4) << "loops from robot2 into robot1, of " << n << " keyframes";
  std::printf(
      "robot2: %zu loops into robot1 over %zu keyframes; during a hung request robot3 unloaded in %.2f s, "
      "robot4 exited on SIGINT in %.2f s\n",
      into_robot1, n, unload_seconds, sigint_seconds);

  const ros::WallTime now = ros::WallTime::now();
  EXPECT_GE(two_diagnostics.value("team claims refused (robot id bound to another node)", now, 10.0), 3)
      << "the impostor's announcement and records, the forged publisher, the bad node name";
  EXPECT_GE(two_diagnostics.value("team requests timed out", now, 10.0), 1);
  EXPECT_GE(two_diagnostics.value("team records refused (team_max_bytes)", now, 10.0), 1);
  const long memory = two_diagnostics.value("team records memory [bytes]", now, 10.0);
  EXPECT_GT(memory, 0);
  EXPECT_LE(memory, 2000000 + 10000) << "team_max_bytes 2,000,000";
  std::printf("robot2: records memory %ld B, claims refused %ld, requests timed out %ld, records over the bound %ld\n",
              memory, two_diagnostics.value("team claims refused (robot id bound to another node)", now, 10.0),
              two_diagnostics.value("team requests timed out", now, 10.0),
              two_diagnostics.value("team records refused (team_max_bytes)", now, 10.0));
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_team_hostile"); }
