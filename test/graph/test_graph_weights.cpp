// The pose graph's odometry weights against the simulator's drift model (sim/trajectory.h: slowly
// wandering biases, correlated over 300 m) along the real KITTI 00 trajectory (3.7 km, two thirds of it
// driven once), with a true loop at every revisit (the oracle's). An odometry whose heading errs only in
// its turns is corrected better by a graph told so (odometry_rotation_per_radian) than by the defaults,
// which spread the heading noise over every metre.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/sequence.h"
#include "scan_context_loop/eval/trajectory_error.h"
#include "scan_context_loop/graph/pose_graph.h"
#include "scan_context_sim/trajectory.h"
#include "../common/block_poses.h"

namespace scan_context_loop {
namespace {

using test::verifiedCovariance;

struct DriftDrive {
  std::vector<Eigen::Isometry3d> truth, odometry;
  std::vector<std::pair<std::size_t, std::size_t>> loops;  ///< (query, match): every revisit
};

/// KITTI 00's true LiDAR poses with a keyframe every 2 m, their odometry drifted by `drift` (seed), and as loops each
/// keyframe joined to the nearest keyframe within 5 m driven at least 50 m before it.
DriftDrive driftDrive(sim::DriftOptions drift, std::uint32_t seed) {
  DriftDrive d;
  const char* env = std::getenv("SCL_SHARED_DATA");
  std::vector<Eigen::Isometry3d> poses;
  std::string error;
  EXPECT_TRUE(eval::readTruePoses(std::string(env ? env : SCL_SHARED_DATA) + "/kitti/00", &poses, &error)) << error;
  std::vector<double> at;
  double travelled = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (i > 0) travelled += (poses[i].translation() - poses[i - 1].translation()).norm();
    if (!d.truth.empty() && travelled - at.back() < 2.0) continue;
    // KITTI's rotations are printed to a few digits; composed a thousand times they would stop being ones.
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(poses[i].linear()).normalized().toRotationMatrix();
    pose.translation() = poses[i].translation();
    d.truth.push_back(pose);
    at.push_back(travelled);
  }
  drift.seed = seed;
  d.odometry = sim::driftedOdometry(d.truth, drift);
  for (std::size_t q = 0; q < d.truth.size(); ++q) {
    long best = -1;
    double nearest = 5.0;
    for (std::size_t m = 0; m < q && at[q] - at[m] > 50.0; ++m) {
      const double gap = (d.truth[q].translation() - d.truth[m].translation()).norm();
      if (gap < nearest) {
        nearest = gap;
        best = static_cast<long>(m);
      }
    }
    if (best >= 0) d.loops.emplace_back(q, static_cast<std::size_t>(best));
  }
  return d;
}

/// A verified loop's covariance at the node's floors: 0.1 m, 0.5 deg.

double correctedAte(const DriftDrive& d, const PoseGraphConfig& config) {
  PoseGraph graph(config);
  for (const auto& pose : d.odometry) EXPECT_GE(graph.addKeyframe(pose), 0);
  for (const auto& [q, m] : d.loops) {
    EXPECT_TRUE(graph.addLoop(q, m, d.truth[q].inverse() * d.truth[m], verifiedCovariance()));
  }
  EXPECT_TRUE(graph.optimize().solved);
  return absoluteTrajectoryError(graph.poses(), d.truth).rmse;
}

TEST(PoseGraphWeights, HeadingNoiseInTheTurnsFitsAnOdometryThatErrsInItsTurns) {
  // The simulator's drift with its heading error from the turns alone (1 % of every turn, nothing per
  // metre) and a small translation error (0.2 % of distance).
  sim::DriftOptions turns;
  turns.translation_per_metre = 0.002;
  turns.yaw_per_metre = 0.0;
  turns.yaw_per_degree = 0.01;
  PoseGraphConfig matched;
  matched.odometry_rotation_floor = 0.0001;
  matched.odometry_rotation_per_metre = 0.0;
  matched.odometry_rotation_per_radian = 0.01;
  double defaults_sum = 0.0, matched_sum = 0.0;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    const DriftDrive d = driftDrive(turns, seed);
    ASSERT_GT(d.loops.size(), 200u) << "KITTI 00 revisits a third of its streets";
    const double odometry = absoluteTrajectoryError(d.odometry, d.truth).rmse;
    const double defaults = correctedAte(d, PoseGraphConfig()), turned = correctedAte(d, matched);
    std::printf("seed %u: odometry %.2f m; corrected with the defaults %.3f m, with the heading noise in the turns "
                "%.3f m (%zu loops)\n",
                seed, odometry, defaults, turned, d.loops.size());
    EXPECT_GT(odometry, 1.0) << "the odometry should drift";
    EXPECT_LT(turned, defaults) << "seed " << seed;
    defaults_sum += defaults;
    matched_sum += turned;
  }
  EXPECT_LT(matched_sum, 0.9 * defaults_sum);
}

TEST(PoseGraphWeights, TheRotationNoiseGrowsWithTheTurn) {
  PoseGraphConfig config;
  config.odometry_rotation_per_radian = 0.01;
  const Eigen::Isometry3d straight(Eigen::Translation3d(2.0, 0.0, 0.0));
  const Eigen::Isometry3d turn = straight * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  const Matrix6d a = odometryCovariance(straight, config), b = odometryCovariance(turn, config);
  EXPECT_NEAR(std::sqrt(b(5, 5)) - std::sqrt(a(5, 5)), 0.01 * M_PI / 2, 1e-9);
  EXPECT_NEAR(std::sqrt(b(3, 3)) - std::sqrt(a(3, 3)), 0.01 * M_PI / 2, 1e-9);
  EXPECT_DOUBLE_EQ(b(0, 0), a(0, 0)) << "the translation's noise does not depend on the turn";
}

}  // namespace
}  // namespace scan_context_loop
