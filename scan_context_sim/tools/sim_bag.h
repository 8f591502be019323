// Writes a simulated sequence as a rosbag: keyframe clouds, drifted odometry and ground truth.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace sim {

struct BagOptions {
  std::string path;  ///< empty: no bag
  std::string cloud_topic = "keyframe_cloud";
  std::string odom_topic = "keyframe_odom";
  std::string truth_topic = "ground_truth";
  std::string sensor_frame = "velodyne";
  std::string odom_frame = "odom";
  double start_stamp = 1.6e9;  ///< bag time of the first keyframe [s]
};

/// Reads the scans back from sequence_dir/velodyne and writes one cloud, one odometry and one ground-truth
/// message per keyframe, all stamped start_stamp + times[k].
bool writeBag(const std::string& sequence_dir, const std::vector<Eigen::Isometry3d>& truth,
              const std::vector<Eigen::Isometry3d>& odom, const std::vector<double>& times, const BagOptions& options,
              std::string* error);

}  // namespace sim
}  // namespace scan_context_loop
