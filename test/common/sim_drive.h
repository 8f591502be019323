// A small simulated drive around one block, shared by the evaluator and nodelet tests.
#pragma once

#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_sim/sensor.h"

namespace scan_context_loop {
namespace test {

struct Drive {
  sim::World world;
  sim::SensorModel sensor;
  std::vector<Eigen::Isometry3d> truth;  ///< LiDAR poses, one per keyframe (every 2 m)
  std::vector<double> times;             ///< seconds from the first keyframe
  double world_clock = 0.0;              ///< the world's clock at the first keyframe [s]

  pcl::PointCloud<pcl::PointXYZI> scan(std::size_t k) const;
};

/// sim::blockPath: around a 60 x 40 m block, lap 1 counter-clockwise, then lap 2 either the same way one
/// lane further out (reverse_second_lap false) or clockwise in the same lane (true). HDL-64E beams, 900
/// columns.
Drive blockDrive(bool reverse_second_lap, std::uint32_t seed);

/// Two sessions in one world: lap 1 of sim::blockPath at 10 m/s, and the next day that lap driven back
/// the other way one lane over with the parked cars and plants changed (sim::secondSessionDrive). Truth
/// in one frame, keyframes every 2 m, HDL-64E beams, 900 columns.
struct Sessions {
  Drive first, second;
};
Sessions blockSessions(std::uint32_t seed);

}  // namespace test
}  // namespace scan_context_loop
