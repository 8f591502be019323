// A team's inputs are validated like any other (test/ros/team_input.test): a loop node with robot_id
// takes hostile records and announcements on the team's topics and hostile calls of its team services,
// refuses them with a reason, and goes on serving its own keyframes and finding loops into records that
// are good.
#include <gtest/gtest.h>

#include <unistd.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <std_srvs/Trigger.h>

#include "harness.h"
#include "scan_context_loop/GetKeyframeCloud.h"
#include "scan_context_loop/GetKeyframeRecords.h"
#include "scan_context_loop/LoadDatabase.h"
#include "scan_context_loop/SaveDatabase.h"
#include "scan_context_loop/KeyframeRecord.h"
#include "scan_context_loop/TeamMember.h"
#include "scan_context_loop/core/file_io.h"
#include "scan_context_loop/core/database_file.h"
#include "topic_watch.h"

namespace scan_context_loop {
namespace test {
namespace {

/// The node's latest value of diagnostic `key` (-1 before any).
double diagnostic(const Latest<diagnostic_msgs::DiagnosticArray>& topic, const std::string& key) {
  diagnostic_msgs::DiagnosticArray array;
  double value = -1.0;
  topic.waitFor(
      [&](const diagnostic_msgs::DiagnosticArray& a) {
        for (const auto& status : a.status) {
          for (const auto& kv : status.values) {
            if (kv.key == key) {
              value = std::stod(kv.value);
              return true;
            }
          }
        }
        return false;
      },
      5.0, &array);
  return value;
}

/// Waits until diagnostic `key` reaches `at_least`; its last value.
double waitForDiagnostic(const Latest<diagnostic_msgs::DiagnosticArray>& topic, const std::string& key, double at_least,
                         double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  double value = -1.0;
  while (ros::ok() && ros::WallTime::now() < end) {
    value = diagnostic(topic, key);
    if (value >= at_least) break;
    ros::WallDuration(0.5).sleep();
  }
  return value;
}

TEST(TeamInput, HostileRecordsAnnouncementsAndCallsAreRefusedAndTheNodeGoesOn) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(30.0));
  Latest<scan_context_loop::TeamMember> member(nh, "/team/members");
  Latest<diagnostic_msgs::DiagnosticArray> diagnostics(nh, "/diagnostics");
  Collected<scan_context_loop::KeyframeRecord> shared(nh, "/team/keyframe_records");
  ros::Publisher records = nh.advertise<scan_context_loop::KeyframeRecord>("/team/keyframe_records", 100);
  ros::Publisher members = nh.advertise<scan_context_loop::TeamMember>("/team/members", 100);

  // The node's own keyframes: a lap of a block.
  const Drive drive = blockDrive(false, 7);
  const std::size_t count = 40;
  harness.publish(drive, 0, count, 10.0);
  ASSERT_TRUE(harness.waitForKeyframes(count / 2, 60.0));
  scan_context_loop::TeamMember self;
  ASSERT_TRUE(member.waitFor([](const scan_context_loop::TeamMember& m) { return m.keyframes >= 10; }, 30.0, &self));
  EXPECT_EQ(self.robot, "robot1");
  ASSERT_GT(shared.count(), 0u);
  const scan_context_loop::KeyframeRecord good = shared.messages().front();

  // Records: another robot's copy of a good one is taken; corrupt data, an invalid robot id, another
  // settings fingerprint, an empty image and one of 10 MB of noise are refused.
  ros::WallDuration(1.0).sleep();  // our publishers connected
  auto copy = [&](const std::string& robot, std::uint32_t keyframe) {
    scan_context_loop::KeyframeRecord r = good;
    r.robot = robot;
    r.run = 99;
    r.keyframe = keyframe;
    r.node = "/nowhere";
    return r;
  };
  records.publish(copy("robot9", 0));
  records.publish(copy("robot9", 0));  // the same again: already held
  auto corrupt = copy("robot9", 1);
  corrupt.data[corrupt.data.size() / 2] ^= 0x55;
  records.publish(corrupt);
  records.publish(copy("robot 9/../x", 2));
  auto other_settings = copy("robot9", 3);
  other_settings.settings ^= 1;
  records.publish(other_settings);
  auto empty = copy("robot9", 4);
  empty.data.clear();
  records.publish(empty);
  auto noise = copy("robot9", 5);
  noise.data.assign(10u << 20, 0xAB);
  records.publish(noise);
  EXPECT_GE(waitForDiagnostic(diagnostics, "team records refused", 5, 20.0), 5.0);
  EXPECT_GE(waitForDiagnostic(diagnostics, "team records already held", 1, 10.0), 1.0);
  EXPECT_EQ(diagnostic(diagnostics, "team keyframes held"), 1.0);

  // An announcement with other settings: refused (by name in the log); one of an invalid id: ignored.
  scan_context_loop::TeamMember foreign = self;
  foreign.robot = "robot8";
  foreign.run = 5;
  foreign.settings_text = "num_rings 20, num_sectors 72";
  foreign.settings ^= 1;
  members.publish(foreign);
  foreign.robot = "";
  members.publish(foreign);
  // A good-looking announcement of a node that does not exist: its records are asked for and not found,
  // and that is counted, not fatal.
  scan_context_loop::TeamMember ghost = self;
  ghost.robot = "robot7";
  ghost.run = 6;
  ghost.node = "/robot7/nowhere";
  ghost.keyframes = 1000000;
  members.publish(ghost);
  EXPECT_GE(waitForDiagnostic(diagnostics, "team requests failed", 1, 20.0), 1.0);

