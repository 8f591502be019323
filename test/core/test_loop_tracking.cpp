// Loop tracking (LoopTracker): where a confirmed loop and the odometry put the next keyframes.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/descriptor.h"
#include "scan_context_loop/core/loop_tracking.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

Eigen::Isometry3d pose(double x, double y, double yaw_deg) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, 0.0);
  return p;
}

/// Two sessions of one street in the world frame: the first drives +x with a keyframe every 2 m; the
/// second drives it back (-x) 3 m over, its odometry in a frame of its own (turned by 90 degrees and
/// moved, as a run that starts elsewhere has). world_from_second maps its odometry into the world.
struct TwoSessions {
  explicit TwoSessions(const Config& c) : config(c), database(c) {
    const Descriptor d = makeDescriptor(test::streetScene(5), config);
    for (int k = 0; k < 50; ++k) {
      KeyframeInfo info;
      info.stamp = k;
      info.pose = pose(2.0 * k, 0.0, 0.0);
      EXPECT_TRUE(database.add(info, d));
    }
    database.startSession();
    for (int k = 0; k < 50; ++k) {
      KeyframeInfo info;
      info.stamp = k;
      info.pose = world_from_second.inverse() * truthOfSecond(k);
      EXPECT_TRUE(database.add(info, d));
    }
  }
  /// Keyframe k of the second session: from x = 90 m back to -8 m, at y = 3 m, facing -x.
  static Eigen::Isometry3d truthOfSecond(int k) { return pose(90.0 - 2.0 * k, 3.0, 180.0); }
  std::size_t second(int k) const { return 50 + static_cast<std::size_t>(k); }
  /// The verified loop of second-session keyframe k into first-session keyframe m, at the truth moved by
  /// `error_m` along x.
  Loop loop(int k, std::size_t m, double error_m = 0.0) const {
    Loop l;
    l.query = second(k);
    l.match = m;
    l.verified = true;
    l.verification.accepted = true;
    l.verification.relative = truthOfSecond(k).inverse() * pose(2.0 * m, 0.0, 0.0) * pose(error_m, 0.0, 0.0);
    return l;
  }
  Config config;
  Database database;
  const Eigen::Isometry3d world_from_second = pose(-300.0, 50.0, 90.0);
};

TEST(LoopTracking, AConfirmedLoopPredictsTheNextKeyframesMatchAndPose) {
  TwoSessions s{Config()};
  LoopTracker tracker;
  tracker.anchor(s.loop(5, 40));  // second-session keyframe 5 stands at x = 80 m, by first-session 40
  for (int k = 6; k < 15; ++k) {
    const auto predicted = tracker.predict(s.database, s.second(k), s.database.sessionStart());
    ASSERT_TRUE(predicted) << k;
    // x = 90 - 2k: the first session's keyframe 45 - k stands there, 3 m to the side.
    EXPECT_EQ(predicted->index, static_cast<std::size_t>(45 - k));
    EXPECT_NEAR(predicted->gap, 3.0, 1e-6);
    const Eigen::Isometry3d truth = TwoSessions::truthOfSecond(k).inverse() * pose(2.0 * (45 - k), 0.0, 0.0);
    EXPECT_LT((predicted->guess.translation() - truth.translation()).norm(), 1e-6);
    EXPECT_LT(Eigen::AngleAxisd(predicted->guess.linear().transpose() * truth.linear()).angle(), 1e-9);
  }
}

TEST(LoopTracking, OnlyAUsableKeyframeIsChosen) {
  // The cloud store may have dropped the nearest keyframe's registration data on a long run: the
  // nearest one that still has them is tried instead.
  TwoSessions s{Config()};
  LoopTracker tracker;
  tracker.anchor(s.loop(5, 40));
  const auto kept =
      tracker.predict(s.database, s.second(8), s.database.sessionStart(), [](std::size_t i) { return i % 4 == 0; });
  ASSERT_TRUE(kept);
  EXPECT_EQ(kept->index, 36u);  // 37 is nearest (3 m), 36 next (about 3.6 m)
  EXPECT_FALSE(tracker.predict(s.database, s.second(8), s.database.sessionStart(), [](std::size_t) { return false; }));
}

