// Keyframe input shared by the node and the evaluator (KeyframePipeline, loopCovariance).
#include <cmath>

#include <gtest/gtest.h>
#include <pcl/common/transforms.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/keyframes.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

KeyframeInfo headingAt(double x, double yaw_deg, double stamp) {
  KeyframeInfo info;
  info.stamp = stamp;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, 0.5 * x, 0.2);
  pose.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  info.pose = pose;
  return info;
}

TEST(KeyframePipeline, SelectsByDistanceOrYawSinceTheLastKeyframe) {
  Config c;
  c.keyframe_min_distance = 1.0;
  c.keyframe_min_angle = 10.0;
  KeyframePipeline pipeline(c);
  const auto scene = test::streetScene(3);
  // Poses at (x, x / 2) [m] turned by yaw [deg]: selected?
  const struct {
    double x, yaw;
    bool selected;
  } steps[] = {{0.0, 0.0, true},  {0.5, 0.0, false}, {0.95, 0.0, true},
               {1.2, 5.0, false}, {1.3, 12.0, true}, {1.4, 15.0, false}};
  double stamp = 0.0;
  for (const auto& s : steps) {
    const Detection d = pipeline.process(viewOf(scene), headingAt(s.x, s.yaw, stamp += 1.0));
    EXPECT_EQ(d.selected, s.selected) << "x " << s.x << ", yaw " << s.yaw;
    if (d.selected) {
      EXPECT_TRUE(d.accepted) << d.error;
    }
  }
  EXPECT_EQ(pipeline.detector().database().size(), 3u);
}

TEST(KeyframePipeline, RegisteredCloudsDescribeLikeSensorFrameClouds) {
  Config sensor_frame;
  Config world_frame;
  world_frame.cloud_in_world_frame = true;
  KeyframePipeline a(sensor_frame), b(world_frame);
  const auto scene = test::streetScene(4);
  const KeyframeInfo info = headingAt(40.0, 30.0, 1.0);
  pcl::PointCloud<pcl::PointXYZ> registered;
  pcl::transformPointCloud(scene, registered, info.pose->matrix().cast<float>());
  ASSERT_TRUE(a.process(viewOf(scene), info).accepted);
  ASSERT_TRUE(b.process(viewOf(registered), info).accepted);
  const Descriptor& da = a.detector().database().keyframe(0).descriptor;
  const Descriptor& db = b.detector().database().keyframe(0).descriptor;
  ASSERT_EQ(da.ring_key.size(), db.ring_key.size());
  for (std::size_t i = 0; i < da.ring_key.size(); ++i) EXPECT_NEAR(da.ring_key[i], db.ring_key[i], 1e-3) << i;
  // Heights differing in the last float bits can round a unit-column entry the other way.
  EXPECT_LT(align(da, db, sensor_frame).distance, 5e-3);

  // Without its pose a registered cloud cannot be brought back: refused, nothing added.
  KeyframeInfo no_pose;
  no_pose.stamp = 2.0;
  const Detection refused = b.process(viewOf(registered), no_pose);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.error.find("cloud_in_world_frame"), std::string::npos) << refused.error;
  EXPECT_EQ(b.detector().database().size(), 1u);
}

TEST(KeyframePipeline, VoxelFilterThinsTheCloudBeforeDescribing) {
  Config plain, filtered;
  filtered.voxel_leaf = 1.0;
  KeyframePipeline a(plain), b(filtered);
  const auto scene = test::streetScene(5);
  const Detection da = a.process(viewOf(scene), headingAt(0.0, 0.0, 1.0));
  const Detection db = b.process(viewOf(scene), headingAt(0.0, 0.0, 1.0));
  ASSERT_TRUE(da.accepted && db.accepted);
  EXPECT_LT(db.points_used, da.points_used / 2) << da.points_used << " -> " << db.points_used;
  EXPECT_GT(db.points_used, 0u);
}

TEST(KeyframePipeline, TheDescribedCloudIsTheSensorFrameCloudInRange) {
  // A registered cloud comes back in the sensor frame, with the points beyond max_radius (and NaN) left out.
  Config c;
  c.cloud_in_world_frame = true;
  c.max_radius = 30.0;
  KeyframePipeline pipeline(c);
  auto scene = test::streetScene(7);
  scene.push_back(pcl::PointXYZ(std::nanf(""), 1.0f, 1.0f));
  scene.push_back(pcl::PointXYZ(40.0f, 0.0f, 1.0f));
  const KeyframeInfo info = headingAt(40.0, 30.0, 1.0);
  pcl::PointCloud<pcl::PointXYZ> registered, described;
  pcl::transformPointCloud(scene, registered, info.pose->matrix().cast<float>());
  ASSERT_TRUE(pipeline.process(viewOf(registered), info, &described).accepted);
  const pcl::PointCloud<pcl::PointXYZ> expected = keyframeCloud(viewOf(scene), c);
  ASSERT_GT(expected.size(), 1000u);
  EXPECT_LT(expected.size(), scene.size() - 1) << "the far point and the NaN are left out";
  ASSERT_EQ(described.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_LT((described[i].getVector3fMap() - expected[i].getVector3fMap()).norm(), 1e-3f) << i;
    ASSERT_LE(std::hypot(described[i].x, described[i].y), 30.0 + 1e-3) << i;
  }
  // A keyframe that selection passes over leaves it as it was.
  c.keyframe_min_distance = 1.0;
  KeyframePipeline selecting(c);
  ASSERT_TRUE(selecting.process(viewOf(registered), info, &described).accepted);
  pcl::PointCloud<pcl::PointXYZ> untouched;
  EXPECT_FALSE(selecting.process(viewOf(registered), headingAt(40.1, 30.0, 2.0), &untouched).selected);
  EXPECT_TRUE(untouched.empty());
}

