// Relocalization in a prior map: LoopDetector::locate and Config::prior_sessions_only, on real scans.
#include <gtest/gtest.h>

#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

Config relocalizing() {
  Config config;
  config.exclude_recent_frames = 0;
  config.consistency_min_support = 0;  // single scans: each verified loop at once
  config.prior_sessions_only = true;
  return config;
}

/// A prior session of two real places: KITTI 08 720 and KITTI 00 94.
void priorMap(LoopDetector* detector) {
  KeyframeInfo info;
  for (const auto& [sequence, frame] : {std::pair<const char*, int>{"08", 720}, {"00", 94}}) {
    info.stamp += 1.0;
    ASSERT_TRUE(detector->process(viewOf(test::kittiScan(sequence, frame)), info).accepted);
  }
  detector->startSession();
}

TEST(Relocalization, LocatesAScanInThePriorMapWithoutStoringIt) {
  LoopDetector detector(relocalizing());
  priorMap(&detector);
  // 95 is the next scan after 94: located at 94 with the true pose.
  const Detection next = detector.locate(viewOf(test::kittiScan("00", 95)));
  EXPECT_FALSE(next.accepted);
  ASSERT_TRUE(next.verified);
  EXPECT_EQ(next.verifications.back().index, 1u);
  const Eigen::Isometry3d truth = test::kittiRelative("00", 95, 94);
  EXPECT_LT((next.verifications.back().result.relative.translation() - truth.translation()).norm(), 0.1);
  // 1500 drives 720's street the other way.
  const Detection reverse = detector.locate(viewOf(test::kittiScan("08", 1500)));
  ASSERT_TRUE(reverse.verified);
  EXPECT_EQ(reverse.verifications.back().index, 0u);
  // Nothing was added.
  EXPECT_EQ(detector.database().size(), 2u);
  EXPECT_EQ(detector.cloudStore().stored(), 2u);
  // A place the map does not hold (KITTI 00 198 is 58 m from 94) is not verified anywhere.
  const Detection elsewhere = detector.locate(viewOf(test::kittiScan("00", 198)));
  EXPECT_FALSE(elsewhere.verified);
}

TEST(Relocalization, PriorSessionsOnlyNeverMatchesTheCurrentSession) {
  LoopDetector detector(relocalizing());
  priorMap(&detector);
  KeyframeInfo info;
  info.stamp = 1.0;
  ASSERT_TRUE(detector.process(viewOf(test::kittiScan("00", 94)), info).accepted);
  info.stamp = 2.0;
  // 95 matches the current session's copy of 94 (index 2) as well as the prior map's (index 1), but only
  // the prior map's may be its place.
  const Detection d = detector.process(viewOf(test::kittiScan("00", 95)), info);
  EXPECT_EQ(d.query.eligible, 2u);
  ASSERT_EQ(d.loops.size(), 1u);
  EXPECT_EQ(d.loops.front().match, 1u);
}

}  // namespace
}  // namespace scan_context_loop
