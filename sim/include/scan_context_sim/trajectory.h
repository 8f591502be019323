// Drives for the simulator: keyframes along a real KITTI trajectory or a procedural city drive, the
// sensor poses over the simulated ground, and a drifting odometry.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

/// Planar positions and headings, one per source frame, from LiDAR poses (x forward, z up), frames
/// [first, last] (last < 0: to the end).
std::vector<PathPoint> pathFromPoses(const std::vector<Eigen::Isometry3d>& lidar_poses, int first, int last);

/// The procedural drive, about 2.1 km sampled every 0.5 m: a loop around a 250 x 150 m block, the same
/// loop again one lane (3 m) further out, the first half of the bottom street again in the same lane
/// (same-direction revisit), a new street through the middle, then the east half of the top street
/// and the east street driven the other way in the opposite lane, 3 m to the side (reverse-direction
/// revisits, as real traffic makes them).
std::vector<PathPoint> proceduralPath();

/// A short drive around a 60 x 40 m block sampled every 0.5 m (sharp corners): lap 1 counter-clockwise,
/// then lap 2 either clockwise in the same lane (reverse_second_lap) or the same way 3 m further out.
/// About 400 m.
std::vector<PathPoint> blockPath(bool reverse_second_lap);

/// Distance travelled from the first path point to each one [m].
std::vector<double> distanceAlong(const std::vector<PathPoint>& path);

/// Indices of the path points that become keyframes: the first, then each one at least `spacing`
/// metres of travel after the previous keyframe.
std::vector<std::size_t> keyframesEvery(const std::vector<PathPoint>& path, double spacing);

/// Indices of the frames a sensor scanning every `period` seconds keeps: the first, then each one at
/// least `period` after the previous one kept (times in seconds, ascending).
std::vector<std::size_t> framesEvery(const std::vector<double>& times, double period);

/// Sensor pose over the world's ground: above (x, y), mount_height along the ground's normal, yawed by
/// heading and tilted with the slope.
Eigen::Isometry3d sensorPose(const World& world, const PathPoint& p, double mount_height);

/// How the simulated odometry drifts. Each error rate is a slowly wandering bias (a Gauss-Markov
/// process with the given standard deviation and correlation length), not white noise, so the drift
/// over a stretch is about rate x length whatever the keyframe spacing, like a real odometry's scale
/// error, side slip and gyro bias.
struct DriftOptions {
  double translation_per_metre = 0.01;  ///< translation error per metre travelled (0.01: 1 %) [m/m]
  double yaw_per_metre = 0.003;         ///< heading error per metre travelled [deg/m]
  double yaw_per_degree = 0.005;        ///< heading error per degree turned [deg/deg]
  double correlation_length = 300.0;    ///< distance over which the biases change [m]
  std::uint32_t seed = 1;
};

/// Odometry that starts at the first true pose and composes each true relative motion with an error
/// drawn from the drifting biases (plus a little white noise).
std::vector<Eigen::Isometry3d> driftedOdometry(const std::vector<Eigen::Isometry3d>& truth,
                                               const DriftOptions& options);

}  // namespace sim
}  // namespace scan_context_loop
