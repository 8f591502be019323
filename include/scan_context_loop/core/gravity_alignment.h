// Gravity alignment of keyframe clouds before they are described.
//
// Scan Context bins points by horizontal range and azimuth and keeps the maximum height per bin, so it
// assumes the sensor's z axis points up. A hand-held, backpack or legged sensor tilted by 10-20 degrees
// sees the ground rise on one side and fall on the other, and its descriptor no longer matches the one
// of a level pass through the same place. Rotating each cloud into a gravity-aligned frame L first removes that.
//
// The gravity-aligned frame L of a sensor: z of L points up (against gravity), x of L is the sensor's x axis
// projected on the horizontal plane (the sensor's heading), y completes a right-handed frame. Its
// origin is the sensor's. Only roll and pitch are removed; yaw is what Scan Context aligns itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {

/// L_R_sensor for a sensor that sees `up` (the direction against gravity, in the sensor frame, any
/// length > 0). Row 2 is the unit `up`; row 0 the sensor's x projected on the plane normal to it. When
/// the sensor's x points straight up or down (no heading), the sensor's y projected takes the role of
/// L's y instead.
Eigen::Matrix3d gravityAlignmentFromUp(const Eigen::Vector3d& up);

/// L_R_sensor from an orientation world_R_sensor whose world frame has z up (gravity-aligned):
/// Rz(-psi) * world_R_sensor with psi = atan2(R(1, 0), R(0, 0)), the sensor's heading in the world.
/// Assumes the pose's world frame is gravity-aligned. That holds for odometry that turns its first pose
/// to the IMU's gravity-referenced orientation (LIO-SAM takes its first roll and pitch from the IMU), but
/// not for odometry whose world frame is the first scan's sensor frame (A-LOAM, LeGO-LOAM) or the IMU's
/// frame at start-up (FAST-LIO estimates gravity as a state in that frame and leaves the orientation at
/// the identity): those frames are as tilted as the sensor was when it started; use gravityAlignmentFromGround
/// then.
Eigen::Matrix3d gravityAlignmentFromOrientation(const Eigen::Matrix3d& world_R_sensor);

/// How the ground plane is looked for. Defaults suit a LiDAR 0.3-5 m above mostly open ground.
struct GroundFitOptions {
  /// Only points whose horizontal range (in the sensor frame) is in [min_range, max_range] [m]: the
  /// carrier's own returns are closer, and far ground is sparse, noisy and often not the same plane.
  double min_range = 2.0;
  double max_range = 30.0;
  /// The ground's normal is within this angle of the sensor's z axis [degrees].
  double ground_plane_max_tilt_deg = 35.0;
  /// The sensor is between min_height and max_height above the plane [m]: rejects ceilings, table
  /// tops and car roofs just below the sensor.
  double min_height = 0.3;
  double max_height = 5.0;
  /// A point within this distance of the plane is ground [m]. Road camber and kerbs are within it.
  double inlier_distance = 0.15;
  /// Points sampled from the cloud at most, evenly by index (spinning LiDARs store their points ring
  /// by ring, so this keeps every ring). Bounds the time of the fit (tools/bench.cpp measures it).
  std::size_t max_points = 3000;
  /// Plane hypotheses from three sampled points each.
  int iterations = 100;
  /// No gravity alignment is given when fewer of the sampled points than this, or than min_inlier_ratio of
  /// them, lie on the best plane. The ratio is above what a slab of 2 x inlier_distance cuts from walls
  /// 3 m high (10%), so a corridor whose floor is out of view is not gravity-aligned to a band of its walls.
  std::size_t min_inliers = 100;
  double min_inlier_ratio = 0.2;
  /// The ground hides what is under it: a plane with more than this many sampled points further than
  /// 2 x inlier_distance below it per point on it is a slab through something else (car bodies, hedges,
  /// walls), not the ground (doc/defaults.md gives the values on real scans). A sensor that sees land
  /// well below its own ground (from a bridge or a ledge) gets no fit either.
  double max_below_ratio = 0.1;
  /// Seed of the sampling: the same cloud always gives the same fit.
  std::uint32_t seed = 1;
};

/// What the ground fit found, in the sensor frame.
struct GroundFit {
  /// Unit normal of the ground, pointing from the ground towards the sensor side (up).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  /// The sensor's distance above the plane [m].
  double height = 0.0;
  /// Angle between the normal and the sensor's z axis [degrees].
  double tilt_deg = 0.0;
  /// Sampled points within the range band that the fit looked at, and how many of them lie on the plane.
  std::size_t considered = 0;
  std::size_t inliers = 0;
  /// Root mean square distance of the inliers from the plane [m].
  double rms = 0.0;
  /// Sampled points more than 2 x inlier_distance below the plane.
  std::size_t below = 0;
  /// Why there is no fit; empty when there is one.
  std::string reason;
};

/// Gravity-aligning from the ground plane, for when no orientation is given or the odometry frame is not
/// gravity-aligned. Robust plane fit (RANSAC over a fixed-seed sample of the points in the range band,
/// with the tilt and height limits of `options`), refined by least squares over its inliers; then
/// L_R_sensor = gravityAlignmentFromUp(normal), so the result follows the same convention as
/// gravityAlignmentFromOrientation (not the minimal rotation taking the normal to +z, whose heading differs
/// from the sensor's by a yaw of second order in the tilt: 3.6 degrees at 20 degrees of roll and
/// pitch). Assumes the ground near the sensor is level: on a slope it levels to the slope.
///
/// Returns false, leaving *L_R_sensor unchanged and saying why in fit->reason, when the cloud has too
/// few ground points (empty, all NaN, indoors with little floor in view) or the options are invalid.
/// Either output may be null.
bool gravityAlignmentFromGround(const PointView& points, const GroundFitOptions& options, Eigen::Matrix3d* L_R_sensor,
                                GroundFit* fit);

}  // namespace scan_context_loop
