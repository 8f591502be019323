#include "scan_context_loop/eval/trajectory_error.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace scan_context_loop {

TrajectoryError absoluteTrajectoryError(const std::vector<Eigen::Isometry3d>& estimate,
                                        const std::vector<Eigen::Isometry3d>& truth) {
  TrajectoryError error;
  if (estimate.size() != truth.size() || estimate.size() < 3) return error;
  Eigen::Matrix3Xd from(3, estimate.size()), to(3, truth.size());
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    from.col(i) = estimate[i].translation();
    to.col(i) = truth[i].translation();
  }
  error.alignment.matrix() = Eigen::umeyama(from, to, false);
  double sum_squares = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double e = (error.alignment * from.col(i) - to.col(i)).norm();
    sum_squares += e * e;
    sum += e;
    error.max = std::max(error.max, e);
  }
  error.poses = estimate.size();
  error.rmse = std::sqrt(sum_squares / error.poses);
  error.mean = sum / error.poses;
  return error;
}

}  // namespace scan_context_loop
