#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "scan_context_loop/graph/keyframe_map.h"

namespace scan_context_loop {
namespace {

/// A 10 x 10 m wall of points every 5 cm at x = 5 m, and one far point and one NaN.
std::vector<Eigen::Vector3f> wall() {
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 40; ++j) points.emplace_back(5.0f, -5.0f + 0.05f * i, 0.05f * j);
  }
  points.emplace_back(80.0f, 0.0f, 1.0f);
  points.emplace_back(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f);
  return points;
}

TEST(KeyframeMap, ThinsEachCloudDropsFarAndNonFinitePointsAndPlacesThemAtThePoses) {
  KeyframeMapConfig config;
  config.voxel = 0.5;
  config.max_range = 50.0;
  KeyframeMap map(config);
  const std::size_t kept = map.add(0, wall());
  // 10 m x 2 m of wall in 0.5 m voxels: 20 x 4 cells (the wall sits on one cell boundary at most).
  EXPECT_GE(kept, 80u);
  EXPECT_LE(kept, 2 * 80u);
  EXPECT_EQ(map.points(), kept);

  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(100.0, 0.0, 0.0));
  pose.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const auto cloud = map.assemble({pose});
  ASSERT_FALSE(cloud.empty());
  for (const auto& p : cloud) {
    // The wall at sensor x = 5 m turned a quarter left and moved to x = 100: world y = 5 m.
    EXPECT_NEAR(p.y, 5.0, 0.3);
    EXPECT_NEAR(p.x, 100.0, 5.3);
    EXPECT_TRUE(std::isfinite(p.z));
  }
}

TEST(KeyframeMap, KeepsEveryNthKeyframeAndMergesOverlapsIntoOneVoxelGrid) {
  KeyframeMapConfig config;
  config.keyframe_stride = 2;
  KeyframeMap map(config);
  EXPECT_GT(map.add(0, wall()), 0u);
  EXPECT_EQ(map.add(1, wall()), 0u);
  EXPECT_GT(map.add(2, wall()), 0u);
  EXPECT_EQ(map.keyframes(), 2u);
  const std::vector<Eigen::Isometry3d> same(3, Eigen::Isometry3d::Identity());
  // Two keyframes at one pose see the same wall: the map holds it once.
  EXPECT_EQ(map.assemble(same).size(), map.points() / 2);
  // A keyframe beyond the poses given is left out.
  EXPECT_EQ(map.assemble({Eigen::Isometry3d::Identity()}).size(), map.points() / 2);
  EXPECT_TRUE(map.assemble({}).empty());
}

TEST(KeyframeMap, RefusesUnusableSettings) {
  KeyframeMapConfig config;
  EXPECT_TRUE(config.validate().empty());
  config.voxel = 0.0;
  config.max_range = -1.0;
  config.keyframe_stride = 0;
  EXPECT_EQ(config.validate().size(), 3u);
}

}  // namespace
}  // namespace scan_context_loop
