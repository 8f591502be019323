// The free-space check behind verification: what stands in space a keyframe saw through.
#include <cmath>

#include <gtest/gtest.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/free_space.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {
namespace {

/// A vertical wall of points across the x axis at distance `x`, `width` wide, from 1.7 m below the
/// sensor to its height.
void addWall(pcl::PointCloud<pcl::PointXYZ>* cloud, double x, double width) {
  for (double y = -width / 2; y <= width / 2; y += 0.1) {
    for (double z = -1.7; z <= 0.0; z += 0.1) cloud->push_back(pcl::PointXYZ(x, y, z));
  }
}

VoxelCloud voxels(const pcl::PointCloud<pcl::PointXYZ>& cloud) {
  return prepareCloud(viewOf(cloud), VerificationConfig());
}

TEST(FreeSpace, StructureInFrontOfWhatWasSeenViolatesIt) {
  pcl::PointCloud<pcl::PointXYZ> far_wall, near_wall, farther_wall;
  addWall(&far_wall, 12.0, 6.0);
  addWall(&near_wall, 5.0, 3.0);
  addWall(&farther_wall, 20.0, 6.0);
  const VoxelCloud seen = voxels(far_wall);
  const FreeSpace free_space = freeSpace(seen);
  // Straight ahead the nearest structure is 12 m away; elsewhere nothing within the crop.
  EXPECT_NEAR(free_space.nearest[free_space.nearest.size() / 2], 12.0, 0.6);
  EXPECT_FLOAT_EQ(free_space.nearest[0], seen.max_range);
  // A wall at 5 m would have hidden it: every one of its structure voxels violates the free space.
  const FreeSpaceCheck in_front = checkFreeSpace(voxels(near_wall), free_space, Eigen::Isometry3d::Identity());
  EXPECT_GT(in_front.covered, 5u);
  EXPECT_GT(in_front.ratio(), 0.9);
  // One behind it is hidden by it, not contradicted; and the wall itself agrees with itself.
  EXPECT_EQ(checkFreeSpace(voxels(farther_wall), free_space, Eigen::Isometry3d::Identity()).violating, 0u);
  EXPECT_EQ(checkFreeSpace(seen, free_space, Eigen::Isometry3d::Identity()).violating, 0u);
  // Moved 3 m towards the sensor it stands in seen-through space.
  Eigen::Isometry3d closer = Eigen::Isometry3d::Identity();
  closer.translation().x() = -3.0;
  EXPECT_GT(checkFreeSpace(seen, free_space, closer).ratio(), 0.9);
}

TEST(FreeSpace, OnlyTheBandEverySensorSeesCounts) {
  const FreeSpace band;
  EXPECT_TRUE(band.counts(Eigen::Vector3f(10.0f, 0.0f, 0.1f)));
  EXPECT_FALSE(band.counts(Eigen::Vector3f(10.0f, 0.0f, 1.0f)));  // above +1 deg
  EXPECT_TRUE(band.counts(Eigen::Vector3f(10.0f, 0.0f, -1.7f)));
  EXPECT_FALSE(band.counts(Eigen::Vector3f(3.0f, 0.0f, -1.7f)));  // below -20 deg
  const FreeSpace nothing = freeSpace(VoxelCloud());
  EXPECT_EQ(checkFreeSpace(VoxelCloud(), nothing, Eigen::Isometry3d::Identity()).covered, 0u);
  EXPECT_EQ(checkFreeSpace(VoxelCloud(), nothing, Eigen::Isometry3d::Identity()).ratio(), 0.0);
}

/// A VLP-16-like keyframe: flat ground 1.7 m below seen by rings from -15 deg up (every 2 deg), and a
/// wall 12 m ahead.
pcl::PointCloud<pcl::PointXYZ> sparseScene() {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (double elevation = -15.0; elevation < -1.0; elevation += 2.0) {
    const double r = 1.7 / std::tan(-elevation * M_PI / 180.0);
    if (r > 11.0) continue;
    for (double a = -M_PI; a < M_PI; a += 0.004) cloud.push_back(pcl::PointXYZ(r * std::cos(a), r * std::sin(a), -1.7));
  }
  addWall(&cloud, 12.0, 6.0);
  return cloud;
}

TEST(FreeSpace, ASparseSensorAnswersOnlyForTheBandItSees) {
  const VoxelCloud seen = voxels(sparseScene());
  const FreeSpace free_space = freeSpace(seen);
  // Its lowest returns are 15 deg down, so the band it answers for ends a degree or so above them (within
  // its two lowest rings: the second percentile of its voxels), not at 20 deg.
  EXPECT_GT(free_space.min_slope, std::tan(-15.0 * M_PI / 180.0));
  EXPECT_LT(free_space.min_slope, std::tan(-11.0 * M_PI / 180.0));
  EXPECT_FALSE(free_space.counts(Eigen::Vector3f(5.0f, 0.0f, -1.6f)));  // -17.7 deg: below what it sees
  EXPECT_TRUE(free_space.counts(Eigen::Vector3f(12.0f, 0.0f, -1.6f)));
  // So a low wall 5 m to its side, which another keyframe saw and it could not have, does not count
  // against a loop; the default band would have held it against it.
  pcl::PointCloud<pcl::PointXYZ> low_wall;
  for (double x = -1.0; x <= 1.0; x += 0.05) {
    for (double z = -1.7; z <= -1.06; z += 0.05) low_wall.push_back(pcl::PointXYZ(x, 5.0, z));
  }
  const VoxelCloud low = voxels(low_wall);
  EXPECT_EQ(checkFreeSpace(low, free_space, Eigen::Isometry3d::Identity()).covered, 0u);
  FreeSpace default_band = free_space;
  default_band.min_slope = FreeSpace().min_slope;
  EXPECT_GT(checkFreeSpace(low, default_band, Eigen::Isometry3d::Identity()).violating, 0u);
  // A dense sensor (returns down to 40 deg) keeps the default band.
  pcl::PointCloud<pcl::PointXYZ> dense;
  addWall(&dense, 12.0, 6.0);
  for (double x = -20.0; x < 20.0; x += 0.2) {
    for (double y = -20.0; y < 20.0; y += 0.2) {
      if (std::hypot(x, y) > 2.0) dense.push_back(pcl::PointXYZ(x, y, -1.7));
    }
  }
  EXPECT_FLOAT_EQ(freeSpace(voxels(dense)).min_slope, FreeSpace().min_slope);
}

}  // namespace
}  // namespace scan_context_loop
