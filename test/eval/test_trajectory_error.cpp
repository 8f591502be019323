#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/trajectory_error.h"

namespace scan_context_loop {
namespace {

std::vector<Eigen::Isometry3d> circle(std::size_t n, double radius) {
  std::vector<Eigen::Isometry3d> poses;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    poses.push_back(Eigen::Translation3d(radius * std::cos(a), radius * std::sin(a), 0.1 * i) *
                    Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()));
  }
  return poses;
}

TEST(TrajectoryError, ARigidlyMovedCopyHasNoError) {
  const auto truth = circle(50, 20.0);
  const Eigen::Isometry3d motion =
      Eigen::Translation3d(5.0, -3.0, 1.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  std::vector<Eigen::Isometry3d> moved;
  for (const auto& p : truth) moved.push_back(motion * p);
  const TrajectoryError e = absoluteTrajectoryError(moved, truth);
  EXPECT_EQ(e.poses, 50u);
  EXPECT_LT(e.rmse, 1e-9);
  EXPECT_LT(e.max, 1e-9);
  EXPECT_TRUE(e.alignment.isApprox(motion.inverse(), 1e-9));
}

TEST(TrajectoryError, KnownOffsetsGiveTheirRmseAndMax) {
  // Every other pose 1 m off along z, alternately up and down: the best alignment cannot remove it.
  const auto truth = circle(40, 20.0);
  std::vector<Eigen::Isometry3d> estimate = truth;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    estimate[i].translation().z() += (i % 2 == 0) ? 1.0 : -1.0;
  }
  const TrajectoryError e = absoluteTrajectoryError(estimate, truth);
  EXPECT_NEAR(e.rmse, 1.0, 0.02);
  EXPECT_NEAR(e.max, 1.0, 0.05);
}

TEST(TrajectoryError, MismatchedOrTooShortIsRefused) {
  const auto truth = circle(10, 5.0);
  EXPECT_EQ(absoluteTrajectoryError(std::vector<Eigen::Isometry3d>(truth.begin(), truth.begin() + 9), truth).poses, 0u);
  EXPECT_EQ(absoluteTrajectoryError({truth[0], truth[1]}, {truth[0], truth[1]}).poses, 0u);
}

}  // namespace
}  // namespace scan_context_loop
