// Pairwise consistency of loops through the odometry (ConsistencyFilter, loopsAgree).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/consistency.h"
#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/detector.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

/// A drive along x with a keyframe every 2 m, odometry poses given, and the descriptor of one scene
/// (the consistency check reads only poses and path lengths).
struct Drive {
  explicit Drive(Config c) : config(c), database(c) {
    const Descriptor d = makeDescriptor(test::streetScene(5), config);
    for (int k = 0; k < 60; ++k) {
      KeyframeInfo info;
      info.stamp = k;
      info.pose = pose(k);
      EXPECT_TRUE(database.add(info, d));
    }
  }
  static Eigen::Isometry3d pose(int k) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(2.0 * k, 0.0, 0.0);
    return p;
  }
  /// A loop whose relative pose is the odometry's, moved by (dx, dy) and turned by yaw_deg.
  static Loop loop(int query, int match, double dx = 0.0, double dy = 0.0, double yaw_deg = 0.0) {
    Loop l;
    l.query = query;
    l.match = match;
    l.verified = true;
    Eigen::Isometry3d error = Eigen::Isometry3d::Identity();
    error.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    error.translation() = Eigen::Vector3d(dx, dy, 0.0);
    l.verification.relative = pose(query).inverse() * pose(match) * error;
    return l;
  }
  Config config;
  Database database;
};

/// Feeds loops to a ConsistencyFilter one keyframe at a time; `confirmed` holds the last step's output.
struct Stepper {
  explicit Stepper(const Drive& d) : drive(d), filter(d.config) {}
  void operator()(const Loop& loop) {
    confirmed.clear();
    filter.advance(loop.query, &dropped);
    filter.offer(loop, drive.database, &confirmed);
  }
  const Drive& drive;
  ConsistencyFilter filter;
  std::vector<Loop> confirmed, dropped;
};

Config checked() {
  Config c;
  c.verification.enabled = true;
  c.consistency_min_support = 1;
  c.consistency_window = 5;
  return c;
}

TEST(Consistency, LoopsAgreeWhenTheCycleClosesWithinTheTolerances) {
  Drive drive(checked());
  double t = 0.0, r = 0.0;
  EXPECT_TRUE(loopsAgree(Drive::loop(40, 2), Drive::loop(41, 3), drive.database, &t, &r));
  EXPECT_NEAR(t, 0.0, 1e-9);
  // Half a metre off: inside 1 m.
  EXPECT_TRUE(loopsAgree(Drive::loop(40, 2, 0.5), Drive::loop(41, 3), drive.database, &t));
  EXPECT_NEAR(t, 0.5, 1e-9);
  // 3 m off, 1.5 deg: too far for keyframes 2 m apart (1 m + 5% of 4 m of path).
  EXPECT_FALSE(loopsAgree(Drive::loop(40, 2, 3.0), Drive::loop(41, 3), drive.database));
  // Turned by 5 deg: over 2 deg.
  EXPECT_FALSE(loopsAgree(Drive::loop(40, 2, 0.0, 0.0, 5.0), Drive::loop(41, 3), drive.database, &t, &r));
  EXPECT_NEAR(r, 5.0 * M_PI / 180.0, 1e-6);
  // The drift allowance grows with the path the cycle runs along: 3 m off between loops 20 keyframes
  // (40 m + 40 m of path) apart is within 1 m + 5% of 80 m.
  EXPECT_TRUE(loopsAgree(Drive::loop(40, 2, 3.0), Drive::loop(20, 22), drive.database));
  // A loop to the wrong place (it claims keyframe 20 sits where 2 is) agrees with nothing true.
  Loop wrong = Drive::loop(41, 3);
  wrong.match = 20;
  EXPECT_FALSE(loopsAgree(Drive::loop(40, 2), wrong, drive.database));
}

TEST(Consistency, KeyframesWithoutPosesNeverAgree) {
  Config c = checked();
  Database database(c);
  const Descriptor d = makeDescriptor(test::streetScene(5), c);
  for (int k = 0; k < 10; ++k) {
    KeyframeInfo info;
    info.stamp = k;
    ASSERT_TRUE(database.add(info, d));
  }
  EXPECT_FALSE(loopsAgree(Drive::loop(8, 1), Drive::loop(9, 2), database));
}

