#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/keyframes.h"

#include <cmath>

#include <pcl/filters/voxel_grid.h>

#include "scan_context_loop/core/levelling.h"

namespace scan_context_loop {

Eigen::Matrix<double, 6, 6> loopCovariance(const Loop& loop, const Config& config) {
  if (loop.verified || !loop.verification.reason.empty()) return loop.verification.covariance;
  const double half_sector = M_PI / config.num_sectors;
  Eigen::Matrix<double, 6, 1> diagonal;
  diagonal << config.covariance_translation, config.covariance_translation, config.covariance_translation,
      config.covariance_rotation, config.covariance_rotation, half_sector * half_sector;
  return diagonal.asDiagonal();
}

bool KeyframePipeline::selected(const KeyframeInfo& info) const {
  const Config& c = config();
  if (c.keyframe_min_distance <= 0.0 && c.keyframe_min_angle <= 0.0) return true;
  if (!has_last_ || !info.pose) return true;
  const Eigen::Isometry3d delta = last_pose_.inverse() * *info.pose;
  const bool moved = c.keyframe_min_distance > 0.0 && delta.translation().norm() >= c.keyframe_min_distance;
  const double yaw = std::atan2(delta(1, 0), delta(0, 0));
  const bool turned = c.keyframe_min_angle > 0.0 && std::fabs(yaw) * 180.0 / M_PI >= c.keyframe_min_angle;
  return moved || turned;
}

Detection KeyframePipeline::process(const PointView& cloud, const KeyframeInfo& info) {
  const Config& c = config();
  if (!selected(info)) {
    Detection skipped;
    skipped.selected = false;
    return skipped;
  }
  PointView view = cloud;
  pcl::PointCloud<pcl::PointXYZ> copy;
  if (c.cloud_in_world_frame || c.voxel_leaf > 0.0) {
    Eigen::Affine3f to_sensor = Eigen::Affine3f::Identity();
    if (c.cloud_in_world_frame) {
      if (!info.pose) {
        Detection refused;
        refused.error = "a cloud registered in the world frame (cloud_in_world_frame) needs its pose";
        return refused;
      }
      to_sensor = Eigen::Affine3f(info.pose->inverse().matrix().cast<float>());
    }
    copy = transformedCloud(cloud, to_sensor);
    if (c.voxel_leaf > 0.0 && !copy.empty()) {
      pcl::PointCloud<pcl::PointXYZ> filtered;
      pcl::VoxelGrid<pcl::PointXYZ> grid;
      const float leaf = static_cast<float>(c.voxel_leaf);
      grid.setLeafSize(leaf, leaf, leaf);
      grid.setInputCloud(copy.makeShared());
      grid.filter(filtered);
      copy.swap(filtered);
    }
    view = viewOf(copy);
  }
  Detection detection = detector_.process(view, info);
  if (detection.accepted && info.pose) {
    has_last_ = true;
    last_pose_ = *info.pose;
  }
  return detection;
}

}  // namespace scan_context_loop
