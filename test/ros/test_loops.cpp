// rostest: a simulated drive in, loop closures out; checks ids, stamps, revisits, yaw and markers.
#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <tf2_eigen/tf2_eigen.h>

#include "harness.h"
#include "topic_watch.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/config.h"
#include "../common/planar.h"

namespace scan_context_loop {
namespace test {
namespace {

using Covariance = Eigen::Matrix<double, 6, 6>;

Covariance covarianceOf(const boost::array<double, 36>& values) {
  Covariance c;
  for (int i = 0; i < 36; ++i) c(i / 6, i % 6) = values[i];
  return c;
}

/// A loop's covariance is what a backend can use: symmetric and positive definite. A verified loop's is
/// the registration's (each variance at least the floor); a descriptor loop's is the documented prior:
/// covariance_translation, covariance_rotation and half a sector's yaw squared, nothing off the diagonal.
void expectUsableCovariance(const Covariance& c, bool verified) {
  const Config config;
  EXPECT_TRUE(c.isApprox(c.transpose(), 1e-9)) << c;
  const Eigen::SelfAdjointEigenSolver<Covariance> eigen(c);
  EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0) << c;
  if (verified) {
    for (int i = 0; i < 3; ++i) EXPECT_GE(c(i, i), config.verification.min_translation_variance * (1 - 1e-4)) << c;
    for (int i = 3; i < 6; ++i) EXPECT_GE(c(i, i), config.verification.min_rotation_variance * (1 - 1e-4)) << c;
    // (The floor holds for the eigenvalues, so a diagonal may sit a rounding below it.)
    // A registration that found the loop to 0.3 m (checked against the truth) does not report it as
    // unknown: every standard deviation under 1 m and 5 degrees on this well-structured drive.
    for (int i = 0; i < 3; ++i) EXPECT_LT(c(i, i), 1.0) << c;
    for (int i = 3; i < 6; ++i) EXPECT_LT(c(i, i), std::pow(5.0 * M_PI / 180.0, 2)) << c;
  } else {
    const double half_sector = M_PI / config.num_sectors;
    Eigen::Matrix<double, 6, 1> prior;
    prior << config.covariance_translation, config.covariance_translation, config.covariance_translation,
        config.covariance_rotation, config.covariance_rotation, half_sector * half_sector;
    EXPECT_TRUE(c.isApprox(Covariance(prior.asDiagonal()), 1e-12)) << c;
  }
}

TEST(LoopClosureNode, PublishesTrueRevisitsWithTheirYawAndMarkers) {
  ros::NodeHandle nh, pnh("~");
  bool expect_lio = false, expect_verified = false;
  int expect_support = 0;
  pnh.param("expect_lio", expect_lio, expect_lio);
  pnh.param("expect_support", expect_support, expect_support);
  pnh.param("expect_verified", expect_verified, expect_verified);
  // lio_unheard: nobody subscribes to LIO-SAM's hook, and the node must say so once.
  const bool lio_unheard = pnh.param("lio_unheard", false);
  RosoutWatch rosout(nh);
  Harness harness(nh, !lio_unheard);
  ASSERT_TRUE(harness.waitForNode(30.0)) << "the loop-closure node never subscribed";
  const Drive drive = blockDrive(true, 7);  // lap 2 drives lap 1 in reverse
  harness.publish(drive, 0, drive.truth.size(), 15.0);
  harness.settle(3.0, 30.0);

  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u) << "reverse revisits of a whole lap";
  for (const auto& loop : loops) {
    const int q = keyframeAt(drive, harness.base, loop.query_stamp);
    const int m = keyframeAt(drive, harness.base, loop.match_stamp);
    ASSERT_GE(q, 0);
    ASSERT_GE(m, 0);
    // Every keyframe was accepted, so keyframe numbers are publication indices.
    EXPECT_EQ(loop.query_id, static_cast<std::uint32_t>(q));
    EXPECT_EQ(loop.match_id, static_cast<std::uint32_t>(m));
    EXPECT_EQ(loop.header.stamp, loop.query_stamp);
    EXPECT_EQ(loop.header.frame_id, "odom");
    const Eigen::Isometry3d truth = drive.truth[q].inverse() * drive.truth[m];
    // A descriptor loop must join a revisit; a verified one is a constraint, checked by its pose below
    // (it may join keyframes a little more than 5 m apart).
    EXPECT_LT(truth.translation().norm(), expect_verified ? 10.0 : 5.0) << "loop " << q << " -> " << m;
    EXPECT_LT(std::fabs(wrapAngle(loop.yaw - yawOf(truth))), 6.0 * M_PI / 180.0) << "loop " << q << " -> " << m;
    Eigen::Isometry3d relative;
    tf2::fromMsg(loop.relative_pose, relative);
    expectUsableCovariance(covarianceOf(loop.covariance), loop.verified);
    EXPECT_EQ(loop.verified, expect_verified);
    EXPECT_GE(loop.support, static_cast<std::uint32_t>(expect_support)) << "loop " << q << " -> " << m;
    if (expect_verified) {
      // The registered pose, not the prior: translation and yaw against the truth.
      EXPECT_LT(loop.distance, Config().verification.threshold);  // the launch files keep the default
      EXPECT_LT((relative.translation() - truth.translation()).norm(), 0.3) << "loop " << q << " -> " << m;
      EXPECT_LT(std::fabs(wrapAngle(yawOf(relative) - yawOf(truth))), 1.0 * M_PI / 180.0);
      EXPECT_GT(loop.fitness, 0.0);
    } else {
      EXPECT_LT(loop.distance, 0.21);
      EXPECT_NEAR(yawOf(relative), loop.yaw, 1e-6);
    }
  }

