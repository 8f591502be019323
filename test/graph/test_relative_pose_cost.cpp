// The pose graph's factor: the hand-written Jacobians against Ceres's automatic differentiation of the
// same residual, at random poses, measurements and information matrices.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "relative_pose_error.h"

namespace scan_context_loop {
namespace {

TEST(RelativePoseCost, ResidualAndJacobiansAreTheAutomaticOnes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> place(-50.0, 50.0), unit(-1.0, 1.0), positive(0.1, 10.0);
  const auto randomQuaternion = [&] {
    return Eigen::Quaterniond(Eigen::Vector4d(unit(rng), unit(rng), unit(rng), unit(rng))).normalized();
  };
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Isometry3d measured = Eigen::Isometry3d::Identity();
    measured.linear() = randomQuaternion().toRotationMatrix();
    measured.translation() << place(rng), place(rng), place(rng) / 10.0;
    Matrix6d sqrt_information = Matrix6d::Zero();
    for (int r = 0; r < 6; ++r) {
      sqrt_information(r, r) = positive(rng);
      for (int c = r + 1; c < 6; ++c) sqrt_information(r, c) = unit(rng);
    }
    Eigen::Vector3d p_a(place(rng), place(rng), place(rng)), p_b(place(rng), place(rng), place(rng));
    // On the manifold the quaternions are unit; a solver step leaves them a little off before they are
    // renormalised, and the Jacobians must hold there too.
    Eigen::Quaterniond q_a = randomQuaternion(), q_b = randomQuaternion();
    if (trial % 2 == 1) q_a.coeffs() *= 1.0 + 0.01 * unit(rng);
    const double* parameters[4] = {p_a.data(), q_a.coeffs().data(), p_b.data(), q_b.coeffs().data()};

    const RelativePoseCost analytic(measured, sqrt_information);
    const ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4> automatic(
        new RelativePoseError(measured, sqrt_information));
    double residual[2][6];
    double jacobian[2][4][6 * 4];
    double* blocks[2][4] = {{jacobian[0][0], jacobian[0][1], jacobian[0][2], jacobian[0][3]},
                            {jacobian[1][0], jacobian[1][1], jacobian[1][2], jacobian[1][3]}};
    ASSERT_TRUE(analytic.Evaluate(parameters, residual[0], blocks[0]));
    ASSERT_TRUE(automatic.Evaluate(parameters, residual[1], blocks[1]));
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(residual[0][i], residual[1][i], 1e-9) << "trial " << trial;
    const int sizes[4] = {3, 4, 3, 4};
    for (int b = 0; b < 4; ++b) {
      for (int k = 0; k < 6 * sizes[b]; ++k) {
        const double scale = std::max(1.0, std::fabs(jacobian[1][b][k]));
        EXPECT_NEAR(jacobian[0][b][k], jacobian[1][b][k], 1e-9 * scale) << "trial " << trial << " block " << b;
      }
    }
    // Some blocks asked for, others not.
    double* some[4] = {nullptr, jacobian[0][1], nullptr, nullptr};
    ASSERT_TRUE(analytic.Evaluate(parameters, residual[0], some));
    for (int k = 0; k < 24; ++k) {
      EXPECT_NEAR(jacobian[0][1][k], jacobian[1][1][k], 1e-9 * std::max(1.0, std::fabs(jacobian[1][1][k])));
    }
  }
}

}  // namespace
}  // namespace scan_context_loop
