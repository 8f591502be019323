// Ray-casting keyframes in parallel and writing them in the KITTI odometry layout.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_sim/sensor.h"

namespace scan_context_loop {
namespace sim {

struct SequenceData {
  std::vector<Eigen::Isometry3d> truth, odometry;  ///< LiDAR poses, one per keyframe, in the frame `origin`
  /// T_world<-frame of truth: the scans are cast from origin * truth[k] (a team robot's sequence is
  /// relative to its own first keyframe).
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  std::vector<double> times;  ///< seconds from the first keyframe
  double world_clock = 0.0;   ///< the world's clock at the first keyframe [s] (a later drive's start)
};

/// Writes dir/velodyne/%06d.bin (optionally voxel-downsampled), poses.txt, odom_poses.txt, times.txt
/// and calib.txt (Tr: identity). Scan k uses noise seed (seed << 32) ^ k. Returns the mean point count,
/// or -1 with a reason.
double writeSequence(const std::string& dir, const World& world, const SensorModel& sensor, const SequenceData& data,
                     double voxel, std::uint32_t seed, int threads, std::string* error);

}  // namespace sim
}  // namespace scan_context_loop