  // The standard-type copy: for every loop, the match's pose then the query's, whose difference is the
  // loop's relative pose.
  const auto pairs = harness.loopPairs();
  ASSERT_EQ(pairs.size(), 2 * loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    EXPECT_EQ(pairs[2 * i].header.stamp, loops[i].match_stamp);
    EXPECT_EQ(pairs[2 * i + 1].header.stamp, loops[i].query_stamp);
    Eigen::Isometry3d match, query, relative;
    tf2::fromMsg(pairs[2 * i].pose.pose, match);
    tf2::fromMsg(pairs[2 * i + 1].pose.pose, query);
    tf2::fromMsg(loops[i].relative_pose, relative);
    EXPECT_TRUE((query.inverse() * match).isApprox(relative, 1e-6)) << "loop " << loops[i].query_id;
    // The query's pose carries the loop's covariance turned into the pose frame's axes, the match's none.
    Covariance rotate = Covariance::Zero();
    rotate.topLeftCorner<3, 3>() = rotate.bottomRightCorner<3, 3>() = query.linear();
    const Covariance expected = rotate * covarianceOf(loops[i].covariance) * rotate.transpose();
    // (A registered rotation is orthonormal to float precision, hence the tolerance.)
    EXPECT_TRUE(covarianceOf(pairs[2 * i + 1].pose.covariance).isApprox(expected, 1e-5))
        << "loop " << loops[i].query_id << "\n"
        << covarianceOf(pairs[2 * i + 1].pose.covariance);
    EXPECT_TRUE(covarianceOf(pairs[2 * i].pose.covariance).isZero(0.0));
  }

