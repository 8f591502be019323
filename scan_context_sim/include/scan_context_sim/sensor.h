// Spinning LiDAR models (real beam patterns) and ray-cast scans of a World.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

struct SensorModel {
  std::string name;
  std::vector<float> elevations_deg;  ///< one per beam
  int columns = 2000;                 ///< firings per revolution
  float max_range = 100.0f;           ///< [m]
  float min_range = 0.9f;             ///< returns closer than this are dropped [m]
  float range_noise = 0.02f;          ///< Gaussian sigma [m]
  float dropout = 0.02f;              ///< probability that a return is lost
  /// Range at which a dim return (reflectivity 0.1 at normal incidence) is detected half the time [m];
  /// brighter surfaces reach further (with the square root of the reflectivity), and grazing ones --
  /// distant ground -- fade sooner, as the rings of real scans do. 0: every return within max_range.
  float dim_range = 100.0f;
  float mount_height = 1.73f;         ///< sensor above the ground [m]
  /// A ray without a return (nothing hit, lost, too dim, out of range) is still reported, as (0, 0, 0):
  /// Ouster's drivers publish their organised clouds this way.
  bool zeros_for_no_return = false;
};

/// "hdl64" (Velodyne HDL-64E: 64 beams, +2 to -24.9 deg), "vlp16" (Velodyne VLP-16: 16 beams, +-15 deg),
/// "os1-64" (Ouster OS1-64: 64 beams, +-16.6 deg, (0, 0, 0) for rays without a return). Returns false
/// for an unknown name.
bool sensorPreset(const std::string& name, SensorModel* model);

/// Ray-casts one revolution from the sensor pose `world_from_sensor` at `time`; points in the sensor
/// frame (x forward, y left, z up) with an intensity from the surface and the incidence angle.
/// `seed` makes the noise and dropout repeatable.
pcl::PointCloud<pcl::PointXYZI> scan(const World& world, const SensorModel& sensor,
                                     const Eigen::Isometry3d& world_from_sensor, double time, std::uint64_t seed);

}  // namespace sim
}  // namespace scan_context_loop
