// The sensor extrinsic from tf, looked up without waiting: held while tf has none, then the fallback
// after the wait, and found from transforms sent tf1's way (frame ids with a leading '/'); a transform
// that moves after it was found is no extrinsic and is refused.
#include <gtest/gtest.h>
#include <tf2/buffer_core.h>
#include <tf2_eigen/tf2_eigen.h>

#include "loop_closure/sensor_extrinsic.h"

namespace scan_context_loop {
namespace {

using State = SensorExtrinsic::State;

/// T_parent<-child = `pose` at `stamp`, frame ids as given.
geometry_msgs::TransformStamped stamped(const Eigen::Isometry3d& pose, double stamp, const char* parent,
                                       const char* child) {
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(pose);
  t.header.stamp = ros::Time(stamp);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  return t;
}

/// LeGO-LOAM's run.launch: "/camera" -> "/base_link", camera axes (x_camera = y_lidar, y = z, z = x).
geometry_msgs::TransformStamped cameraToBaseLink(double stamp) {
  Eigen::Isometry3d axes = Eigen::Isometry3d::Identity();
  axes.linear() << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return stamped(axes, stamp, "/camera", "/base_link");
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

/// A-LOAM's /camera_init -> /aft_mapped at `stamp`: the vehicle's pose, `x` metres along.
geometry_msgs::TransformStamped vehiclePose(double stamp, double x) {
  return stamped(Eigen::Isometry3d(Eigen::Translation3d(x, 0.0, 0.0)), stamp, "/camera_init", "/aft_mapped");
}

TEST(SensorExtrinsic, ATransformThatMovesIsRefusedForGood) {
  tf2::BufferCore tf;
  SensorExtrinsic extrinsic(tf, "test", 5.0, 1.0);
  ros::Time::init();  // the error's log reads the time
  // Clouds labelled camera_init taken as the sensor's: aft_mapped <- camera_init is the pose, inverted.
  ASSERT_TRUE(tf.setTransform(vehiclePose(1.6e9, 0.0), "aloam"));
  EXPECT_EQ(extrinsic.resolve("aft_mapped", "camera_init", 10.0), State::kKnown);
  // Read again only after the recheck interval; unchanged, it stays.
  ASSERT_TRUE(tf.setTransform(vehiclePose(1.6e9 + 0.1, SensorExtrinsic::kMovedMeters * 0.5), "aloam"));
  EXPECT_EQ(extrinsic.resolve("aft_mapped", "camera_init", 11.0), State::kKnown);
  ASSERT_TRUE(tf.setTransform(vehiclePose(1.6e9 + 0.2, 0.5), "aloam"));
  EXPECT_EQ(extrinsic.resolve("aft_mapped", "camera_init", 11.5), State::kKnown);
  EXPECT_EQ(extrinsic.resolve("aft_mapped", "camera_init", 12.0), State::kMoving);
  // For good, even if it stood still again.
  ASSERT_TRUE(tf.setTransform(vehiclePose(1.6e9 + 0.3, 0.0), "aloam"));
  EXPECT_EQ(extrinsic.resolve("aft_mapped", "camera_init", 20.0), State::kMoving);
}

TEST(SensorExtrinsic, AFixedOneResentStaysKnown) {
  tf2::BufferCore tf;
  SensorExtrinsic extrinsic(tf, "test", 5.0, 1.0);
  ASSERT_TRUE(tf.setTransform(cameraToBaseLink(1.6e9), "tf1"));
  EXPECT_EQ(extrinsic.resolve("camera", "base_link", 0.0), State::kKnown);
  for (int i = 1; i <= 5; ++i) {
    ASSERT_TRUE(tf.setTransform(cameraToBaseLink(1.6e9 + i), "tf1"));
    EXPECT_EQ(extrinsic.resolve("camera", "base_link", 1.0 * i), State::kKnown);
  }
}

}  // namespace
}  // namespace scan_context_loop