  // The services: another run, a keyframe past the shared ones and a huge count are answered, not obeyed.
  const std::string node = self.node;
  scan_context_loop::GetKeyframeRecords list;
  list.request.run = self.run + 1;
  list.request.first = 0;
  list.request.count = 10;
  ASSERT_TRUE(ros::service::call(node + "/team_records", list));
  EXPECT_FALSE(list.response.ok);
  EXPECT_NE(list.response.message.find("run"), std::string::npos);
  list.request.run = self.run;
  list.request.first = 3;
  list.request.count = 4000000000u;
  ASSERT_TRUE(ros::service::call(node + "/team_records", list));
  EXPECT_TRUE(list.response.ok);
  ASSERT_FALSE(list.response.records.empty());
  EXPECT_LE(list.response.records.size(), 100u);
  EXPECT_EQ(list.response.records.front().keyframe, 3u);
  list.request.first = 4000000000u;
  ASSERT_TRUE(ros::service::call(node + "/team_records", list));
  EXPECT_TRUE(list.response.records.empty());

  scan_context_loop::GetKeyframeCloud cloud;
  cloud.request.run = self.run;
  cloud.request.keyframe = 4000000000u;
  ASSERT_TRUE(ros::service::call(node + "/team_cloud", cloud));
  EXPECT_FALSE(cloud.response.ok);
  EXPECT_TRUE(cloud.response.data.empty());
  cloud.request.keyframe = 2;
  ASSERT_TRUE(ros::service::call(node + "/team_cloud", cloud));
  ASSERT_TRUE(cloud.response.ok) << cloud.response.message;
  // What it serves is a one-keyframe database with its registration data, as the format says.
  MemoryReader reader(cloud.response.data.data(), cloud.response.data.size());
  PriorSessions one;
  std::string error;
  ASSERT_TRUE(readDatabase(&reader, "team_cloud", Config(), &one, &error)) << error;
  ASSERT_EQ(one.keyframes.size(), 1u);
  ASSERT_EQ(one.clouds.size(), 1u);
  EXPECT_TRUE(one.clouds.front() != nullptr);

  // And the node goes on: the rest of the drive is processed.
  harness.publish(drive, count, count + 20, 10.0);
  EXPECT_TRUE(harness.waitForKeyframes(count + 10, 60.0));
}

// ~reset then ~load_database of as many keyframes as were shared: the team must hear of it (a new run, its
// keyframes shared again from the first), or the others would keep the old run's records under numbers
// that now name other keyframes.
TEST(TeamInput, AResetThenALoadOfAsManyKeyframesStartsANewRun) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(30.0));
  Latest<scan_context_loop::TeamMember> member(nh, "/team/members");
  // Once the node has shared all it will (the last test's keyframes may still be in its queue): two
  // announcements two seconds apart that agree.
  scan_context_loop::TeamMember before, again;
  for (int attempt = 0; attempt < 30; ++attempt) {
    ASSERT_TRUE(member.waitFor([](const scan_context_loop::TeamMember& m) { return m.keyframes > 0; }, 30.0, &before));
    ros::WallDuration(2.0).sleep();
    ASSERT_TRUE(member.waitFor([](const scan_context_loop::TeamMember&) { return true; }, 5.0, &again));
    if (again.keyframes == before.keyframes && again.run == before.run) break;
  }
  ASSERT_EQ(again.keyframes, before.keyframes) << "the node kept sharing keyframes";
  const std::string node = before.node;
  const std::string name = "scl_team_reset_" + std::to_string(::getpid()) + ".scdb";
  SaveDatabase save;
  save.request.path = name;
  save.request.include_clouds = true;
  ASSERT_TRUE(ros::service::call(node + "/save_database", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  ASSERT_EQ(save.response.keyframes, before.keyframes) << "the database holds what was shared";
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call(node + "/reset", reset));
  ASSERT_TRUE(reset.response.success);
  LoadDatabase load;
  load.request.path = "/tmp/" + name;
  ASSERT_TRUE(ros::service::call(node + "/load_database", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  ::unlink(load.request.path.c_str());
  EXPECT_EQ(load.response.keyframes, save.response.keyframes);

  scan_context_loop::TeamMember after;
  ASSERT_TRUE(member.waitFor(
      [&](const scan_context_loop::TeamMember& m) {
        return m.run != before.run && m.keyframes == load.response.keyframes;
      },
      10.0, &after))
      << "still run " << after.run << " with " << after.keyframes << " keyframes after the reset and the load";
  // The new run serves the loaded keyframes from the first; the old run is no more.
  scan_context_loop::GetKeyframeRecords list;
  list.request.run = after.run;
  list.request.first = 0;
  list.request.count = 5;
  ASSERT_TRUE(ros::service::call(node + "/team_records", list));
  ASSERT_TRUE(list.response.ok) << list.response.message;
  ASSERT_FALSE(list.response.records.empty());
  EXPECT_EQ(list.response.records.front().run, after.run);
  EXPECT_EQ(list.response.records.front().keyframe, 0u);
  list.request.run = before.run;
  ASSERT_TRUE(ros::service::call(node + "/team_records", list));
  EXPECT_FALSE(list.response.ok);
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_team_input"); }
