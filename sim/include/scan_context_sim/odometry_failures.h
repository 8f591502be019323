// Odometry that fails the way real LiDAR odometry does, on top of the slow drift of driftedOdometry():
// a heading that breaks down and keeps turning away (A-LOAM over a long drive), sudden heading jumps (a
// bad scan match), forward motion lost along a featureless stretch (a degenerate corridor or an open
// road), and a restart from the identity (the odometry node restarted, stamps going on).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace sim {

struct OdometryFailures {
  /// Heading error added from `ramp_start` (a fraction of the path length) on, growing in proportion to
  /// the distance travelled to this at the end [deg] (0: none).
  double heading_ramp_deg = 0.0;
  double ramp_start = 0.5;
  /// Sudden heading errors of `heading_jump_deg` (random sign) at `heading_jumps` random keyframes.
  int heading_jumps = 0;
  double heading_jump_deg = 15.0;
  /// Forward motion scaled by `slip_scale` over `slip_length` metres from `slip_start` metres along the
  /// path (slip_length 0: none): the odometry of a corridor its scan matching cannot fix along.
  double slip_start = 0.0, slip_length = 0.0, slip_scale = 0.5;
  /// The odometry restarts from the identity at this path length [m] (negative: never).
  double restart_at = -1.0;
  std::uint32_t seed = 1;

  bool any() const { return heading_ramp_deg != 0.0 || heading_jumps > 0 || slip_length > 0.0 || restart_at >= 0.0; }
};

/// Empty when the options are usable, else what is wrong.
std::string checkFailures(const OdometryFailures& failures);

/// `odometry` (one pose per keyframe) with each relative motion composed with the failures' errors.
std::vector<Eigen::Isometry3d> withFailures(const std::vector<Eigen::Isometry3d>& odometry,
                                            const OdometryFailures& failures);

}  // namespace sim
}  // namespace scan_context_loop
