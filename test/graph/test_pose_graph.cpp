// The reference backend on a simulated multi-lap drive with drifting odometry: correct loops bring the
// trajectory back to the truth; a false loop neither pulls it when its covariance says it is vague nor,
// under the robust loss, when it claims to be sure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "scan_context_loop/graph/pose_graph.h"
#include "scan_context_loop/eval/trajectory_error.h"
#include "../common/planar.h"
#include "../common/block_poses.h"

namespace scan_context_loop {
namespace {

using test::kPerLap;
using test::verifiedCovariance;

using test::planar;

constexpr std::size_t kLaps = 3;

/// The true poses: the block's perimeter counter-clockwise, each lap 0.8 m further in (another lane).
std::vector<Eigen::Isometry3d> blockTruth() {
  std::vector<Eigen::Isometry3d> truth;
  for (std::size_t lap = 0; lap < kLaps; ++lap) {
    const double in = 0.8 * lap, w = 120.0 - 2 * in, h = 60.0 - 2 * in;
    for (std::size_t k = 0; k < kPerLap; ++k) {
      double s = (w + h) * 2.0 * k / kPerLap;  // arc length along this lap's rectangle
      if (s < w)
        truth.push_back(planar(in + s, in, 0.0));
      else if ((s -= w) < h)
        truth.push_back(planar(in + w, in + s, M_PI / 2));
      else if ((s -= h) < w)
        truth.push_back(planar(in + w - s, in + h, M_PI));
      else
        truth.push_back(planar(in, in + h - (s - w), -M_PI / 2));
    }
  }
  return truth;
}

/// Odometry from the true steps with a yaw bias (10 deg a lap), 1% scale error and noise.
std::vector<Eigen::Isometry3d> drifting(const std::vector<Eigen::Isometry3d>& truth, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> metres(0.0, 0.01), radians(0.0, 0.0005);
  std::vector<Eigen::Isometry3d> odometry{truth[0]};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Eigen::Isometry3d step = truth[i - 1].inverse() * truth[i];
    step.translation() = 1.01 * step.translation() + Eigen::Vector3d(metres(rng), metres(rng), metres(rng));
    step.linear() = step.linear() * (Eigen::AngleAxisd(0.001 + radians(rng), Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(radians(rng), Eigen::Vector3d::UnitX()) *
                                     Eigen::AngleAxisd(radians(rng), Eigen::Vector3d::UnitY()))
                                        .toRotationMatrix();
    odometry.push_back(odometry.back() * step);
  }
  return odometry;
}

/// A verified loop's covariance as the node reports one at its floors: 0.1 m, 0.5 deg.

struct Drive {
  std::vector<Eigen::Isometry3d> truth = blockTruth();
  std::vector<Eigen::Isometry3d> odometry = drifting(truth, 7);
};

/// A graph of the drive's odometry with a true loop (measured with 3 cm / 0.1 deg noise) from every
/// third keyframe of laps 2 and 3 to the same place one lap earlier.
void build(const Drive& drive, PoseGraph* graph) {
  std::mt19937 rng(11);
  std::normal_distribution<double> metres(0.0, 0.03), radians(0.0, 0.1 * M_PI / 180.0);
  for (const auto& pose : drive.odometry) ASSERT_GE(graph->addKeyframe(pose), 0);
  for (std::size_t q = kPerLap; q < drive.truth.size(); q += 3) {
    const std::size_t m = q - kPerLap;
    const Eigen::Isometry3d measured =
        drive.truth[q].inverse() * drive.truth[m] * planar(metres(rng), metres(rng), radians(rng));
    ASSERT_TRUE(graph->addLoop(q, m, measured, verifiedCovariance()));
  }
}

double ate(const PoseGraph& graph, const Drive& drive) {
  return absoluteTrajectoryError(graph.poses(), drive.truth).rmse;
}

TEST(PoseGraph, CorrectLoopsBringADriftedTrajectoryBackToTheTruth) {
  const Drive drive;
  PoseGraph graph;
  build(drive, &graph);
  const double before = absoluteTrajectoryError(drive.odometry, drive.truth).rmse;
  EXPECT_NEAR(ate(graph, drive), before, 1e-9) << "the estimates start at the odometry";
  const PoseGraphResult result = graph.optimize();
  ASSERT_TRUE(result.solved) << result.message;
  const TrajectoryError after = absoluteTrajectoryError(graph.poses(), drive.truth);
  std::printf("odometry ATE %.2f m; corrected %.3f m (max %.3f m), %d iterations, %.3f s\n", before, after.rmse,
              after.max, result.iterations, result.seconds);
  EXPECT_GT(before, 5.0) << "the simulated odometry should drift";
  EXPECT_LT(after.rmse, 0.2 * before);
  // What remains is mostly the odometry's 1% scale error, which loops between laps cannot see: every
  // lap is equally too large, and alignment without scale leaves ~0.5 m on a 120 m block.
  EXPECT_LT(after.rmse, 1.0);
  EXPECT_TRUE(graph.pose(0).isApprox(drive.odometry[0], 1e-12)) << "the first keyframe is the gauge";
}

TEST(PoseGraph, AFalseLoopWithALargeCovarianceDoesNotPull) {
  // A descriptor-only loop between places 60 m apart, reported with the node's prior covariance
  // (10 m standard deviation in position): the corrected trajectory is the same with it or without.
  const Drive drive;
  PoseGraph clean, with_false;
  build(drive, &clean);
  build(drive, &with_false);
  Eigen::Matrix<double, 6, 1> prior;
  prior << 100.0, 100.0, 100.0, 0.01, 0.01, std::pow(M_PI / 60, 2);
  ASSERT_TRUE(with_false.addLoop(2 * kPerLap + 20, 110, Eigen::Isometry3d::Identity(), prior.asDiagonal()));
  ASSERT_TRUE(clean.optimize().solved);
  ASSERT_TRUE(with_false.optimize().solved);
  const double a = ate(clean, drive), b = ate(with_false, drive);
  std::printf("corrected ATE without the false loop %.3f m, with it %.3f m\n", a, b);
  EXPECT_LT(std::fabs(b - a), 0.05);
}

TEST(PoseGraph, TheRobustLossKeepsAConfidentFalseLoopFromBendingTheMap) {
  // The same false loop claiming verified accuracy (0.1 m): plain least squares bends the map towards
  // it; the Cauchy loss leaves the map close to the clean solution.
  const Drive drive;
  PoseGraphConfig plain_config;
  plain_config.loop_robust_scale = 0.0;
  PoseGraph clean, robust, plain(plain_config);
  for (PoseGraph* g : {&clean, &robust, &plain}) build(drive, g);
  for (PoseGraph* g : {&robust, &plain}) {
    ASSERT_TRUE(g->addLoop(2 * kPerLap + 20, 110, Eigen::Isometry3d::Identity(), verifiedCovariance()));
  }
  for (PoseGraph* g : {&clean, &robust, &plain}) ASSERT_TRUE(g->optimize().solved);
  const double odometry = absoluteTrajectoryError(drive.odometry, drive.truth).rmse;
  const double c = ate(clean, drive), r = ate(robust, drive), p = ate(plain, drive);
  std::printf("ATE: odometry %.2f m, clean %.3f m, false loop with the robust loss %.3f m, without %.2f m\n", odometry,
              c, r, p);
  EXPECT_GT(p, 5.0 * c) << "plain least squares should be bent by the false loop";
  EXPECT_LT(r, 0.2 * odometry);
  EXPECT_LT(r, c + 0.2);
}

TEST(PoseGraph, KeyframesAddedAfterACorrectionStartFromIt) {
  const Drive drive;
  PoseGraph graph;
  build(drive, &graph);
  ASSERT_TRUE(graph.optimize().solved);
  const Eigen::Isometry3d step = planar(2.0, 0.0, 0.05);
  const Eigen::Isometry3d next_odometry = drive.odometry.back() * step;
  ASSERT_EQ(graph.addKeyframe(next_odometry), static_cast<long>(drive.odometry.size()));
  EXPECT_TRUE(graph.pose(graph.size() - 1).isApprox(graph.pose(graph.size() - 2) * step, 1e-9));
  EXPECT_TRUE((graph.correction() * next_odometry).isApprox(graph.pose(graph.size() - 1), 1e-9));
}

TEST(PoseGraph, FixedKeyframesStayPutAndHoldTheChainThroughItsLoops) {
  // A prior map (lap 1 at its true poses, fixed) and a later session (laps 2 and 3) whose drifting
  // odometry starts in a frame of its own, 30 m and 100 deg off: its loops into the prior bring it into
  // the prior's frame and onto the truth there, the prior keyframes untouched.
  const Drive drive;
  const Eigen::Isometry3d elsewhere = planar(30.0, -12.0, 100.0 * M_PI / 180.0);
  PoseGraph graph;
  for (std::size_t i = 0; i < kPerLap; ++i) ASSERT_EQ(graph.addFixedKeyframe(drive.truth[i]), static_cast<long>(i));
  std::vector<Eigen::Isometry3d> session_truth, session_odometry;
  for (std::size_t i = kPerLap; i < drive.truth.size(); ++i) {
    session_truth.push_back(drive.truth[i]);
    session_odometry.push_back(elsewhere * drive.odometry[kPerLap].inverse() * drive.odometry[i]);
    ASSERT_EQ(graph.addKeyframe(session_odometry.back()), static_cast<long>(i));
  }
  EXPECT_TRUE(graph.fixed(0) && graph.fixed(kPerLap - 1));
  EXPECT_FALSE(graph.fixed(kPerLap) || graph.fixed(graph.size() - 1));
  std::string error;
  EXPECT_FALSE(graph.addLoop(5, 3, Eigen::Isometry3d::Identity(), verifiedCovariance(), &error));
  EXPECT_EQ(error, "a loop between two fixed keyframes");
  // Before any loop into the prior the chain's first keyframe is the gauge, as without fixed keyframes.
  EXPECT_TRUE(graph.correction().isApprox(Eigen::Isometry3d::Identity(), 1e-9));

  std::mt19937 rng(13);
  std::normal_distribution<double> metres(0.0, 0.03), radians(0.0, 0.1 * M_PI / 180.0);
  std::size_t into_prior = 0;
  for (std::size_t q = kPerLap + 1; q < drive.truth.size(); q += 3) {
    const std::size_t m = q % kPerLap;  // the same place in lap 1, the prior's
    const Eigen::Isometry3d measured =
        drive.truth[q].inverse() * drive.truth[m] * planar(metres(rng), metres(rng), radians(rng));
    ASSERT_TRUE(graph.addLoop(q, m, measured, verifiedCovariance(), &error)) << error;
    ++into_prior;
    if (into_prior == 1) {
      // The first loop into the prior moved the chain into its frame: that loop holds exactly.
      EXPECT_TRUE((graph.pose(q).inverse() * graph.pose(m)).isApprox(measured, 1e-9));
    }
    if (q >= 2 * kPerLap) {  // and to lap 2, the session's own
      ASSERT_TRUE(
          graph.addLoop(q, q - kPerLap, drive.truth[q].inverse() * drive.truth[q - kPerLap], verifiedCovariance()));
    }
  }
  const PoseGraphResult result = graph.optimize();
  ASSERT_TRUE(result.solved) << result.message;
  for (std::size_t i = 0; i < kPerLap; ++i) {
    EXPECT_EQ(graph.pose(i).translation(), drive.truth[i].translation()) << "prior keyframe " << i;
    EXPECT_TRUE(graph.pose(i).linear().isApprox(drive.truth[i].linear(), 1e-12)) << "prior keyframe " << i;
  }
  // The session lies on the truth in the prior's frame, with no alignment.
  double worst = 0.0;
  std::vector<Eigen::Isometry3d> corrected;
  for (std::size_t i = kPerLap; i < graph.size(); ++i) {
    corrected.push_back(graph.pose(i));
    worst = std::max(worst, (graph.pose(i).translation() - drive.truth[i].translation()).norm());
  }
  const double odometry = absoluteTrajectoryError(session_odometry, session_truth).rmse;
  const double after = absoluteTrajectoryError(corrected, session_truth).rmse;
  std::printf("session in a fixed prior: odometry ATE %.2f m, corrected %.3f m, %.3f m at most off the truth\n",
              odometry, after, worst);
  EXPECT_GT(odometry, 2.0) << "the simulated odometry should drift";
  EXPECT_LT(after, 0.1 * odometry);
  EXPECT_LT(worst, 0.5);
  EXPECT_FALSE(graph.pose(kPerLap).isApprox(session_odometry.front(), 1e-3)) << "the chain's start moved too";
}

TEST(PoseGraph, UnusableInputIsRefusedAndNamed) {
  PoseGraph graph;
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 2.0;
  EXPECT_EQ(graph.addKeyframe(scaled), -1);
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation().x() = std::nan("");
  EXPECT_EQ(graph.addKeyframe(nan), -1);
  // Huge but finite: the step from the last keyframe would overflow its covariance.
  EXPECT_EQ(graph.addKeyframe(planar(1e300, 0.0, 0.0)), -1);
  EXPECT_EQ(graph.addFixedKeyframe(planar(0.0, -2e7, 0.0)), -1);
  EXPECT_EQ(graph.size(), 0u);
  ASSERT_EQ(graph.addKeyframe(Eigen::Isometry3d::Identity()), 0);
  ASSERT_EQ(graph.addKeyframe(planar(2.0, 0.0, 0.0)), 1);
  std::string error;
  EXPECT_FALSE(graph.addLoop(1, 5, Eigen::Isometry3d::Identity(), verifiedCovariance(), &error));
  EXPECT_EQ(error, "unknown keyframe");
  EXPECT_FALSE(graph.addLoop(1, 1, Eigen::Isometry3d::Identity(), verifiedCovariance(), &error));
  EXPECT_FALSE(graph.addLoop(1, 0, scaled, verifiedCovariance(), &error));
  Matrix6d not_definite = verifiedCovariance();
  not_definite(2, 2) = -1.0;
  EXPECT_FALSE(graph.addLoop(1, 0, Eigen::Isometry3d::Identity(), not_definite, &error));
  EXPECT_NE(error.find("positive definite"), std::string::npos) << error;
  EXPECT_EQ(graph.loops(), 0u);
  EXPECT_TRUE(graph.optimize().solved);
  // After keyframes, too: nothing is added, and the graph still solves to its odometry.
  EXPECT_EQ(graph.addKeyframe(planar(1e300, 0.0, 0.0)), -1);
  EXPECT_EQ(graph.addKeyframe(planar(5e6, 5e6, 0.0)), 2) << "far, but within kMaxCoordinate";
  EXPECT_EQ(graph.size(), 3u);
  const PoseGraphResult result = graph.optimize();
  EXPECT_TRUE(result.solved) << result.message;
  EXPECT_TRUE(graph.pose(1).translation().isApprox(Eigen::Vector3d(2.0, 0.0, 0.0), 1e-6));
}

}  // namespace
}  // namespace scan_context_loop
