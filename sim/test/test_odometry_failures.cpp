#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_sim/odometry_failures.h"

namespace scan_context_loop {
namespace sim {
namespace {

/// 1 m steps along x, then a left turn every 100 m: a drive of `n` keyframes.
std::vector<Eigen::Isometry3d> drive(int n) {
  std::vector<Eigen::Isometry3d> poses = {Eigen::Isometry3d::Identity()};
  for (int k = 1; k < n; ++k) {
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation().x() = 1.0;
    if (k % 100 == 0) step.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    poses.push_back(poses.back() * step);
  }
  return poses;
}

double headingError(const Eigen::Isometry3d& truth, const Eigen::Isometry3d& odometry) {
  const Eigen::Matrix3d r = truth.linear().transpose() * odometry.linear();
  return std::atan2(r(1, 0), r(0, 0)) * 180.0 / M_PI;
}

TEST(OdometryFailures, NoneLeavesTheOdometryAlone) {
  const auto truth = drive(50);
  const auto out = withFailures(truth, OdometryFailures());
  ASSERT_EQ(out.size(), truth.size());
  for (std::size_t k = 0; k < out.size(); ++k) EXPECT_TRUE(out[k].isApprox(truth[k]));
}

TEST(OdometryFailures, TheHeadingRampGrowsOverTheSecondHalfOnly) {
  const auto truth = drive(1001);
  OdometryFailures f;
  f.heading_ramp_deg = 100.0;
  const auto out = withFailures(truth, f);
  EXPECT_NEAR(headingError(truth[500], out[500]), 0.0, 1e-6);
  EXPECT_NEAR(headingError(truth[750], out[750]), 50.0, 0.5);
  EXPECT_NEAR(headingError(truth[1000], out[1000]), 100.0, 0.5);
  // Far off by the end: a broken heading moves everything after it.
  EXPECT_GT((truth[1000].translation() - out[1000].translation()).norm(), 50.0);
}

TEST(OdometryFailures, JumpsAddUpToTheirCount) {
  const auto truth = drive(300);
  OdometryFailures f;
  f.heading_jumps = 3;
  f.heading_jump_deg = 20.0;
  const auto out = withFailures(truth, f);
  int steps = 0;
  for (std::size_t k = 1; k < out.size(); ++k) {
    const double e = headingError(truth[k - 1].inverse() * truth[k], out[k - 1].inverse() * out[k]);
    if (std::fabs(e) > 1.0) {
      ++steps;
      EXPECT_NEAR(std::fmod(std::fabs(e), 20.0), 0.0, 1e-6);
    }
  }
  EXPECT_GE(steps, 1);
  EXPECT_LE(steps, 3);
}

TEST(OdometryFailures, ASlipShortensItsStretchAndARestartStartsFromTheIdentity) {
  const auto truth = drive(300);
  OdometryFailures f;
  f.slip_start = 20.0;
  f.slip_length = 40.0;
  f.slip_scale = 0.5;
  auto out = withFailures(truth, f);
  EXPECT_NEAR((out[80].translation() - out[0].translation()).norm(), 60.0, 1e-6);  // 20 + 20 + 20
  f = OdometryFailures();
  f.restart_at = 150.0;
  out = withFailures(truth, f);
  EXPECT_TRUE(out[150].isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE((out[150].inverse() * out[200]).isApprox(truth[150].inverse() * truth[200]));
  EXPECT_FALSE(checkFailures(f).size());
  f.ramp_start = 1.5;
  EXPECT_FALSE(checkFailures(f).empty());
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
