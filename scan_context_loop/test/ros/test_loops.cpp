// rostest: a simulated drive in, loop closures out; checks ids, stamps, revisits, yaw and markers.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <tf2_eigen/tf2_eigen.h>

#include "harness.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/config.h"

namespace scan_context_loop {
namespace test {
namespace {

double yawOf(const Eigen::Isometry3d& t) { return std::atan2(t(1, 0), t(0, 0)); }

TEST(LoopClosureNode, PublishesTrueRevisitsWithTheirYawAndMarkers) {
  ros::NodeHandle nh, pnh("~");
  bool expect_lio = false, expect_verified = false;
  int expect_support = 0;
  pnh.param("expect_lio", expect_lio, expect_lio);
  pnh.param("expect_support", expect_support, expect_support);
  pnh.param("expect_verified", expect_verified, expect_verified);
  Harness harness(nh);
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
    EXPECT_GT(loop.covariance[35], 0.0);
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
    EXPECT_GT(pairs[2 * i + 1].pose.covariance[35], 0.0);
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
    EXPECT_LT(t.processing_ms, 10000.0) << "keyframe " << k;
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
