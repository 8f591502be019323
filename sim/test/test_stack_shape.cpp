// The odometry stacks' shapes (topics, frames, camera axes) and the short block drive their bags use.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_sim/stack_shape.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {
namespace {

TEST(StackShape, EveryStackByNameWithItsTopicsAndFrames) {
  ASSERT_EQ(stackShapes().size(), 6u);
  for (const StackShape& s : stackShapes()) {
    ASSERT_EQ(findStackShape(s.name), &s);
    EXPECT_NE(stackNames().find(s.name), std::string::npos);
    EXPECT_DOUBLE_EQ(s.rate_hz, 10.0);
    // Registered clouds are in the odometry frame; sensor-frame clouds are not, except SC-A-LOAM's local
    // clouds, which carry the world's name.
    if (s.name != "sc_aloam") {
      EXPECT_EQ(s.registered, s.cloud_frame == s.odom_frame) << s.name;
    }
  }
  const StackShape& sc = *findStackShape("sc_aloam");
  EXPECT_FALSE(sc.registered);
  EXPECT_EQ(sc.cloud_frame, sc.odom_frame);
  EXPECT_EQ(sc.cloud_topic, "/velodyne_cloud_registered_local");
  const StackShape& hdl = *findStackShape("hdl_graph_slam");
  EXPECT_EQ(hdl.cloud_topic, "/filtered_points");
  EXPECT_EQ(hdl.child_frame, hdl.cloud_frame);
  EXPECT_EQ(findStackShape("loam"), nullptr);
  const StackShape* lego = findStackShape("lego_loam");
  ASSERT_NE(lego, nullptr);
  EXPECT_EQ(lego->cloud_topic, "/full_cloud_projected");
  EXPECT_EQ(lego->odom_topic, "/integrated_to_init");
  EXPECT_TRUE(lego->camera_axes);
  EXPECT_EQ(findStackShape("lio_sam")->cloud_topic, "/lio_sam/mapping/cloud_registered_raw");
  EXPECT_EQ(findStackShape("fast_lio")->child_frame, findStackShape("fast_lio")->cloud_frame);
}

TEST(StackShape, FramesAndTfAsTheStacksWriteThem) {
  // A-LOAM and LeGO-LOAM spell their frames tf1's way, with a leading '/'.
  const StackShape& aloam = *findStackShape("aloam");
  EXPECT_EQ(aloam.odom_frame, "/camera_init");
  EXPECT_EQ(aloam.cloud_frame, "/camera_init");
  EXPECT_EQ(aloam.child_frame, "/aft_mapped");
  EXPECT_TRUE(fixedTransforms(aloam).empty());
  const StackShape& lego = *findStackShape("lego_loam");
  EXPECT_EQ(lego.odom_frame, "/camera_init");
  EXPECT_EQ(lego.child_frame, "/camera");
  EXPECT_EQ(lego.cloud_frame, "base_link");
  // run.launch: tf1's static_transform_publisher, period 10 ms, "/camera /base_link" and "/map /camera_init".
  EXPECT_DOUBLE_EQ(lego.fixed_tf_period, 0.01);
  const std::vector<FixedTransform> fixed = fixedTransforms(lego);
  ASSERT_EQ(fixed.size(), 2u);
  EXPECT_EQ(fixed[0].parent, "/camera");
  EXPECT_EQ(fixed[0].child, "/base_link");
  EXPECT_EQ(fixed[1].parent, "/map");
  EXPECT_EQ(fixed[1].child, "/camera_init");
  // The LiDAR's forward axis is the camera's z; map -> camera_init -> camera -> base_link is z up again.
  EXPECT_TRUE((fixed[0].pose * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitZ()));
  Eigen::Isometry3d lidar = Eigen::Isometry3d::Identity();
  lidar.translation() << 5.0, 2.0, 1.0;
  lidar.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE((fixed[1].pose * toStackPose(lego, lidar) * fixed[0].pose).isApprox(lidar));
  // The others send none of their own, or (FAST-LIO, LIO-SAM) without a slash.
  for (const char* name : {"lio_sam", "fast_lio"}) {
    const StackShape& s = *findStackShape(name);
    EXPECT_TRUE(fixedTransforms(s).empty()) << name;
    EXPECT_NE(s.odom_frame.front(), '/') << name;
  }
}

TEST(StackShape, CameraAxesPutForwardOnZAndUpOnY) {
  const StackShape& lego = *findStackShape("lego_loam");
  Eigen::Isometry3d lidar = Eigen::Isometry3d::Identity();
  lidar.translation() << 5.0, 2.0, 1.0;  // 5 m forward, 2 m left, 1 m up
  lidar.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Eigen::Isometry3d camera = toStackPose(lego, lidar);
  EXPECT_TRUE(camera.translation().isApprox(Eigen::Vector3d(2.0, 1.0, 5.0)));
  // A yaw about the world's up axis is a rotation about the camera's y axis.
  EXPECT_TRUE(Eigen::AngleAxisd(camera.linear()).axis().isApprox(Eigen::Vector3d::UnitY(), 1e-9));
  EXPECT_TRUE(fromStackPose(lego, camera).isApprox(lidar));
  // The other stacks keep LiDAR axes.
  EXPECT_TRUE(toStackPose(*findStackShape("aloam"), lidar).isApprox(lidar));
}

TEST(Trajectory, BlockDriveGoesRoundTwiceTheSecondTimeReversed) {
  const std::vector<PathPoint> path = blockPath(true);
  const std::vector<double> along = distanceAlong(path);
  EXPECT_NEAR(along.back(), 400.0, 2.0);
  // Halfway, the drive is back at the start, then passes every place of lap 1 heading the other way.
  const PathPoint& half = path[path.size() / 2];
  EXPECT_LT(std::hypot(half.x, half.y), 1.0);
  const auto at = [&](double metres) {
    return path[std::lower_bound(along.begin(), along.end(), metres) - along.begin()];
  };
  const PathPoint& a = at(30.0);   // lap 1, along the first street
  const PathPoint& b = at(370.0);  // lap 2, back along it
  EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 1.0);
  EXPECT_NEAR(std::fabs(std::remainder(a.heading - b.heading, 2.0 * M_PI)), M_PI, 1e-9);
}

TEST(Trajectory, FramesEveryScanPeriod) {
  std::vector<double> times;
  for (int k = 0; k <= 100; ++k) times.push_back(0.05 * k);  // 20 Hz source, 5 s
  const std::vector<std::size_t> frames = framesEvery(times, 0.1);
  ASSERT_EQ(frames.size(), 51u);
  for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i], 2 * i);
  EXPECT_EQ(framesEvery(times, 1.0).size(), 6u);
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
