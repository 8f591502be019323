#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "principal_axes.h"

namespace scan_context_loop {
namespace {

/// Covariances of points spread along random axes with the given standard deviations [m].
Eigen::Matrix3d spread(std::mt19937* rng, double s0, double s1, double s2) {
  std::normal_distribution<double> normal;
  const Eigen::Matrix3d axes =
      Eigen::Quaterniond(normal(*rng), normal(*rng), normal(*rng), normal(*rng)).normalized().toRotationMatrix();
  return axes * Eigen::Vector3d(s0 * s0, s1 * s1, s2 * s2).asDiagonal() * axes.transpose();
}

void put(const Eigen::Matrix3d& c, std::size_t i, SymmetricBlock* block) {
  block->xx[i] = static_cast<float>(c(0, 0));
  block->xy[i] = static_cast<float>(c(0, 1));
  block->xz[i] = static_cast<float>(c(0, 2));
  block->yy[i] = static_cast<float>(c(1, 1));
  block->yz[i] = static_cast<float>(c(1, 2));
  block->zz[i] = static_cast<float>(c(2, 2));
}

/// Solves `matrices` a block at a time.
std::vector<AxesBlock> solve(const std::vector<Eigen::Matrix3d>& matrices) {
  std::vector<AxesBlock> out((matrices.size() + kAxesBlock - 1) / kAxesBlock);
  SymmetricBlock block;
  for (std::size_t b = 0; b < out.size(); ++b) {
    const std::size_t n = std::min(kAxesBlock, matrices.size() - b * kAxesBlock);
    for (std::size_t i = 0; i < n; ++i) put(matrices[b * kAxesBlock + i], i, &block);
    principalAxes(block, n, &out[b]);
  }
  return out;
}

TEST(PrincipalAxes, AgreesWithEigensSolverOnVoxelSpreads) {
  // Float against double: eigenvalues within 3e-4 of the largest (near-equal pairs are the worst),
  // normals within 5e-4 rad (an int8 normal resolves 8e-3 rad), the major axis's z within 1e-4.
  constexpr double kValue = 3e-4, kAngle = 5e-4, kMajor = 1e-4;
  // Planes (a few cm thick), lines, scatter and everything between, as 1 m voxels hold them.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> log_sd(std::log(0.003), std::log(0.4));
  std::vector<Eigen::Matrix3d> matrices;
  for (int i = 0; i < 3000; ++i) {
    matrices.push_back(spread(&rng, std::exp(log_sd(rng)), std::exp(log_sd(rng)), std::exp(log_sd(rng))));
  }
  const std::vector<AxesBlock> axes = solve(matrices);
  int normals_checked = 0;
  double worst_angle = 0.0, worst_value = 0.0, worst_major = 0.0;
  for (std::size_t k = 0; k < matrices.size(); ++k) {
    const AxesBlock& a = axes[k / kAxesBlock];
    const std::size_t i = k % kAxesBlock;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(matrices[k]);
    const Eigen::Vector3d l = eig.eigenvalues();
    for (int j = 0; j < 3; ++j) {
      const double value = j == 0 ? a.l0[i] : j == 1 ? a.l1[i] : a.l2[i];
      worst_value = std::max(worst_value, std::fabs(value - l(j)) / l(2));
      EXPECT_NEAR(value, l(j), kValue * l(2)) << k << " eigenvalue " << j;
    }
    const Eigen::Vector3d normal(a.nx[i], a.ny[i], a.nz[i]);
    EXPECT_NEAR(normal.norm(), 1.0, 1e-5) << k;
    // Where the smallest eigenvalue stands apart (by a percent of the largest), the normal is Eigen's up
    // to sign.
    if (l(1) - l(0) > 0.01 * l(2)) {
      ++normals_checked;
      const double angle = std::acos(std::min(1.0, std::fabs(normal.normalized().dot(eig.eigenvectors().col(0)))));
      worst_angle = std::max(worst_angle, angle);
      EXPECT_LT(angle, kAngle) << k;
    }
    if (l(2) - l(1) > 0.01 * l(2)) {
      worst_major = std::max(worst_major, std::fabs(std::fabs(a.major_z[i]) - std::fabs(eig.eigenvectors()(2, 2))));
      EXPECT_NEAR(std::fabs(a.major_z[i]), std::fabs(eig.eigenvectors()(2, 2)), kMajor) << k;
    }
  }
  EXPECT_GT(normals_checked, 2000);
  std::printf("worst: eigenvalue %.2e of the largest, normal %.2e rad, major axis z %.2e\n", worst_value, worst_angle,
              worst_major);
}

TEST(PrincipalAxes, DegenerateSpreadsGiveUnitAxes) {
  std::mt19937 rng(3);
  std::vector<Eigen::Matrix3d> matrices = {
      Eigen::Matrix3d::Zero(),                        // one point, many times
      0.04 * Eigen::Matrix3d::Identity(),             // isotropic
      spread(&rng, 0.0, 0.0, 0.3),                    // an exact line
      spread(&rng, 0.0, 0.2, 0.2),                    // an exact plane, round within it
      Eigen::Vector3d(0.0, 0.0, 0.09).asDiagonal(),   // a vertical line along the axes
      Eigen::Vector3d(0.01, 0.01, 0.0).asDiagonal(),  // a horizontal plane along the axes
  };
  const AxesBlock a = solve(matrices).front();
  for (std::size_t i = 0; i < matrices.size(); ++i) {
    const Eigen::Vector3d normal(a.nx[i], a.ny[i], a.nz[i]);
    ASSERT_TRUE(normal.allFinite()) << i;
    EXPECT_NEAR(normal.norm(), 1.0, 1e-5) << i;
    EXPECT_TRUE(std::isfinite(a.major_z[i])) << i;
    EXPECT_LE(a.l0[i], a.l1[i] + 1e-7f) << i;
    EXPECT_LE(a.l1[i], a.l2[i] + 1e-7f) << i;
    // The normal spans the smallest spread: its variance along it is the smallest eigenvalue.
    EXPECT_NEAR(normal.dot(matrices[i] * normal), a.l0[i], 1e-5) << i;
  }
  EXPECT_NEAR(std::fabs(a.major_z[4]), 1.0, 1e-5);  // the vertical line's direction
  EXPECT_NEAR(std::fabs(a.nz[5]), 1.0, 1e-5);       // the horizontal plane's normal
}

}  // namespace
}  // namespace scan_context_loop
