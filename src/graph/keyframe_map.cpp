#include "scan_context_loop/graph/keyframe_map.h"

#include <cmath>

#include <pcl/filters/voxel_grid.h>

#include "scan_context_loop/graph/pose_graph_settings.h"

namespace scan_context_loop {

namespace {

/// `cloud` thinned to one point (the centroid) per voxel of edge `voxel`.
pcl::PointCloud<pcl::PointXYZ> thinned(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, double voxel) {
  pcl::PointCloud<pcl::PointXYZ> out;
  if (cloud->empty()) return out;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(cloud);
  grid.setLeafSize(static_cast<float>(voxel), static_cast<float>(voxel), static_cast<float>(voxel));
  grid.filter(out);
  return out;
}

}  // namespace

std::vector<std::string> KeyframeMapConfig::validate() const { return checkSettings(keyframeMapSettings(), *this); }

KeyframeMap::KeyframeMap(const KeyframeMapConfig& config) : config_(config) {}

std::size_t KeyframeMap::add(std::size_t index, const std::vector<Eigen::Vector3f>& points, long ordinal) {
  const std::size_t counted = ordinal >= 0 ? static_cast<std::size_t>(ordinal) : index;
  if (counted % static_cast<std::size_t>(config_.keyframe_stride) != 0) return 0;
  pcl::PointCloud<pcl::PointXYZ>::Ptr near(new pcl::PointCloud<pcl::PointXYZ>);
  near->reserve(points.size());
  const double r2 = config_.max_range * config_.max_range;
  for (const auto& p : points) {
    if (!p.allFinite() || std::abs(p.z()) > config_.max_range) continue;
    if (static_cast<double>(p.x()) * p.x() + static_cast<double>(p.y()) * p.y() > r2) continue;
    near->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  }
  const auto thin = thinned(near, config_.voxel);
  Stored stored{index, {}};
  stored.points.reserve(thin.size());
  for (const auto& p : thin) stored.points.emplace_back(p.x, p.y, p.z);
  points_ += stored.points.size();
  clouds_.push_back(std::move(stored));
  return clouds_.back().points.size();
}

pcl::PointCloud<pcl::PointXYZ> KeyframeMap::assemble(const std::vector<Eigen::Isometry3d>& poses,
                                                     const std::vector<bool>& leave_out) const {
  pcl::PointCloud<pcl::PointXYZ>::Ptr all(new pcl::PointCloud<pcl::PointXYZ>);
  all->reserve(points_);
  for (const auto& stored : clouds_) {
    if (stored.index >= poses.size() || (stored.index < leave_out.size() && leave_out[stored.index])) continue;
    const Eigen::Isometry3f pose = poses[stored.index].cast<float>();
    for (const auto& p : stored.points) {
      const Eigen::Vector3f w = pose * p;
      all->push_back(pcl::PointXYZ(w.x(), w.y(), w.z()));
    }
  }
  return thinned(all, config_.voxel);
}

}  // namespace scan_context_loop
