// rostest: poses from tf and clouds registered in the odometry frame (pose_source: tf,
// cloud_in_world_frame: true) give the same true revisits as clouds in the sensor frame.
#include <cmath>

#include <gtest/gtest.h>
#include <pcl_conversions/pcl_conversions.h>
#include <tf2_ros/transform_broadcaster.h>

#include "harness.h"
#include "scan_context_loop/core/alignment.h"

namespace scan_context_loop {
namespace test {
namespace {

TEST(LoopClosureNode, PosesFromTfAndRegisteredClouds) {
  ros::NodeHandle nh;
  Harness harness(nh);
  DiagnosticsWatch diagnostics(nh);
  ASSERT_TRUE(harness.waitForNode(30.0, false));
  const Drive drive = blockDrive(true, 7);
  harness.publishTfAndWorldClouds(drive, 12.0);
  harness.settle(3.0, 30.0);

  // Clouds whose pose tf cannot give: one long after the last transform (the lookup waits tf_timeout,
  // then fails) and one whose transform has an all-zero quaternion (tf2 refuses to store it, or the
  // node refuses the rotation). Each is skipped with an error and counted; the database stays as it was.
  // (The first keyframes may have come before the node heard any transform: counted the same way.)
  const ros::WallTime before = ros::WallTime::now();
  const long kept = diagnostics.value("database size", before, 10.0);
  const long refused = diagnostics.value("keyframes rejected", before, 10.0);
  const long dropped = diagnostics.value("keyframes dropped", before, 10.0);  // a full queue, under load
  // A keyframe a full queue dropped under load is counted too (the accounting below): what tf must
  // give is the pose of every other keyframe but the first few.
  EXPECT_GE(kept + dropped, static_cast<long>(drive.truth.size()) - 5)
      << refused << " refused, " << dropped << " dropped";
  sensor_msgs::PointCloud2 late, zero_rotation;
  pcl::toROSMsg(drive.scan(0), late);
  late.header.frame_id = "odom";
  zero_rotation = late;
  const ros::Time after = harness.base + ros::Duration(drive.times.back() + 100.0);
  late.header.stamp = after;
  harness.cloud_pub.publish(late);
  ros::WallDuration(1.0).sleep();
  tf2_ros::TransformBroadcaster broadcaster;
  geometry_msgs::TransformStamped zero;
  zero.header.stamp = zero_rotation.header.stamp = after + ros::Duration(2.0);
  zero.header.frame_id = "odom";
  zero.child_frame_id = "velodyne";
  broadcaster.sendTransform(zero);  // translation and rotation all zero
  ros::WallDuration(0.1).sleep();
  harness.cloud_pub.publish(zero_rotation);
  ros::WallDuration(1.0).sleep();
  const ros::WallTime now = ros::WallTime::now();
  EXPECT_EQ(diagnostics.value("database size", now, 10.0), kept);
  EXPECT_EQ(diagnostics.value("keyframes rejected", now, 10.0), refused + 2);
  EXPECT_EQ(kept + refused + dropped, static_cast<long>(drive.truth.size())) << "every keyframe kept or counted";
  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u);
  expectTrueLoops(drive, harness.base, loops, false);
  for (const auto& loop : loops) {
    const int q = keyframeAt(drive, harness.base, loop.query_stamp);
    const int m = keyframeAt(drive, harness.base, loop.match_stamp);
    if (q < 0 || m < 0) continue;  // reported above
    const Eigen::Isometry3d truth = drive.truth[q].inverse() * drive.truth[m];
    // Back in the sensor frame, the yaw prior is the sensor's again.
    EXPECT_LT(std::fabs(wrapAngle(loop.yaw - std::atan2(truth(1, 0), truth(0, 0)))), 6.0 * M_PI / 180.0);
  }
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_tf_world"); }