  // keyframe_timing: one message per keyframe, in order, with its stamp and the time it took.
  const auto timings = harness.timings();
  ASSERT_EQ(timings.size(), drive.truth.size());
  for (std::size_t k = 0; k < timings.size(); ++k) {
    const auto& t = timings[k];
    EXPECT_EQ(t.keyframe_id, k);
    EXPECT_EQ(t.database_size, k + 1);
    EXPECT_EQ(t.header.stamp, harness.base + ros::Duration(drive.times[k]));
    EXPECT_EQ(t.header.frame_id, "odom");
    EXPECT_GE(t.queue_ms, 0.0);
    EXPECT_GT(t.describe_query_ms, 0.0);
    EXPECT_GE(t.verify_ms, 0.0);
    // The whole keyframe includes its parts (and the cloud checks, the registration data, publishing).
    EXPECT_GE(t.processing_ms, t.describe_query_ms + t.verify_ms) << "keyframe " << k;
    // The core's time holds its timed parts, and with publishing it lies within the whole.
    EXPECT_GE(t.ground_check_ms, 0.0);
    EXPECT_GE(t.choose_ms, 0.0);
    EXPECT_GT(t.publish_ms, 0.0) << "keyframe " << k;  // its markers and selected keyframe at least
    EXPECT_GE(t.detect_ms, t.describe_query_ms + t.verify_ms + t.ground_check_ms + t.choose_ms) << "keyframe " << k;
    EXPECT_LE(t.detect_ms + t.publish_ms, t.processing_ms) << "keyframe " << k;
    EXPECT_LT(t.processing_ms, 10000.0) << "keyframe " << k;
    // The worker's own CPU time is some of that wall time, never more (the clocks read apart by a few us).
    EXPECT_GT(t.cpu_ms, 0.0) << "keyframe " << k;
    EXPECT_LE(t.cpu_ms, t.processing_ms + 0.05) << "keyframe " << k;
  }

  ASSERT_GT(harness.markerMessages(), 0u);
  // The markers RViz would show: every keyframe and every loop, although each message carried only what
  // changed (a few chunks, never the whole map).
  const auto markers = harness.shownMarkers();
  std::size_t edges = 0, keyframes = 0;
  for (const auto& m : markers.markers) {
    if (m.ns == "loops") edges += m.points.size() / 2;
    if (m.ns == "keyframes") keyframes += m.points.size();
  }
  EXPECT_EQ(edges, loops.size());
  EXPECT_EQ(keyframes, drive.truth.size());
  EXPECT_LT(harness.largestMarkerMessage(), 2 * drive.truth.size()) << "a marker message carried the whole map";

  const std::string unheard = "nobody subscribes to";
  const std::size_t unheard_warnings = rosout.count(rosgraph_msgs::Log::WARN, "/loop_closure", unheard);
  if (lio_unheard) {
    EXPECT_EQ(unheard_warnings, 1u) << "the hook's missing subscriber, warned once";
  } else if (expect_lio) {
    EXPECT_EQ(unheard_warnings, 0u) << "warned of a missing subscriber while the test subscribes";
  }
  const auto lio = harness.lioLoops();
  if (expect_lio) {
    // LIO-SAM's hook: verified loops only, one per keyframe, at most one a second (lio_sam_min_interval).
    ASSERT_FALSE(lio.empty());
    EXPECT_LE(lio.size(), loops.size());
    const auto arrivals = harness.lioArrivals();
    for (std::size_t i = 0; i < lio.size(); ++i) {
      ASSERT_EQ(lio[i].data.size(), 2u);
      const auto same = std::find_if(loops.begin(), loops.end(), [&](const LoopClosure& l) {
        return l.query_stamp.toSec() == lio[i].data[0] && l.match_stamp.toSec() == lio[i].data[1];
      });
      ASSERT_NE(same, loops.end()) << "lio_loop " << i << " is no published loop";
      EXPECT_TRUE(same->verified);
      if (i > 0) {
        EXPECT_NE(lio[i].data[0], lio[i - 1].data[0]);
        EXPECT_GT(arrivals[i] - arrivals[i - 1], 0.8) << "lio_loop messages " << i - 1 << " and " << i;
      }
    }
  } else {
    EXPECT_TRUE(lio.empty());
  }
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_loops"); }
