// Absolute trajectory error: how far a keyframe trajectory lies from the truth once the two are
// aligned by the rigid motion that fits them best (Umeyama, without scale).
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {

struct TrajectoryError {
  std::size_t poses = 0;
  double rmse = 0.0;  ///< root mean square of the position errors after alignment [m]
  double mean = 0.0;
  double max = 0.0;
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  ///< truth frame <- estimate frame
};

/// The RMSE over some of the keyframes, with an alignment found on all of them.
struct PartError {
  double rmse = 0.0;
  std::size_t keyframes = 0;
};

/// The error of `estimate` after `alignment` (a TrajectoryError's, found on every pose) over the poses
/// whose flag equals `part`: where the error lies, e.g. on the revisited part of a drive or the rest.
PartError partError(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& truth,
                    const Eigen::Isometry3d& alignment, const std::vector<bool>& flags, bool part);

/// The error of `estimate` against `truth`, pose by pose (same length, at least 3; positions only).
/// Returns poses = 0 when the lengths differ or there are too few.
TrajectoryError absoluteTrajectoryError(const std::vector<Eigen::Isometry3d>& estimate,
                                        const std::vector<Eigen::Isometry3d>& truth);

/// The error of `estimate` against `truth` as they are, in one frame (no alignment; same length, at least
/// one pose): what a map whose frame is fixed (a team's anchor) is off by. poses = 0 as above.
TrajectoryError positionError(const std::vector<Eigen::Isometry3d>& estimate,
                              const std::vector<Eigen::Isometry3d>& truth);

}  // namespace scan_context_loop