TEST(Consistency, FilterReportsARunOfAgreeingLoopsFromItsSecondLoopOnAndDropsALoneWrongOne) {
  Drive drive(checked());
  Stepper step(drive);
  ConsistencyFilter& filter = step.filter;
  std::vector<Loop>& confirmed = step.confirmed;
  std::vector<Loop>& dropped = step.dropped;
  step(Drive::loop(40, 2));  // a true loop: waits for support
  EXPECT_TRUE(confirmed.empty());
  EXPECT_EQ(filter.waiting(), 1u);
  Loop wrong = Drive::loop(41, 3);  // claims keyframe 20 stands where 3 does
  wrong.match = 20;
  step(wrong);
  EXPECT_TRUE(confirmed.empty());
  EXPECT_EQ(filter.waiting(), 2u);
  step(Drive::loop(42, 4));  // agrees with the first: both are reported, the earlier one first
  ASSERT_EQ(confirmed.size(), 2u);
  EXPECT_EQ(confirmed[0].query, 40u);
  EXPECT_EQ(confirmed[1].query, 42u);
  EXPECT_EQ(confirmed[1].support, 1);
  step(Drive::loop(43, 5));  // agrees with both at once
  ASSERT_EQ(confirmed.size(), 1u);
  EXPECT_EQ(confirmed[0].support, 2);
  EXPECT_TRUE(dropped.empty());
  // The wrong loop's wait ends after consistency_window keyframes, unconfirmed.
  filter.advance(47, &dropped);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].query, 41u);
  EXPECT_EQ(dropped[0].match, 20u);
  // With the consistency check's verdict: the support it had against the support it needed.
  EXPECT_FALSE(dropped[0].verified);
  EXPECT_FALSE(dropped[0].verification.accepted);
  EXPECT_EQ(dropped[0].verification.rejected_by, "consistency");
  EXPECT_EQ(dropped[0].verification.rejection_value, 0.0);
  EXPECT_EQ(dropped[0].verification.rejection_limit, 1.0);
  EXPECT_EQ(dropped[0].verification.reason, "no consistent loop within consistency_window keyframes");
  EXPECT_EQ(filter.waiting(), 0u);
  // Loops further apart than the window are not compared: a true loop much later waits again.
  step(Drive::loop(55, 17));
  EXPECT_TRUE(confirmed.empty());
  EXPECT_EQ(filter.waiting(), 1u);
}

/// A loop whose registration passed every test but the full overlap (VerificationResult::needs_support).
Loop needingSupport(const Loop& loop) {
  Loop l = loop;
  l.verified = false;
  l.verification.needs_support = true;
  return l;
}

TEST(Consistency, ALoopThatNeedsSupportIsConfirmedOnlyByAConfirmedFullLoopThatAgreesStrictly) {
  Drive drive(checked());
  Stepper step(drive);
  ConsistencyFilter& filter = step.filter;
  std::vector<Loop>& confirmed = step.confirmed;
  std::vector<Loop>& dropped = step.dropped;
  // Two loops that need support agree with each other, yet neither confirms the other.
  step(needingSupport(Drive::loop(40, 2)));
  step(needingSupport(Drive::loop(41, 3)));
  EXPECT_TRUE(confirmed.empty());
  // One full loop alone is not confirmed either: loops that need support are no support.
  step(Drive::loop(42, 4));
  EXPECT_TRUE(confirmed.empty());
  EXPECT_EQ(filter.waiting(), 3u);
  // A second full loop confirms the first; the confirmed loops then confirm the waiting ones that need
  // support, reported as verified.
  step(Drive::loop(43, 5));
  ASSERT_EQ(confirmed.size(), 4u);
  for (const Loop& l : confirmed) {
    EXPECT_TRUE(l.verified);
    EXPECT_TRUE(l.verification.accepted);
  }
  EXPECT_EQ(filter.waiting(), 0u);
  // Later ones that need support: confirmed at once when they land where the confirmed loops and the
  // odometry put them (0.5 m off)...
  step(needingSupport(Drive::loop(44, 6, 0.5)));
  ASSERT_EQ(confirmed.size(), 1u);
  EXPECT_EQ(confirmed[0].query, 44u);
  EXPECT_TRUE(confirmed[0].verified);
  // ... but not 1.5 m off, which the drift allowance would forgive between two full loops 8 m of
  // path apart on each side (1 m + 5% of 16 m).
  EXPECT_TRUE(loopsAgree(Drive::loop(45, 7, 1.05), Drive::loop(41, 3), drive.database));
  step(needingSupport(Drive::loop(45, 7, 1.05)));
  EXPECT_TRUE(confirmed.empty());
  filter.advance(56, &dropped);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].query, 45u);
}

TEST(Consistency, WithoutVerificationDescriptorMatchesAreReportedAtOnce) {
  Config c;
  ASSERT_GT(c.consistency_min_support, 0);  // on by default, but it only looks at verified loops
  c.verification.enabled = false;
  EXPECT_TRUE(c.validate().empty());
  c.exclude_recent_frames = 0;
  LoopDetector detector(c);
  KeyframeInfo info;
  info.pose = Eigen::Isometry3d::Identity();
  detector.process(viewOf(test::streetScene(9)), info);
  info.stamp = 1.0;
  const Detection d = detector.process(viewOf(test::streetScene(9)), info);
  ASSERT_EQ(d.loops.size(), 1u);
  EXPECT_EQ(d.loops[0].query, 1u);
  EXPECT_FALSE(d.loops[0].verified);
}

