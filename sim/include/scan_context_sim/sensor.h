// LiDAR models -- spinning multi-beam sensors (real beam patterns) and Livox-like non-repetitive
// scanners -- and ray-cast scans of a World.
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

/// How the rays of one scan are laid out.
enum class ScanPattern {
  kSpinning,  ///< elevations_deg x columns: one revolution of a spinning multi-beam sensor, the same every scan
  /// Livox Avia-like: a rosette traced by two counter-rotating prisms (pattern_hz) over a forward field of
  /// view (fov_horizontal_deg wide, fov_top_deg to fov_bottom_deg); the rates never lock, so each scan
  /// covers other patches of the field of view.
  kRosette,
  /// Livox Mid-360-like: pattern_hz[0] turns a second in azimuth while the elevation sweeps between
  /// fov_top_deg and fov_bottom_deg pattern_hz[1] times a second, a rate that never locks to the turn.
  kSweep360,
};

struct SensorModel {
  std::string name;
  ScanPattern pattern = ScanPattern::kSpinning;
  std::vector<float> elevations_deg;  ///< kSpinning: one per beam
  int columns = 2000;                 ///< kSpinning: firings per revolution
  /// Non-repetitive patterns: ray i of the scan at `time` fires at time + i / ray_rate, so the pattern
  /// depends on the time and each scan differs from the one before.
  double ray_rate = 0.0;              ///< rays per second
  int rays_per_scan = 0;              ///< ray_rate x the scan period
  float fov_horizontal_deg = 360.0f;  ///< kRosette: width of the field of view, centred on x [deg]
  float fov_top_deg = 0.0f;           ///< elevation of the field of view's top edge [deg]
  float fov_bottom_deg = 0.0f;        ///< and of its bottom edge [deg]
  double pattern_hz[2] = {0.0, 0.0};  ///< the pattern's two rates (see ScanPattern) [1/s]
  float max_range = 100.0f;           ///< [m]
  float min_range = 0.9f;             ///< returns closer than this are dropped [m]
  float range_noise = 0.02f;          ///< Gaussian sigma [m]
  float dropout = 0.02f;              ///< probability that a return is lost
  /// Range at which a dim return (reflectivity 0.1 at normal incidence) is detected half the time [m];
  /// brighter surfaces reach further (with the square root of the reflectivity), and grazing ones --
  /// distant ground -- fade sooner, as the rings of real scans do. 0: every return within max_range.
  float dim_range = 100.0f;
  float mount_height = 1.73f;  ///< sensor above the ground [m]
  /// Full beam divergence [rad]: a beam's footprint is this times the range wide. A thin limb
  /// (Material::kBranch) narrower than the footprint returns only the share of the beam it covers, so
  /// its return is dimmer and fades sooner with range (the rest of the beam goes on, unseen).
  float beam_divergence = 0.003f;
  /// A ray without a return (nothing hit, lost, too dim, out of range) is still reported, as (0, 0, 0):
  /// Ouster's drivers publish their organised clouds this way.
  bool zeros_for_no_return = false;
};

/// "hdl64" (Velodyne HDL-64E: 64 beams, +2 to -24.9 deg), "vlp16" (Velodyne VLP-16: 16 beams, +-15 deg),
/// "os1-64" (Ouster OS1-64: 64 beams, +-16.6 deg, (0, 0, 0) for rays without a return), "livox-avia"
/// (rosette, 70.4 x 77.2 deg forward, 24,000 rays per 0.1 s scan), "livox-mid360" (360 x -7 to +52 deg,
/// 20,000 rays per 0.1 s scan). Returns false for an unknown name.
bool sensorPreset(const std::string& name, SensorModel* model);

/// The preset names, for usage texts: "hdl64 | vlp16 | ...".
std::string sensorPresetNames();

/// The top and bottom elevation of the sensor's field of view [deg].
float fovTopDeg(const SensorModel& sensor);
float fovBottomDeg(const SensorModel& sensor);

/// Unit directions (sensor frame: x forward, y left, z up) of the rays of the scan at `time`, in firing order.
std::vector<Eigen::Vector3f> rayDirections(const SensorModel& sensor, double time);

/// Ray-casts one scan (rayDirections) from the sensor pose `world_from_sensor` at `time`; points in the sensor
/// frame (x forward, y left, z up) with an intensity from the surface and the incidence angle.
/// `seed` makes the noise and dropout repeatable.
pcl::PointCloud<pcl::PointXYZI> scan(const World& world, const SensorModel& sensor,
                                     const Eigen::Isometry3d& world_from_sensor, double time, std::uint64_t seed);

}  // namespace sim
}  // namespace scan_context_loop
