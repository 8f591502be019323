// The poses of a nav_msgs/Path, for the backend's tests.
#pragma once

#include <vector>

#include <Eigen/Geometry>
#include <nav_msgs/Path.h>
#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {
namespace test {

inline std::vector<Eigen::Isometry3d> posesOf(const nav_msgs::Path& path) {
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : path.poses) {
    Eigen::Isometry3d pose;
    tf2::fromMsg(p.pose, pose);
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace test
}  // namespace scan_context_loop
