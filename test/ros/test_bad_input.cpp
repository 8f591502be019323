// rostest: malformed clouds, broken poses (NaN, unusable quaternions), stamps going backwards and unpaired clouds among
// good keyframes; the node must keep running and still find the loops that follow.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <signal.h>

#include <gtest/gtest.h>

#include "child_process.h"
#include "harness.h"
#include "loop_closure/heap_statistics.h"

namespace scan_context_loop {
namespace test {
namespace {

/// How many times slower than a normal build the node runs here (the test's `~slowdown`, set under TSan):
/// rates are divided by it and waits multiplied.
double slowdown() {
  static const double factor = std::max(1.0, ros::NodeHandle("~").param("slowdown", 1.0));
  return factor;
}

/// The number of bad variants publishBad knows.
constexpr int kBadKinds = 9;

/// Publishes bad variant `kind` at `stamp`.
void publishBad(Harness* h, const Drive& drive, std::size_t k, int kind, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 cloud = h->cloud(drive, k);
  nav_msgs::Odometry odom = h->odom(drive, k);
  cloud.header.stamp = odom.header.stamp = stamp;
  bool send_odom = true;
  switch (kind) {
    case 0:  // no z field
      cloud.fields.erase(cloud.fields.begin() + 2);
      break;
    case 1:  // data shorter than width x height x point_step says
      cloud.data.resize(cloud.data.size() / 2);
      break;
    case 2:  // x declared as float64
      cloud.fields[0].datatype = sensor_msgs::PointField::FLOAT64;
      break;
    case 3: {  // every point NaN: accepted as an empty keyframe that never matches
      const float nan = std::numeric_limits<float>::quiet_NaN();
      for (std::size_t i = 0; i + 12 <= cloud.data.size(); i += cloud.point_step) {
        for (int f = 0; f < 3; ++f) std::memcpy(&cloud.data[i + 4 * f], &nan, 4);
      }
      break;
    }
    case 4:  // empty cloud
      cloud.width = 0;
      cloud.row_step = 0;
      cloud.data.clear();
      break;
    case 5:  // NaN pose
      odom.pose.pose.position.x = std::numeric_limits<double>::quiet_NaN();
      break;
    case 6:  // a cloud nobody pairs with a pose
      send_odom = false;
      break;
    case 7:  // an all-zero orientation quaternion
      odom.pose.pose.orientation = geometry_msgs::Quaternion();
      break;
    case 8:  // an orientation quaternion of norm 2
      odom.pose.pose.orientation.x *= 2.0;
      odom.pose.pose.orientation.y *= 2.0;
      odom.pose.pose.orientation.z *= 2.0;
      odom.pose.pose.orientation.w *= 2.0;
      break;
  }
  h->cloud_pub.publish(cloud);
  if (send_odom) h->odom_pub.publish(odom);
}

/// What bad variant `kind` must do: refused with an error (counted as rejected), or taken as a keyframe
/// (the cloud without a usable point), or neither (the unpaired cloud never reaches the worker).
enum class Outcome { kRejected, kKept, kIgnored };
Outcome expectedOutcome(int kind) {
  if (kind == 3 || kind == 4) return Outcome::kKept;
  if (kind == 6) return Outcome::kIgnored;
  return Outcome::kRejected;
}

TEST(LoopClosureNode, SurvivesBadInputAndStillFindsTheLoopsThatFollow) {
  ros::NodeHandle nh;
  Harness harness(nh);
  DiagnosticsWatch diagnostics(nh, "loop_closure");
  ASSERT_TRUE(harness.waitForNode(30.0));
  const Drive drive = blockDrive(true, 7);
  const std::size_t half = drive.truth.size() / 2;
  ros::WallRate rate(15.0 / slowdown());
  int kind = 0;
  std::size_t expected_rejected = 0, expected_kept = 0, expected_ignored = 0;
  for (std::size_t k = 0; k < half && ros::ok(); ++k) {
    harness.cloud_pub.publish(harness.cloud(drive, k));
    harness.odom_pub.publish(harness.odom(drive, k));
    rate.sleep();
    if (k % 5 == 4) {
      publishBad(&harness, drive, k, kind % kBadKinds, harness.base + ros::Duration(drive.times[k] + 0.05));
      const Outcome outcome = expectedOutcome(kind % kBadKinds);
      expected_rejected += outcome == Outcome::kRejected;
      expected_kept += outcome == Outcome::kKept;
      expected_ignored += outcome == Outcome::kIgnored;
      ++kind;
      rate.sleep();
    }
    if (k == half / 2) {
      // Back in time by 0.5 s, less than new_session_jump (1 s): out of order, so refused; no new
      // session, the database kept.
      sensor_msgs::PointCloud2 cloud = harness.cloud(drive, k - 5);
      nav_msgs::Odometry odom = harness.odom(drive, k - 5);
      cloud.header.stamp = odom.header.stamp = harness.base + ros::Duration(drive.times[k] - 0.5);
      harness.cloud_pub.publish(cloud);
      harness.odom_pub.publish(odom);
      ++expected_rejected;
      rate.sleep();
    }
  }
  harness.publish(drive, half, drive.truth.size(), 15.0 / slowdown());
  harness.settle(3.0 * slowdown(), 30.0 * slowdown());
  ASSERT_GE(kind, 2 * kBadKinds) << "every bad variant twice";

  // Each bad keyframe did what it must: the refused ones are counted and never enter the database, the
  // unpaired cloud is never paired with another keyframe's pose, and no session was started.
  const ros::WallTime now = ros::WallTime::now();
  EXPECT_EQ(diagnostics.value("database size", now, 10.0), static_cast<long>(drive.truth.size() + expected_kept));
  EXPECT_EQ(diagnostics.value("keyframes rejected", now, 10.0), static_cast<long>(expected_rejected));
  EXPECT_EQ(diagnostics.value("keyframes dropped", now, 10.0), 0);
  EXPECT_EQ(diagnostics.value("sessions", now, 10.0), 1);
  // heap_statistics_interval 10: the worker read malloc's statistics, and the diagnostics report them;
  // where malloc cannot report them (a sanitizer's allocator) they are left out, never reported as 0.
  if (HeapStatistics::available()) {
    EXPECT_GT(diagnostics.value("heap allocated [bytes]", now, 10.0), 0);
    EXPECT_GE(diagnostics.value("heap free [bytes]", now, 10.0), 0);
  } else {
    EXPECT_EQ(diagnostics.value("heap allocated [bytes]", now, 3.0), -1) << "absent";
  }
  // Every cloud sent reached the node (the drive's, one per bad variant, the one back in time), and the
  // unpaired ones are counted as never paired.
  const long received = diagnostics.value("clouds received", now, 10.0);
  EXPECT_EQ(received, static_cast<long>(drive.truth.size() + kind + 1));
  EXPECT_EQ(received - diagnostics.value("clouds paired with a pose", now, 10.0), static_cast<long>(expected_ignored));

  const auto loops = harness.loops();
  std::size_t after_bad_input = 0;
  for (const auto& loop : loops) {
    const int q = keyframeAt(drive, harness.base, loop.query_stamp);
    const int m = keyframeAt(drive, harness.base, loop.match_stamp);
    ASSERT_GE(q, 0) << "a loop from a bad keyframe";
    ASSERT_GE(m, 0) << "a loop to a bad keyframe";
    // Lap 1 closes on its own start too (a true revisit); what matters is that lap 2 still finds loops.
    after_bad_input += static_cast<std::size_t>(q) >= half;
    expectTrueLoop(drive, q, m, loop);
  }
  EXPECT_GE(after_bad_input, 10u) << "the node stopped finding loops after bad input";
}

/// "database size" and "keyframes dropped" once two diagnostics statuses 1.5 s apart agree (the worker is idle), or
/// {-1, -1} if they never settle within `limit` seconds.
std::pair<long, long> settledCounts(const DiagnosticsWatch& diagnostics, double limit) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(limit);
  std::pair<long, long> last{-2, -2};
  while (ros::ok() && ros::WallTime::now() < end) {
    const ros::WallTime now = ros::WallTime::now();
    const std::pair<long, long> counts{diagnostics.value("database size", now, 10.0),
                                       diagnostics.value("keyframes dropped", now, 10.0)};
    if (counts == last && counts.first >= 0) return counts;
    last = counts;
    ros::WallDuration(1.5 * slowdown()).sleep();
  }
  return {-1, -1};
}

TEST(LoopClosureNode, AFullQueueDropsKeyframesCountedAndTheNodeGoesOn) {
  // A standalone node with a queue of one, each keyframe a candidate of the next (none excluded as
  // recent, so each registers one). The burst must outrun its worker on any machine, however loaded: the
  // node is stopped (SIGSTOP) while the burst is sent, so that on SIGCONT the messages waiting in its
  // sockets arrive back to back.
  Child node({"scan_context_loop", "loop_closure_node", "__ns:=tiny_queue", "__name:=loop_closure",
              "_queue_size:=1", "_exclude_recent_frames:=0"});
  ASSERT_GT(node.pid(), 0);
  ros::NodeHandle nh("tiny_queue");
  Harness harness(nh);
  DiagnosticsWatch diagnostics(ros::NodeHandle(), "tiny_queue/loop_closure");
  ASSERT_TRUE(harness.waitForNode(60.0));
  const Drive drive = blockDrive(false, 3);
  const std::size_t burst = 120;
  const std::size_t paced = 20;
  ASSERT_GT(drive.truth.size(), burst + paced);
  std::vector<sensor_msgs::PointCloud2> clouds;
  std::vector<nav_msgs::Odometry> poses;
  for (std::size_t k = 0; k < burst; ++k) {
    clouds.push_back(harness.cloud(drive, k));
    poses.push_back(harness.odom(drive, k));
  }
  ASSERT_EQ(::kill(node.pid(), SIGSTOP), 0);
  for (std::size_t k = 0; k < burst; ++k) {
    harness.cloud_pub.publish(clouds[k]);
    harness.odom_pub.publish(poses[k]);
  }
  ros::WallDuration(1.0).sleep();  // the publisher's threads write what its queues hold
  ASSERT_EQ(::kill(node.pid(), SIGCONT), 0);
  const auto [kept, dropped] = settledCounts(diagnostics, 60.0 * slowdown());
  std::printf("burst of %zu: %ld kept, %ld dropped by the queue\n", burst, kept, dropped);
  EXPECT_GT(dropped, 0) << "the burst never filled a queue of one";
  EXPECT_GT(kept, 0);
  // Some of the burst may be lost before the node (the transport's own queue); what reaches it is kept or counted.
  EXPECT_LE(kept + dropped, static_cast<long>(burst));
  // Then keyframes at a pace the worker normally keeps. On a loaded machine one may still find the queue full;
  // either way each is kept or counted as dropped, none vanishes, and the node goes on adding to its database.
  harness.publish(drive, burst, burst + paced, 4.0 / slowdown());
  const auto [kept_after, dropped_after] = settledCounts(diagnostics, 60.0 * slowdown());
  EXPECT_EQ(kept_after + dropped_after, kept + dropped + static_cast<long>(paced)) << "a keyframe vanished uncounted";
  EXPECT_GE(kept_after, kept + static_cast<long>(paced) / 2) << "the node stopped taking keyframes after the burst";
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_bad_input"); }
