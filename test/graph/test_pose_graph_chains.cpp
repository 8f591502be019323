// The pose graph with several chains (one per robot's odometry frame): three robots driving the same
// block from different starts, each with its own origin and drifting odometry, joined by loops between
// them; a group joined through another chain; a loop inside a chain no loop joined yet; chain 0 as it
// is without chains.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "scan_context_loop/graph/pose_graph.h"

#include "../common/block_poses.h"

namespace scan_context_loop {
namespace {

using test::kPerLap;
using test::verifiedCovariance;

using test::planar;
Eigen::Isometry3d blockPoseOf(std::size_t k, double in) { return test::blockPose(k, in, kPerLap); }

/// A robot driving `keyframes` keyframes along its lane from keyframe `start` of the lap, truth in the world frame; its
/// odometry starts at the identity (its own origin) and drifts: a yaw bias (`yaw_bias` a step) and noise.
struct Robot {
  std::vector<Eigen::Isometry3d> truth, odometry;
  std::size_t start = 0;
  double in = 0.0;
  /// The true T_world<-odom: the odometry's origin is the robot's first true pose.
  Eigen::Isometry3d origin() const { return truth.front(); }
};

Robot drive(std::size_t start, double in, double yaw_bias, std::uint32_t seed, std::size_t keyframes = kPerLap) {
  Robot r;
  r.start = start;
  r.in = in;
  std::mt19937 rng(seed);
  std::normal_distribution<double> metres(0.0, 0.01), radians(0.0, 0.0005);
  for (std::size_t k = 0; k < keyframes; ++k) r.truth.push_back(blockPoseOf(start + k, in));
  r.odometry.push_back(Eigen::Isometry3d::Identity());
  for (std::size_t k = 1; k < r.truth.size(); ++k) {
    Eigen::Isometry3d step = r.truth[k - 1].inverse() * r.truth[k];
    step.translation() += Eigen::Vector3d(metres(rng), metres(rng), metres(rng));
    step.linear() = step.linear() * (Eigen::AngleAxisd(yaw_bias + radians(rng), Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(radians(rng), Eigen::Vector3d::UnitX()))
                                        .toRotationMatrix();
    r.odometry.push_back(r.odometry.back() * step);
  }
  return r;
}

/// Each robot drives a lap and a fifth (it passes its start again).
constexpr std::size_t kDriven = kPerLap + kPerLap / 5;

/// Three robots, keyframes added interleaved as they would arrive, robot r on chain r.
struct Team {
  std::vector<Robot> robots{drive(0, 0.0, 0.0005, 7, kDriven), drive(50, 0.8, -0.0007, 8, kDriven),
                            drive(120, 1.6, 0.0009, 9, kDriven)};
  std::vector<std::vector<std::size_t>> index{3};  // graph index of robot r's keyframe k

  void addKeyframes(PoseGraph* graph) {
    for (std::size_t k = 0; k < kDriven; ++k) {
      for (std::size_t r = 0; r < robots.size(); ++r) {
        const long i = graph->addKeyframe(robots[r].odometry[k], r);
        ASSERT_GE(i, 0);
        index[r].push_back(static_cast<std::size_t>(i));
      }
    }
  }
  /// The keyframe of robot `r` at the block position of robot q's keyframe k (the same place, another lane).
  std::size_t samePlace(std::size_t q, std::size_t k, std::size_t r) const {
    return (robots[q].start + k + kPerLap - robots[r].start) % kPerLap;
  }
  /// A true loop from robot q's keyframe k to robot r's at the same place, measured with 3 cm / 0.1 deg noise.
  bool addLoop(PoseGraph* graph, std::size_t q, std::size_t k, std::size_t r, std::mt19937* rng) const {
    std::normal_distribution<double> metres(0.0, 0.03), radians(0.0, 0.1 * M_PI / 180.0);
    const std::size_t m = samePlace(q, k, r);
    const Eigen::Isometry3d measured =
        robots[q].truth[k].inverse() * robots[r].truth[m] * planar(metres(*rng), metres(*rng), radians(*rng));
    std::string error;
    const bool added = graph->addLoop(index[q][k], index[r][m], measured, verifiedCovariance(), &error);
    EXPECT_TRUE(added) << error;
    return added;
  }
  /// Each robot's own loops where it passes its start again (every 2nd keyframe past the lap), as its
  /// own loop-closure node would find them.
  void addOwnLoops(PoseGraph* graph, std::mt19937* rng) const {
    std::normal_distribution<double> metres(0.0, 0.03), radians(0.0, 0.1 * M_PI / 180.0);
    for (std::size_t r = 0; r < robots.size(); ++r) {
      for (std::size_t k = kPerLap; k < kDriven; k += 2) {
        const Eigen::Isometry3d measured = robots[r].truth[k].inverse() * robots[r].truth[k - kPerLap] *
                                           planar(metres(*rng), metres(*rng), radians(*rng));
        EXPECT_TRUE(graph->addLoop(index[r][k], index[r][k - kPerLap], measured, verifiedCovariance()));
      }
    }
  }
  /// The true T_map<-odom_r, map = robot 0's odometry frame.
  Eigen::Isometry3d trueFrame(std::size_t r) const { return robots[0].origin().inverse() * robots[r].origin(); }
};

double angleOf(const Eigen::Isometry3d& t) { return Eigen::AngleAxisd(t.linear()).angle(); }

TEST(PoseGraphChains, InterRobotLoopsRecoverEachRobotsFrame) {
  Team team;
  PoseGraph graph;
  team.addKeyframes(&graph);
  EXPECT_EQ(graph.chains(), 3u);
  for (std::size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(graph.chainKeyframes(r), team.index[r]);
    EXPECT_EQ(graph.chainOf(team.index[r][5]), static_cast<long>(r));
    EXPECT_TRUE(graph.frame(r).isApprox(Eigen::Isometry3d::Identity(), 1e-12)) << "unjoined: its own origin";
  }
  EXPECT_TRUE(graph.joined(0));
  EXPECT_FALSE(graph.joined(1) || graph.joined(2));
  EXPECT_EQ(graph.held(), (std::vector<std::size_t>{team.index[0][0], team.index[1][0], team.index[2][0]}));
  // Each robot's odometry factors link its own keyframes only.
  for (const PoseGraphFactor& f : graph.factors()) EXPECT_EQ(graph.chainOf(f.a), graph.chainOf(f.b));

  std::mt19937 rng(21);
  // Robot 1 -> robot 0 every 4th keyframe; the first of these joins robot 1 and holds exactly.
  for (std::size_t k = 0; k < kPerLap; k += 4) {
    ASSERT_TRUE(team.addLoop(&graph, 1, k, 0, &rng));
    if (k == 0) {
      const std::size_t m = team.samePlace(1, 0, 0);
      EXPECT_TRUE(graph.joined(1));
      EXPECT_FALSE(graph.joined(2));
      const Eigen::Isometry3d measured = graph.factors().back().measurement;
      EXPECT_TRUE((graph.pose(team.index[1][0]).inverse() * graph.pose(team.index[0][m])).isApprox(measured, 1e-9));
      EXPECT_EQ(graph.held(), (std::vector<std::size_t>{team.index[0][0], team.index[2][0]}));
    }
  }
  // Robot 2 -> robots 0 and 1 every 6th keyframe (robot 2 is a query as often as a match).
  for (std::size_t k = 3; k < kPerLap; k += 6) {
    ASSERT_TRUE(team.addLoop(&graph, 2, k, k % 4 == 1 ? 0 : 1, &rng));
  }
  EXPECT_TRUE(graph.joined(2));
  EXPECT_EQ(graph.held(), std::vector<std::size_t>{team.index[0][0]});
  team.addOwnLoops(&graph, &rng);
  const PoseGraphResult result = graph.optimize();
  ASSERT_TRUE(result.solved) << result.message;
  EXPECT_TRUE(graph.pose(team.index[0][0]).isApprox(Eigen::Isometry3d::Identity(), 1e-12)) << "the anchor's gauge";
  for (std::size_t r = 1; r < 3; ++r) {
    const Eigen::Isometry3d error = team.trueFrame(r).inverse() * graph.frame(r);
    const double metres = error.translation().norm(), degrees = angleOf(error) * 180.0 / M_PI;
    // The odometry alone (without the loops) would put the robot at the anchor's origin: tens of metres off.
    std::printf("robot %zu: true frame %.1f m / %.1f deg from the anchor's; estimated within %.3f m, %.3f deg\n", r,
                team.trueFrame(r).translation().norm(), angleOf(team.trueFrame(r)) * 180.0 / M_PI, metres, degrees);
    // The frame is the corrected first keyframe. The robots' odometries carry a heading bias (3 to 6 deg
    // a lap) that the odometry's noise model takes for zero-mean noise; the graph spreads it over the
    // steps and what remains is the residual the single-robot drive leaves too (0.54 m ATE there): here
    // 0.49 m / 0.73 deg at most. Without the loops the robots would sit at the anchor's origin, 84 m
    // and 99 m off.
    EXPECT_LT(metres, 0.6) << "robot " << r;
    EXPECT_LT(degrees, 1.0) << "robot " << r;
  }
  // And every robot's corrected trajectory lies on its truth in the anchor's frame.
  for (std::size_t r = 0; r < 3; ++r) {
    double worst = 0.0, odometry_worst = 0.0;
    for (std::size_t k = 0; k < kDriven; ++k) {
      const Eigen::Vector3d truth = (team.robots[0].origin().inverse() * team.robots[r].truth[k]).translation();
      worst = std::max(worst, (graph.pose(team.index[r][k]).translation() - truth).norm());
      odometry_worst =
          std::max(odometry_worst, ((team.trueFrame(r) * team.robots[r].odometry[k]).translation() - truth).norm());
    }
    std::printf("robot %zu: odometry (at the true frame) up to %.2f m off the truth, corrected %.3f m\n", r,
                odometry_worst, worst);
    EXPECT_GT(odometry_worst, 5.0) << "the simulated odometry should drift";
    EXPECT_LT(worst, 1.0);
  }
}

TEST(PoseGraphChains, AGroupJoinedThroughAnotherChainMovesAsOne) {
  Team team;
  PoseGraph graph;
  team.addKeyframes(&graph);
  std::mt19937 rng(5);
  // Robots 1 and 2 meet first: robot 2 moves onto robot 1 (the lower chain), robot 1 stays at its origin.
  ASSERT_TRUE(team.addLoop(&graph, 2, 10, 1, &rng));
  EXPECT_FALSE(graph.joined(1) || graph.joined(2));
  EXPECT_TRUE(graph.frame(1).isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  EXPECT_EQ(graph.held(), (std::vector<std::size_t>{team.index[0][0], team.index[1][0]}));
  // Robot 2's frame in robot 1's: already the truth up to the two odometries' drift.
  const Eigen::Isometry3d two_in_one = team.robots[1].origin().inverse() * team.robots[2].origin();
  EXPECT_LT((graph.frame(2).translation() - two_in_one.translation()).norm(), 5.0);
  ASSERT_TRUE(team.addLoop(&graph, 2, 40, 1, &rng));
  ASSERT_TRUE(graph.optimize().solved);
  EXPECT_TRUE(graph.frame(1).isApprox(Eigen::Isometry3d::Identity(), 1e-12)) << "robot 1's gauge is held";
  const Eigen::Isometry3d before_12 = graph.pose(team.index[1][0]).inverse() * graph.pose(team.index[2][0]);

  // Then robot 1 meets robot 0: robots 1 and 2 move together, rigidly.
  ASSERT_TRUE(team.addLoop(&graph, 0, 30, 1, &rng));
  EXPECT_TRUE(graph.joined(1) && graph.joined(2));
  EXPECT_EQ(graph.held(), std::vector<std::size_t>{team.index[0][0]});
  const Eigen::Isometry3d after_12 = graph.pose(team.index[1][0]).inverse() * graph.pose(team.index[2][0]);
  EXPECT_TRUE(after_12.isApprox(before_12, 1e-9)) << "the group did not move rigidly";
  for (std::size_t k = 0; k < kPerLap; k += 4) team.addLoop(&graph, 1, k, 0, &rng);
  for (std::size_t k = 2; k < kPerLap; k += 6) team.addLoop(&graph, 2, k, 1, &rng);
  team.addOwnLoops(&graph, &rng);
  ASSERT_TRUE(graph.optimize().solved);
  for (std::size_t r = 1; r < 3; ++r) {
    const Eigen::Isometry3d error = team.trueFrame(r).inverse() * graph.frame(r);
    std::printf("robot %zu (robots 1-2 joined, then 1-0): frame within %.3f m, %.3f deg\n", r,
                error.translation().norm(), angleOf(error) * 180.0 / M_PI);
    EXPECT_LT(error.translation().norm(), 0.6);  // as when joined directly (above)
    EXPECT_LT(angleOf(error) * 180.0 / M_PI, 1.0);
  }
}

TEST(PoseGraphChains, ALoopInsideAnUnjoinedChainCorrectsItInItsOwnFrame) {
  // Robot 1 drives two laps and closes a loop on itself every 3rd keyframe of its second lap; no loop
  // reaches robot 0. It stays unjoined, held at its own origin, and its own drift is corrected.
  const Robot robot = drive(50, 0.8, 0.001, 4, 2 * kPerLap);
  const std::vector<Eigen::Isometry3d>& truth = robot.truth;
  const std::vector<Eigen::Isometry3d>& odometry = robot.odometry;
  const Robot anchor = drive(0, 0.0, 0.001, 6);
  PoseGraph graph, alone;
  std::vector<std::size_t> own;
  for (std::size_t k = 0; k < 2 * kPerLap; ++k) {
    if (k < kPerLap) {
      ASSERT_GE(graph.addKeyframe(anchor.odometry[k]), 0);
      ASSERT_GE(alone.addKeyframe(anchor.odometry[k]), 0);
    }
    own.push_back(static_cast<std::size_t>(graph.addKeyframe(odometry[k], 1)));
  }
  std::mt19937 rng(3);
  std::normal_distribution<double> metres(0.0, 0.03);
  for (std::size_t k = kPerLap; k < 2 * kPerLap; k += 3) {
    const Eigen::Isometry3d measured = truth[k].inverse() * truth[k - kPerLap] * planar(metres(rng), metres(rng), 0.0);
    ASSERT_TRUE(graph.addLoop(own[k], own[k - kPerLap], measured, verifiedCovariance()));
  }
  ASSERT_TRUE(graph.optimize().solved);
  ASSERT_TRUE(alone.optimize().solved);
  EXPECT_FALSE(graph.joined(1));
  EXPECT_TRUE(graph.frame(1).isApprox(Eigen::Isometry3d::Identity(), 1e-12)) << "held at its own origin";
  // In its own frame (its first true pose the origin) the corrected second lap lies on the truth.
  double odometry_worst = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < 2 * kPerLap; ++k) {
    const Eigen::Vector3d t = (truth[0].inverse() * truth[k]).translation();
    odometry_worst = std::max(odometry_worst, (odometry[k].translation() - t).norm());
    if (k >= kPerLap) worst = std::max(worst, (graph.pose(own[k]).translation() - t).norm());
  }
  std::printf("unjoined robot closing its own loops: odometry up to %.2f m off, corrected lap 2 %.3f m\n",
              odometry_worst, worst);
  EXPECT_GT(odometry_worst, 5.0);
  EXPECT_LT(worst, 0.25 * odometry_worst);
  // Robot 0 is exactly what it is without robot 1 in the graph.
  for (std::size_t k = 0; k < kPerLap; ++k) {
    EXPECT_TRUE(graph.pose(2 * k).isApprox(alone.pose(k), 1e-12)) << k;  // interleaved: robot 0's at 2k
  }
}

TEST(PoseGraphChains, ChainZeroIsTheGraphWithoutChains) {
  // addKeyframe(pose) and addKeyframe(pose, 0) build the same graph: same factors, same solution.
  const Robot a = drive(0, 0.0, 0.002, 1);
  PoseGraph plain, zero;
  for (std::size_t k = 0; k < kPerLap; ++k) {
    ASSERT_EQ(plain.addKeyframe(a.odometry[k]), static_cast<long>(k));
    ASSERT_EQ(zero.addKeyframe(a.odometry[k], 0), static_cast<long>(k));
  }
  for (PoseGraph* g : {&plain, &zero}) {
    ASSERT_TRUE(g->addLoop(kPerLap - 1, 0, a.truth.back().inverse() * a.truth.front(), verifiedCovariance()));
    ASSERT_TRUE(g->optimize().solved);
  }
  ASSERT_EQ(plain.factors().size(), kPerLap);
  for (std::size_t k = 0; k + 1 < kPerLap; ++k) {
    EXPECT_EQ(plain.factors()[k].a, k);
    EXPECT_EQ(plain.factors()[k].b, k + 1);
  }
  for (std::size_t k = 0; k < kPerLap; ++k) EXPECT_TRUE(plain.pose(k).isApprox(zero.pose(k), 1e-12));
  EXPECT_EQ(plain.chains(), 1u);
  EXPECT_TRUE(plain.joined(0));
  EXPECT_EQ(plain.held(), std::vector<std::size_t>{0});
  EXPECT_TRUE(plain.frame(0).isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  EXPECT_TRUE(plain.correction().isApprox(plain.correction(0), 1e-15));
  EXPECT_TRUE(plain.correction(5).isApprox(Eigen::Isometry3d::Identity(), 1e-15)) << "a chain without keyframes";
  EXPECT_FALSE(plain.joined(5));
  EXPECT_EQ(plain.addKeyframe(a.odometry[0], PoseGraph::kMaxChains), -1);
}

}  // namespace
}  // namespace scan_context_loop