TEST(LoopTracking, OnlyLoopsVerifiedInFullAnchorAndTheLatestWins) {
  TwoSessions s{Config()};
  LoopTracker tracker;
  Loop unverified = s.loop(5, 40);
  unverified.verified = false;
  tracker.anchor(unverified);
  EXPECT_FALSE(tracker.current());
  Loop weak = s.loop(5, 40);
  weak.verification.needs_support = true;
  tracker.anchor(weak);
  EXPECT_FALSE(tracker.current());
  EXPECT_FALSE(tracker.predict(s.database, s.second(6), s.database.sessionStart()));
  tracker.anchor(s.loop(8, 37));
  tracker.anchor(s.loop(5, 40));  // an older query (a loop confirmed late) does not take over
  ASSERT_TRUE(tracker.current());
  EXPECT_EQ(tracker.current()->query, s.second(8));
}

TEST(LoopTracking, TheTrackEndsAfterTrackDistanceAndWithoutAPlaceInReach) {
  Config config;
  config.track_distance = 10.0;
  TwoSessions s{config};
  LoopTracker tracker;
  tracker.anchor(s.loop(5, 40));
  EXPECT_TRUE(tracker.predict(s.database, s.second(10), s.database.sessionStart()));   // 10 m on
  EXPECT_FALSE(tracker.predict(s.database, s.second(11), s.database.sessionStart()));  // 12 m on
  // Past the first session's start (x = 0) no keyframe is within reach.
  config.track_distance = 1000.0;
  TwoSessions far{config};
  tracker.anchor(far.loop(40, 5));                                                                   // x = 10 m
  const auto at_start = tracker.predict(far.database, far.second(46), far.database.sessionStart());  // x = -2 m
  ASSERT_TRUE(at_start);
  EXPECT_EQ(at_start->index, 0u);
  EXPECT_FALSE(tracker.predict(far.database, far.second(49), far.database.sessionStart()));  // x = -8 m
  // Only the keyframes the query may match: none when nothing is eligible.
  EXPECT_FALSE(tracker.predict(far.database, far.second(46), 0));
  config.track_distance = 0.0;
  TwoSessions off{config};
  tracker.clear();
  tracker.anchor(off.loop(5, 40));
  EXPECT_FALSE(tracker.predict(off.database, off.second(6), off.database.sessionStart()));
}

TEST(LoopTracking, AnotherPassOfTheMatchSessionIsNeverTheTrackedPlace) {
  // The first session drives the street twice: out along y = 0, then back along y = 2 (keyframes 50-99),
  // nearer the second session's lane (y = 3). The two passes are related only through the odometry of
  // everything driven in between, so the track stays with the anchor's pass, and a loop into the other
  // pass does not count as agreeing with the anchor however the odometry happens to line up.
  Config config;
  Database database(config);
  const Descriptor d = makeDescriptor(test::streetScene(5), config);
  const auto add = [&](const Eigen::Isometry3d& p, double stamp) {
    KeyframeInfo info;
    info.stamp = stamp;
    info.pose = p;
    EXPECT_TRUE(database.add(info, d));
  };
  for (int k = 0; k < 50; ++k) add(pose(2.0 * k, 0.0, 0.0), k);
  for (int k = 0; k < 50; ++k) add(pose(98.0 - 2.0 * k, 2.0, 180.0), 50 + k);
  database.startSession();
  for (int k = 0; k < 20; ++k) add(TwoSessions::truthOfSecond(k), k);  // odometry in the world frame
  const auto query = [](int k) { return std::size_t{100} + static_cast<std::size_t>(k); };
  Loop anchor;
  anchor.query = query(5);
  anchor.match = 40;
  anchor.verified = true;
  anchor.verification.relative = TwoSessions::truthOfSecond(5).inverse() * pose(80.0, 0.0, 0.0);
  LoopTracker tracker;
  tracker.anchor(anchor);
  const auto predicted = tracker.predict(database, query(8), database.sessionStart());
  ASSERT_TRUE(predicted);
  EXPECT_EQ(predicted->index, 37u);  // x = 74 m on the first pass, 3 m away; not 62 (1 m away)
  Loop other_pass;
  other_pass.query = query(8);
  other_pass.match = 62;
  other_pass.verified = true;
  other_pass.verification.relative = TwoSessions::truthOfSecond(8).inverse() * pose(74.0, 2.0, 180.0);
  EXPECT_FALSE(tracker.agrees(other_pass, database, false));
  Loop same_pass = other_pass;
  same_pass.match = 37;
  same_pass.verification.relative = TwoSessions::truthOfSecond(8).inverse() * pose(74.0, 0.0, 0.0);
  EXPECT_TRUE(tracker.agrees(same_pass, database, false));
}

