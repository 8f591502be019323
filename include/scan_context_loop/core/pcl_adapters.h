// PCL at the edge of the core, in one header: views of PCL clouds for the descriptor and the detector
// (which take a PointView), the descriptor's PCL overloads, and the PCL clouds the core builds.
#pragma once

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {

/// A view of any PCL cloud whose point type has float x, y, z members.
template <typename PointT>
PointView viewOf(const pcl::PointCloud<PointT>& cloud) {
  PointView view;
  if (cloud.empty()) return view;
  const auto* base = reinterpret_cast<const std::uint8_t*>(cloud.points.data());
  const auto* first = &cloud.points.front();
  view.data = base;
  view.count = cloud.size();
  view.stride = sizeof(PointT);
  view.offset_x = reinterpret_cast<const std::uint8_t*>(&first->x) - base;
  view.offset_y = reinterpret_cast<const std::uint8_t*>(&first->y) - base;
  view.offset_z = reinterpret_cast<const std::uint8_t*>(&first->z) - base;
  return view;
}

template <typename PointT>
HeightGrid makeHeightGrid(const pcl::PointCloud<PointT>& cloud, const Config& config,
                          const Eigen::Vector2f& viewpoint = Eigen::Vector2f::Zero()) {
  return makeHeightGrid(viewOf(cloud), config, viewpoint);
}

template <typename PointT>
Descriptor makeDescriptor(const pcl::PointCloud<PointT>& cloud, const Config& config,
                          const Eigen::Vector2f& viewpoint = Eigen::Vector2f::Zero()) {
  return makeDescriptor(viewOf(cloud), config, viewpoint);
}

/// The finite points of `points`, each rotated by R (NaN/Inf points are dropped).
pcl::PointCloud<pcl::PointXYZ> rotatedCloud(const PointView& points, const Eigen::Matrix3f& R);
/// The finite points of `points`, each moved by `transform` (NaN/Inf points are dropped).
pcl::PointCloud<pcl::PointXYZ> transformedCloud(const PointView& points, const Eigen::Affine3f& transform);

}  // namespace scan_context_loop
