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
  EXPECT_TRUE(FreeSpace::counts(Eigen::Vector3f(10.0f, 0.0f, 0.1f)));
  EXPECT_FALSE(FreeSpace::counts(Eigen::Vector3f(10.0f, 0.0f, 1.0f)));   // above +1 deg
  EXPECT_TRUE(FreeSpace::counts(Eigen::Vector3f(10.0f, 0.0f, -1.7f)));
  EXPECT_FALSE(FreeSpace::counts(Eigen::Vector3f(3.0f, 0.0f, -1.7f)));   // below -20 deg
  const FreeSpace nothing = freeSpace(VoxelCloud());
  EXPECT_EQ(checkFreeSpace(VoxelCloud(), nothing, Eigen::Isometry3d::Identity()).covered, 0u);
  EXPECT_EQ(checkFreeSpace(VoxelCloud(), nothing, Eigen::Isometry3d::Identity()).ratio(), 0.0);
}

}  // namespace
}  // namespace scan_context_loop
