#include "scan_context_loop/eval/trajectory_error.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace scan_context_loop {

namespace {

/// RMSE, mean and max of the distances between alignment x estimate and truth, column by column.
TrajectoryError errorOf(const Eigen::Matrix3Xd& estimate, const Eigen::Matrix3Xd& truth,
                        const Eigen::Isometry3d& alignment) {
  TrajectoryError error;
  error.alignment = alignment;
  double sum_squares = 0.0, sum = 0.0;
  for (Eigen::Index i = 0; i < estimate.cols(); ++i) {
    const double e = (alignment * Eigen::Vector3d(estimate.col(i)) - truth.col(i)).norm();
    sum_squares += e * e;
    sum += e;
    error.max = std::max(error.max, e);
  }
  error.poses = static_cast<std::size_t>(estimate.cols());
  error.rmse = std::sqrt(sum_squares / error.poses);
  error.mean = sum / error.poses;
  return error;
}

void positions(const std::vector<Eigen::Isometry3d>& poses, Eigen::Matrix3Xd* out) {
  out->resize(3, static_cast<Eigen::Index>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i) out->col(static_cast<Eigen::Index>(i)) = poses[i].translation();
}

}  // namespace

TrajectoryError absoluteTrajectoryError(const std::vector<Eigen::Isometry3d>& estimate,
                                        const std::vector<Eigen::Isometry3d>& truth) {
  if (estimate.size() != truth.size() || estimate.size() < 3) return TrajectoryError();
  Eigen::Matrix3Xd from, to;
  positions(estimate, &from);
  positions(truth, &to);
  Eigen::Isometry3d alignment;
  alignment.matrix() = Eigen::umeyama(from, to, false);
  return errorOf(from, to, alignment);
}

PartError partError(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& truth,
                    const Eigen::Isometry3d& alignment, const std::vector<bool>& flags, bool part) {
  PartError p;
  double sum = 0.0;
  for (std::size_t i = 0; i < estimate.size() && i < truth.size() && i < flags.size(); ++i) {
    if (flags[i] != part) continue;
    sum += (alignment * estimate[i].translation() - truth[i].translation()).squaredNorm();
    ++p.keyframes;
  }
  p.rmse = p.keyframes > 0 ? std::sqrt(sum / static_cast<double>(p.keyframes)) : 0.0;
  return p;
}

TrajectoryError positionError(const std::vector<Eigen::Isometry3d>& estimate,
                              const std::vector<Eigen::Isometry3d>& truth) {
  if (estimate.size() != truth.size() || estimate.empty()) return TrajectoryError();
  Eigen::Matrix3Xd from, to;
  positions(estimate, &from);
  positions(truth, &to);
  return errorOf(from, to, Eigen::Isometry3d::Identity());
}

}  // namespace scan_context_loop
