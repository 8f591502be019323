// A sensor that does not stay level: hand-held, on a backpack or on a legged robot, it rolls and
// pitches as the platform sways and steps. Scan Context assumes a level sensor, so this is a hard case.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

struct TiltOptions {
  /// Typical tilt [deg]: roll and pitch each have a standard deviation of 0.58 x this, so the angle
  /// between the sensor's up axis and the platform's has a median of about 0.68 x and a 90th
  /// percentile of about 1.25 x this. 0: a level sensor.
  double typical_deg = 0.0;
  double correlation_length = 12.0;  ///< distance over which the slow sway changes [m]
  double step_length = 0.7;          ///< one step of the gait: the sensor bobs (pitch) once per step,
                                     ///< and sways (roll) once per stride of two steps [m]
  double gait_share = 0.1;           ///< share of the tilt's variance that comes from the gait
  std::uint32_t seed = 1;
};

/// Roll and pitch [rad] at each path point: a smooth random sway (a second-order Gauss-Markov process
/// in distance travelled) plus a gait oscillation whose cadence wanders a little, so keyframes a fixed
/// distance apart do not all catch it at the same phase. All zero when typical_deg is 0.
std::vector<Eigen::Vector2d> platformTilt(const std::vector<PathPoint>& path, const TiltOptions& options);

/// The pose rolled about its forward axis and pitched about its left axis (in the pose's own frame,
/// so the heading is kept): pose * Ry(pitch) * Rx(roll).
Eigen::Isometry3d tiltPose(const Eigen::Isometry3d& pose, const Eigen::Vector2d& roll_pitch);

/// Angle between the pose's up axis and the world's [rad].
double tiltAngle(const Eigen::Isometry3d& pose);

}  // namespace sim
}  // namespace scan_context_loop