TEST(LoopTracking, AKeyframeOfAnotherSessionThanTheAnchorsQueryIsNotPredicted) {
  TwoSessions s{Config()};
  LoopTracker tracker;
  tracker.anchor(s.loop(5, 40));
  // First-session keyframe 45 is not in the anchor query's session: its odometry says nothing.
  EXPECT_FALSE(tracker.predict(s.database, 45, s.database.size()));
}

TEST(LoopTracking, ATrackedLoopAgreesWithTheAnchorOnlyWhereTheOdometryPutsIt) {
  TwoSessions s{Config()};
  LoopTracker tracker;
  EXPECT_FALSE(tracker.agrees(s.loop(8, 37), s.database, false));  // no anchor yet
  tracker.anchor(s.loop(5, 40));
  EXPECT_TRUE(tracker.agrees(s.loop(8, 37), s.database, true));
  EXPECT_TRUE(tracker.agrees(s.loop(8, 37, 0.5), s.database, true));
  EXPECT_FALSE(tracker.agrees(s.loop(8, 37, 3.0), s.database, true));
  // The drift allowance (consistency_drift per metre of path: 12 m here) only without `strict`.
  EXPECT_FALSE(tracker.agrees(s.loop(8, 37, 1.3), s.database, true));
  EXPECT_TRUE(tracker.agrees(s.loop(8, 37, 1.3), s.database, false));
}

TEST(LoopTracking, APredictionLooksOnlyNearTheAnchorsMatchHoweverLongTheSession) {
  // One session driving a 400 m loop again and again (a keyframe every 2 m), a verified loop from the
  // last lap into the lap before as the anchor. The prediction must find the previous lap's keyframe
  // at the predicted spot, never an earlier lap's, and cost the same after 500 laps as after 10: only
  // the keyframes near the anchor's match along the path are looked at, not the whole session.
  Config config;
  config.num_rings = 2;  // a tiny grid: many keyframes cheaply (only poses and paths matter here)
  config.num_sectors = 3;
  const Descriptor d = makeDescriptor(test::streetScene(5), config);
  constexpr int kPerLap = 200;
  const double radius = 400.0 / (2.0 * M_PI);
  auto onLoop = [&](int k) {
    const double angle = 2.0 * M_PI * (k % kPerLap) / kPerLap;
    return pose(radius * std::cos(angle), radius * std::sin(angle), angle * 180.0 / M_PI + 90.0);
  };
  // Seconds per prediction (the best of five runs of 200) and the keyframes predicted.
  auto measure = [&](int laps, std::vector<std::size_t>* predicted) {
    Database database(config);
    const int n = laps * kPerLap;
    for (int k = 0; k < n; ++k) {
      KeyframeInfo info;
      info.stamp = k;
      info.pose = onLoop(k);
      EXPECT_TRUE(database.add(info, d));
    }
    Loop anchor;
    anchor.query = static_cast<std::size_t>(n - 30);
    anchor.match = anchor.query - kPerLap;
    anchor.verified = true;
    anchor.verification.accepted = true;
    anchor.verification.relative = Eigen::Isometry3d::Identity();  // the same place, a lap apart
    LoopTracker tracker;
    tracker.anchor(anchor);
    double best = 1e9;
    for (int run = 0; run < 5; ++run) {
      predicted->clear();
      const auto start = std::chrono::steady_clock::now();
      for (int i = 0; i < 200; ++i) {
        const std::size_t query = anchor.query + 1 + static_cast<std::size_t>(i % 20);
        const auto p = tracker.predict(database, query, database.size() - 50);
        predicted->push_back(p ? p->index : static_cast<std::size_t>(-1));
      }
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 200);
    }
    for (int i = 0; i < 20; ++i) {
      EXPECT_EQ((*predicted)[i], anchor.match + 1 + i) << "query " << anchor.query + 1 + i << " of " << n;
    }
    return best;
  };
  std::vector<std::size_t> short_run, long_run;
  const double short_seconds = measure(10, &short_run);
  const double long_seconds = measure(500, &long_run);
  std::printf("prediction: %.2f us after 2,000 keyframes, %.2f us after 100,000\n", short_seconds * 1e6,
              long_seconds * 1e6);
  // Scanning the session would make it 50 times slower; allow for a loaded machine.
  EXPECT_LT(long_seconds, 5.0 * short_seconds + 20e-6);
}

}  // namespace
}  // namespace scan_context_loop
