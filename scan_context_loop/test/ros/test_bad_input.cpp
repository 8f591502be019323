// rostest: malformed clouds, broken poses (NaN, unusable quaternions), stamps going backwards and unpaired clouds among good
// keyframes; the node must keep running and still find the loops that follow.
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "harness.h"

namespace scan_context_loop {
namespace test {
namespace {

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

TEST(LoopClosureNode, SurvivesBadInputAndStillFindsTheLoopsThatFollow) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(30.0));
  const Drive drive = blockDrive(true, 7);
  const std::size_t half = drive.truth.size() / 2;
  ros::WallRate rate(15.0);
  int kind = 0;
  for (std::size_t k = 0; k < half && ros::ok(); ++k) {
    harness.cloud_pub.publish(harness.cloud(drive, k));
    harness.odom_pub.publish(harness.odom(drive, k));
    rate.sleep();
    if (k % 5 == 4) {
      publishBad(&harness, drive, k, kind % kBadKinds, harness.base + ros::Duration(drive.times[k] + 0.05));
      ++kind;
      rate.sleep();
    }
    if (k == half / 2) {
      // Going back in time by a second: refused, database kept.
      harness.cloud_pub.publish(harness.cloud(drive, k - 10));
      harness.odom_pub.publish(harness.odom(drive, k - 10));
      rate.sleep();
    }
  }
  harness.publish(drive, half, drive.truth.size(), 15.0);
  harness.settle(3.0, 30.0);

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

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_bad_input"); }