TEST(Consistency, VerifiedLoopWaitsForASecondOneThroughTheDetector) {
  Config c;
  c.exclude_recent_frames = 2;
  c.verification.enabled = true;
  LoopDetector detector(c);
  KeyframeInfo info;
  const auto feed = [&](std::uint32_t scene, double x) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = x;
    info.pose = pose;
    info.stamp += 1.0;
    // Each scene seen from the keyframe's own position (the street moves by -x in the sensor frame).
    return detector.process(viewOf(test::rotateTranslate(test::streetScene(scene), 0.0, 0.0, 0.0)), info);
  };
  feed(21, 0.0);
  feed(22, 30.0);
  feed(23, 60.0);
  feed(24, 90.0);
  // The drive comes back: 21 again (query 4), then 22 again (query 5), at the odometry positions of
  // the first visits, so both loops agree through the odometry.
  const Detection first = feed(21, 0.0);
  EXPECT_TRUE(first.verified);
  EXPECT_TRUE(first.loops.empty()) << "a lone verified loop waits for support";
  const Detection second = feed(22, 30.0);
  ASSERT_EQ(second.loops.size(), 2u);
  EXPECT_EQ(second.loops[0].query, 4u);
  EXPECT_EQ(second.loops[0].match, 0u);
  EXPECT_EQ(second.loops[1].query, 5u);
  EXPECT_EQ(second.loops[1].match, 1u);
  EXPECT_EQ(second.loops[1].support, 1);
}

}  // namespace
}  // namespace scan_context_loop

namespace scan_context_loop {
namespace {

/// A loop the odometry checks contradicted by `excess` times their allowance (it passed the geometry).
Loop contradicted(int query, int match, double excess, double dx = 0.0, double yaw_deg = 0.0) {
  Loop l = Drive::loop(query, match, dx, 0.0, yaw_deg);
  l.verified = false;
  l.verification.odometry_contradicted = true;
  l.verification.odometry_excess = excess;
  l.verification.rejected_by = "odometry_rotation";
  return l;
}

TEST(ConsistencyContradicted, NeedsOneSupportMoreAndOnlyFromLoopsLikeIt) {
  Config config;
  config.consistency_min_support = 1;
  const Drive drive(config);
  Stepper step(drive);
  // Two contradicted loops that agree: one support each, one short.
  step(contradicted(40, 10, 3.0));
  step(contradicted(41, 11, 3.0));
  EXPECT_TRUE(step.confirmed.empty());
  // A third confirms all three, without their rejection.
  step(contradicted(42, 12, 3.0));
  ASSERT_EQ(step.confirmed.size(), 3u);
  for (const Loop& l : step.confirmed) {
    EXPECT_TRUE(l.verified);
    EXPECT_TRUE(l.verification.rejected_by.empty());
  }
  // A loop the odometry agrees with is not confirmed by contradicted ones.
  Stepper other(drive);
  other(contradicted(40, 10, 3.0));
  other(contradicted(41, 11, 3.0));
  other(Drive::loop(42, 12));
  EXPECT_TRUE(
      std::none_of(other.confirmed.begin(), other.confirmed.end(), [](const Loop& l) { return l.query == 42; }));
}

TEST(ConsistencyContradicted, OnesDroppedShortOfTheirSupportSayTheyNeededOneMore) {
  Config config;
  config.consistency_min_support = 1;
  const Drive drive(config);
  Stepper step(drive);
  step(contradicted(40, 10, 3.0));
  step(contradicted(41, 11, 3.0));  // each supports the other: one support each, two needed
  EXPECT_TRUE(step.confirmed.empty());
  step.filter.advance(41 + config.consistency_window + 1, &step.dropped);
  ASSERT_EQ(step.dropped.size(), 2u);
  for (const Loop& l : step.dropped) {
    EXPECT_EQ(l.verification.rejected_by, "consistency");
    EXPECT_EQ(l.verification.rejection_value, 1.0);
    EXPECT_EQ(l.verification.rejection_limit, 2.0);
  }
}

TEST(ConsistencyContradicted, ALessContradictedLoopThatDisagreesHoldsItBack) {
  Config config;
  config.consistency_min_support = 1;
  const Drive drive(config);
  // A run of loops all 14 m off (a row of identical houses), agreeing with each other, which the
  // odometry contradicts more than a loop that disagrees with them.
  const auto run = [](Stepper* step) {
    for (int q = 41; q <= 44; ++q) (*step)(contradicted(q, q - 30, 15.0, 14.0));
  };
  Stepper alone(drive);
  run(&alone);
  EXPECT_FALSE(alone.filter.waiting() == 4u) << "on their own they confirm each other";
  Stepper step(drive);
  step(contradicted(40, 10, 1.5));
  std::size_t confirmed = 0;
  for (int q = 41; q <= 44; ++q) {
    step(contradicted(q, q - 30, 15.0, 14.0));
    confirmed += step.confirmed.size();
  }
  EXPECT_EQ(confirmed, 0u);
}

}  // namespace
}  // namespace scan_context_loop
