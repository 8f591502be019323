// Writes a simulated sequence as a rosbag: keyframe clouds, drifted odometry and ground truth, in the
// default shape or shaped like an odometry stack (scan_context_sim/stack_shape.h).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_sim/stack_shape.h"

namespace scan_context_loop {
namespace sim {

struct BagOptions {
  std::string path;  ///< empty: no bag
  StackShape shape;  ///< topics, frames, registered clouds, camera axes
  std::string truth_topic = "ground_truth";
  double start_stamp = 1.6e9;  ///< bag time of the first keyframe [s]
};

/// One robot's sequence in a bag.
struct BagSequence {
  std::string dir;  ///< its KITTI folder, whose scans go in the bag
  std::vector<Eigen::Isometry3d> truth, odom;
  std::vector<double> times;  ///< seconds after the bag's start_stamp
  /// A team robot's id: its topics go in its namespace and its frames are its own (forRobot); empty: one
  /// robot, the shape as it is.
  std::string robot;
};

/// Several robots' sequences in one bag, each as writeBag below writes one, their messages in time order
/// across the robots; the robots' fixed transforms latched together in one /tf_static message.
bool writeBag(const std::vector<BagSequence>& sequences, const BagOptions& options, std::string* error);

/// Reads the scans back from sequence_dir/velodyne and writes one cloud, one odometry and one ground-truth
/// message per keyframe, all stamped start_stamp + times[k]. The ground truth is shaped like the odometry
/// (same frames and axes). Registered clouds are moved into the odometry frame with the drifted pose, as
/// the stack registers them. The stack's tf comes too: its fixed transforms (camera-axes extrinsic, map ->
/// odometry frame) latched on /tf_static or repeated on /tf as tf1's static_transform_publisher sends
/// them (StackShape::fixed_tf_period), and the odometry on /tf when the stack broadcasts it.
bool writeBag(const std::string& sequence_dir, const std::vector<Eigen::Isometry3d>& truth,
              const std::vector<Eigen::Isometry3d>& odom, const std::vector<double>& times, const BagOptions& options,
              std::string* error);

}  // namespace sim
}  // namespace scan_context_loop
