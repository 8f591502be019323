// The odometry checks when the odometry fails: predictions through confirmed loops, allowances that grow
// with the drift the loops measured, and a drive whose odometry heading breaks in the middle.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "../common/sim_drive.h"
#include "scan_context_loop/core/acceptance_rule.h"
#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/odometry_trust.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_sim/odometry_failures.h"

namespace scan_context_loop {
namespace {

Eigen::Isometry3d pose(double x, double y, double yaw_deg) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() << x, y, 0.0;
  p.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

Keyframe keyframe(const Eigen::Isometry3d& p, double path) {
  Keyframe k;
  k.info.pose = p;
  k.path_length = path;
  return k;
}

double yawDeg(const Eigen::Isometry3d& t) { return std::atan2(t(1, 0), t(0, 0)) * 180.0 / M_PI; }

TEST(OdometryTrust, PredictsThroughTheConfirmedLoopNearestInOdometryPath) {
  // The odometry turned 90 degrees away between keyframes 0 (path 0) and 1 (path 500), which are the
  // same place (the loop says T_1<-0 = identity).
  const Keyframe k0 = keyframe(pose(0, 0, 0), 0.0), k1 = keyframe(pose(300, 200, 90), 500.0);
  const Keyframe near_k0 = keyframe(pose(10, 0, 0), 10.0);  // 10 m after k0 along x
  OdometryTrust trust;
  const auto direct = trust.predict(pose(300, 200, 90), 500.0, 0, near_k0);
  EXPECT_FALSE(direct.anchored);
  EXPECT_DOUBLE_EQ(direct.path, 490.0);
  const Config config;
  trust.add(k1, k0, Eigen::Isometry3d::Identity(), config);
  // A query 5 m after k1 (in its broken frame): through the loop, the candidate is 5 m ahead of it.
  const Eigen::Isometry3d query = pose(300, 200, 90) * pose(5, 0, 0);
  const auto via = trust.predict(query, 505.0, 0, near_k0);
  EXPECT_TRUE(via.anchored);
  EXPECT_DOUBLE_EQ(via.path, 15.0);
  EXPECT_NEAR(via.relative.translation().x(), 5.0, 1e-9);
  EXPECT_NEAR(via.relative.translation().y(), 0.0, 1e-9);
  EXPECT_NEAR(yawDeg(via.relative), 0.0, 1e-9);
  // The loop measured the direct odometry 360 m off over 500 m, beyond the gate's fixed 20 m.
  EXPECT_NEAR(trust.translationRate(), (std::hypot(300.0, 200.0) - config.gate_odometry_distance) / 500.0, 1e-9);
}

TEST(OdometryTrust, TheGateGrowsWithTheMeasuredDriftOnly) {
  Config config;
  OdometryTrust trust;
  const double configured = config.gate_odometry_distance + config.gate_odometry_drift * 100.0;
  EXPECT_DOUBLE_EQ(gateRadius(config, trust, 100.0), configured);
  // A short loop (below kMinMeasuredPath) measures nothing; one across another session neither, nor one
  // whose error stays within the fixed part (20 m).
  const Eigen::Isometry3d same = Eigen::Isometry3d::Identity();
  trust.add(keyframe(pose(60, 0, 0), 20.0), keyframe(pose(0, 0, 0), 0.0), same, config);
  Keyframe other = keyframe(pose(0, 0, 0), 0.0);
  other.session = 1;
  trust.add(keyframe(pose(500, 0, 0), 900.0), other, same, config);
  trust.add(keyframe(pose(15, 0, 0), 900.0), keyframe(pose(0, 0, 0), 0.0), same, config);
  EXPECT_DOUBLE_EQ(trust.translationRate(), 0.0);
  EXPECT_DOUBLE_EQ(gateRadius(config, trust, 100.0), configured);
  // 80 m over 200 m: 0.3 m/m beyond the fixed 20 m, 0.45 m/m allowed.
  trust.add(keyframe(pose(80, 0, 0), 300.0), keyframe(pose(0, 0, 0), 100.0), same, config);
  EXPECT_NEAR(gateRadius(config, trust, 100.0),
              config.gate_odometry_distance + OdometryTrust::kMeasuredDriftMargin * 0.3 * 100.0, 1e-9);
  // The rotation allowance stays what is configured.
  EXPECT_DOUBLE_EQ(rotationAllowance(config.verification, 100.0),
                   config.verification.odometry_rotation + config.verification.odometry_rotation_drift * 100.0);
}

/// The block drive (lap 2 the other way round) with the given odometry failures, through the detector
/// with its defaults: the true loops found, and whether any is wrong.
struct Outcome {
  int true_loops = 0, wrong_loops = 0;
};

Outcome runBrokenDrive(const test::Drive& drive, const sim::OdometryFailures& failures) {
  const std::vector<Eigen::Isometry3d> odometry = sim::withFailures(drive.truth, failures);
  Config config;
  config.exclude_recent_frames = 30;
  LoopDetector detector(config);
  Outcome outcome;
  for (std::size_t k = 0; k < drive.truth.size(); ++k) {
    KeyframeInfo info;
    info.stamp = drive.times[k];
    info.pose = odometry[k];
    const pcl::PointCloud<pcl::PointXYZI> cloud = drive.scan(k);
    const Detection d = detector.process(viewOf(cloud), info);
    for (const Loop& loop : d.loops) {
      const Eigen::Isometry3d truth = drive.truth[loop.query].inverse() * drive.truth[loop.match];
      const Eigen::Isometry3d error = truth.inverse() * loop.relative();
      const bool right =
          error.translation().norm() < 1.0 && Eigen::AngleAxisd(error.linear()).angle() < 2.0 * M_PI / 180.0;
      ++(right ? outcome.true_loops : outcome.wrong_loops);
    }
  }
  return outcome;
}

TEST(OdometryTrust, LoopsWhenTheOdometryHeadingBreaksBeforeAReverseRevisit) {
  const test::Drive drive = test::blockDrive(true, 11);
  const Outcome mild = runBrokenDrive(drive, sim::OdometryFailures());
  // The odometry's heading turns away by 60 degrees over lap 2 (which drives lap 1 the other way), from
  // a little before it on: most loops of lap 2 then disagree with the odometry's rotation far beyond
  // its drift allowance (with the allowances fixed, 8 of the 93 true loops were found).
  sim::OdometryFailures broken;
  broken.heading_ramp_deg = 60.0;
  broken.ramp_start = 0.45;
  const Outcome outcome = runBrokenDrive(drive, broken);
  std::printf("true loops: %d with the odometry as it is, %d with its heading broken (%d wrong)\n", mild.true_loops,
              outcome.true_loops, outcome.wrong_loops);
  EXPECT_EQ(mild.wrong_loops, 0);
  EXPECT_EQ(outcome.wrong_loops, 0);
  ASSERT_GT(mild.true_loops, 20);
  EXPECT_GE(outcome.true_loops, 0.8 * mild.true_loops);
}

TEST(OdometryTrust, TheNearestLoopIsTheOneAScanOverAllLoopsFinds) {
  // Thousands of loops in two sessions, paths on a metre grid so that many predictions tie: each
  // prediction must pick what a scan over every loop in the order they were confirmed picks (the
  // direct odometry unless a loop leaves strictly less path; of equal loops the first).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> place(-500.0, 500.0), turn(-180.0, 180.0);
  std::uniform_int_distribution<int> metres(0, 3000), session_of(0, 1);
  struct Loop {
    Keyframe query, match;
    Eigen::Isometry3d relative;
  };
  std::vector<Loop> loops;
  OdometryTrust trust;
  const Config config;
  const auto randomKeyframe = [&](std::uint32_t session) {
    Keyframe k = keyframe(pose(place(rng), place(rng), turn(rng)), metres(rng));
    k.session = session;
    return k;
  };
  for (int i = 0; i < 3000; ++i) {
    const auto session = static_cast<std::uint32_t>(session_of(rng));
    Loop loop{randomKeyframe(session), randomKeyframe(session), pose(place(rng) / 100.0, 0.0, turn(rng) / 10.0)};
    trust.add(loop.query, loop.match, loop.relative, config);
    loops.push_back(loop);
  }
  ASSERT_EQ(trust.anchors(), loops.size());
  int anchored = 0;
  for (int q = 0; q < 2000; ++q) {
    const auto session = static_cast<std::uint32_t>(session_of(rng));
    const Keyframe query = randomKeyframe(session), candidate = randomKeyframe(session);
    const OdometryPrediction got = trust.predict(*query.info.pose, query.path_length, session, candidate);
    double best = std::fabs(query.path_length - candidate.path_length);
    const Loop* via = nullptr;
    for (const Loop& l : loops) {
      if (l.query.session != session) continue;
      const double length =
          std::fabs(query.path_length - l.query.path_length) + std::fabs(l.match.path_length - candidate.path_length);
      if (length < best) {
        best = length;
        via = &l;
      }
    }
    ASSERT_EQ(got.path, best) << "prediction " << q;
    ASSERT_EQ(got.anchored, via != nullptr) << "prediction " << q;
    Eigen::Isometry3d expected = query.info.pose->inverse() * *candidate.info.pose;
    if (via != nullptr) {
      expected = query.info.pose->inverse() * *via->query.info.pose * via->relative * via->match.info.pose->inverse() *
                 *candidate.info.pose;
    }
    ASSERT_TRUE(got.relative.isApprox(expected, 1e-9)) << "prediction " << q;
    anchored += got.anchored;
  }
  // Both kinds were asked for.
  EXPECT_GT(anchored, 1000);
  EXPECT_LT(anchored, 2000);
}

}  // namespace
}  // namespace scan_context_loop
