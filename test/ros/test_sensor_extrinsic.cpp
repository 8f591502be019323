// The sensor extrinsic from tf, looked up without waiting: held while tf has none, then the fallback
// after the wait, and found from transforms sent tf1's way (frame ids with a leading '/').
#include <gtest/gtest.h>
#include <tf2/buffer_core.h>
#include <tf2_eigen/tf2_eigen.h>

#include "loop_closure/sensor_extrinsic.h"

namespace scan_context_loop {
namespace {

using State = SensorExtrinsic::State;

/// LeGO-LOAM's run.launch: "/camera" -> "/base_link", camera axes (x_camera = y_lidar, y = z, z = x).
geometry_msgs::TransformStamped cameraToBaseLink(double stamp) {
  Eigen::Isometry3d axes = Eigen::Isometry3d::Identity();
  axes.linear() << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(axes);
  t.header.stamp = ros::Time(stamp);
  t.header.frame_id = "/camera";
  t.child_frame_id = "/base_link";
  return t;
}

TEST(SensorExtrinsic, OneFrameNeedsNone) {
  tf2::BufferCore tf;
  SensorExtrinsic extrinsic(tf, "test", 5.0, 1.0);
  EXPECT_EQ(extrinsic.resolve("velodyne", "velodyne", 0.0), State::kKnown);
  EXPECT_TRUE(extrinsic.pose().isApprox(Eigen::Isometry3d::Identity()));
}

TEST(SensorExtrinsic, HeldUntilTfHasItThenFoundFromSlashedNames) {
  tf2::BufferCore tf;
  SensorExtrinsic extrinsic(tf, "test", 5.0, 1.0);
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 100.0), State::kWaiting);
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 104.0), State::kWaiting);
  // Sent again and again on /tf, stamped ahead, as tf1's static_transform_publisher does.
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(tf.setTransform(cameraToBaseLink(1.6e9 + 0.01 * (i + 1)), "tf1"));
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 104.5), State::kKnown);
  EXPECT_TRUE((extrinsic.pose() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 200.0), State::kKnown);
}

TEST(SensorExtrinsic, FallbackAfterTheWaitThenFoundLater) {
  tf2::BufferCore tf;
  SensorExtrinsic extrinsic(tf, "test", 5.0, 1.0);
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 10.0), State::kWaiting);
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 15.0), State::kFallback);
  EXPECT_TRUE(extrinsic.pose().isApprox(Eigen::Isometry3d::Identity()));
  ASSERT_TRUE(tf.setTransform(cameraToBaseLink(1.6e9), "tf1"));
  // Looked at again only every recheck interval.
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 15.5), State::kFallback);
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 16.0), State::kKnown);
  EXPECT_FALSE(extrinsic.pose().isApprox(Eigen::Isometry3d::Identity()));
}

}  // namespace
}  // namespace scan_context_loop