/// The points of `scene` within `half_width_deg` of azimuth `centre_deg` (a narrow field of view).
pcl::PointCloud<pcl::PointXYZ> wedge(const pcl::PointCloud<pcl::PointXYZ>& scene, double centre_deg,
                                     double half_width_deg) {
  pcl::PointCloud<pcl::PointXYZ> out;
  for (const auto& p : scene) {
    const double a = std::atan2(p.y, p.x) * 180.0 / M_PI;
    if (std::fabs(std::remainder(a - centre_deg, 360.0)) <= half_width_deg) out.push_back(p);
  }
  return out;
}

TEST(KeyframePipeline, AccumulatedNarrowScansDescribeLikeTheWholeScene) {
  // A sensor that sees 80 degrees at a time, turning 90 degrees between scans at one place: four scans
  // through the odometry cover the scene; one alone is a wedge.
  const auto scene = test::streetScene(6);
  Config whole, narrow, accumulated;
  accumulated.accumulate_seconds = 1.0;
  KeyframePipeline reference(whole), single(narrow), merged(accumulated);
  ASSERT_TRUE(reference.process(viewOf(scene), headingAt(0.0, 0.0, 1.0)).accepted);
  Detection last_single, last_merged;
  for (int k = 0; k < 4; ++k) {
    // Scan k looks along 90k degrees of the world; in its own frame (turned by 90k) that is straight ahead.
    const double heading = 90.0 * k;
    const KeyframeInfo info = headingAt(0.0, heading, 2.0 + 0.1 * k);
    const auto seen = test::rotateTranslate(wedge(scene, heading, 40.0), -heading * M_PI / 180.0, 0.0, 0.0);
    last_single = single.process(viewOf(seen), info);
    last_merged = merged.process(viewOf(seen), info);
  }
  ASSERT_TRUE(last_single.accepted && last_merged.accepted);
  const Descriptor& full = reference.detector().database().keyframe(0).descriptor;
  const auto& dm = merged.detector().database();
  const auto& ds = single.detector().database();
  const double with = align(full, dm.keyframe(dm.size() - 1).descriptor, whole).distance;
  const double without = align(full, ds.keyframe(ds.size() - 1).descriptor, whole).distance;
  EXPECT_LT(with, 0.05) << "merged scans";
  EXPECT_GT(without, 0.3) << "a single wedge";
  EXPECT_GT(last_merged.points_used, 3 * last_single.points_used);
  // Scans older than the window are forgotten: two seconds later only the new scan counts.
  const auto seen = wedge(scene, 0.0, 40.0);
  const Detection later = merged.process(viewOf(seen), headingAt(0.0, 0.0, 5.0));
  EXPECT_EQ(later.points_used, single.process(viewOf(seen), headingAt(0.0, 0.0, 5.0)).points_used);
}

TEST(LoopCovariance, DescriptorPriorIsDiagonalAndARegisteredLoopKeepsItsOwn) {
  Config c;
  c.covariance_translation = 50.0;
  c.covariance_rotation = 0.02;
  Loop prior;
  const Eigen::Matrix<double, 6, 6> p = loopCovariance(prior, c);
  EXPECT_DOUBLE_EQ(p(0, 0), 50.0);
  EXPECT_DOUBLE_EQ(p(2, 2), 50.0);
  EXPECT_DOUBLE_EQ(p(3, 3), 0.02);
  const double half_sector = M_PI / c.num_sectors;
  EXPECT_DOUBLE_EQ(p(5, 5), half_sector * half_sector);
  EXPECT_DOUBLE_EQ(p(0, 1), 0.0);
  Loop registered;
  registered.verified = true;
  registered.verification.covariance = Eigen::Matrix<double, 6, 6>::Identity() * 0.03;
  EXPECT_DOUBLE_EQ(loopCovariance(registered, c)(4, 4), 0.03);
}

}  // namespace
}  // namespace scan_context_loop
