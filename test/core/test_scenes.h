// Synthetic scenes and real-data loading shared by the core tests.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {
namespace test {

/// Where ../shared/data is (SCL_SHARED_DATA in the environment wins over the compiled-in path).
std::string sharedData();

/// A non-empty descriptor whose ring key is given; its columns are all alike (unit columns of equal
/// heights).
Descriptor descriptorWithKey(const std::vector<float>& key, const Config& config);

/// A street-like scene in the sensor frame: ground 1.7 m below the sensor, building facades of varied
/// height on both sides, poles and boxy cars, all sampled as surface points. Different seeds give
/// different streets.
pcl::PointCloud<pcl::PointXYZ> streetScene(std::uint32_t seed);

/// Random points whose azimuths sit in the middle third of a sector, so rotating them by whole
/// sectors never moves a point across a sector border (exact column-shift checks).
pcl::PointCloud<pcl::PointXYZ> sectorCentredScene(std::uint32_t seed, int sectors, double max_radius);

/// p' = Rz(yaw) * p + (tx, ty, 0): the cloud as seen from a sensor whose frame is T^-1.
pcl::PointCloud<pcl::PointXYZ> rotateTranslate(const pcl::PointCloud<pcl::PointXYZ>& cloud, double yaw, double tx = 0.0,
                                               double ty = 0.0);

/// `points` laid out `stride` bytes apart with x, y, z at `offset_x` in each, one byte into `bytes` (so
/// that nothing is aligned), and the view of them; every other byte is 0xAB.
PointView inLayout(const std::vector<Eigen::Vector3f>& points, std::size_t stride, std::size_t offset_x,
                   std::vector<std::uint8_t>* bytes);

/// The memory layouts the point kernels read alike: bytes a point and where x sits. x, y, z first in
/// 16- and 32-byte points (read with a loop of their own), then three read point by point.
const std::vector<std::pair<std::size_t, std::size_t>>& pointLayouts();

/// Loads ../shared/data/kitti/<sequence>/velodyne/<frame>.bin; fails the calling test when missing.
pcl::PointCloud<pcl::PointXYZI> kittiScan(const std::string& sequence, int frame);

/// T_query<-match between two LiDAR frames from the sequence's ground truth.
Eigen::Isometry3d kittiRelative(const std::string& sequence, int query, int match);

/// Yaw of `match` in `query`'s LiDAR frame from the sequence's ground truth.
double kittiTrueYaw(const std::string& sequence, int query, int match);

}  // namespace test
}  // namespace scan_context_loop
