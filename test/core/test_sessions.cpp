// Sessions: time going backwards starts a new session, on evidence only (several keyframes in a row, or
// an odometry jump), so a single bad stamp never splits one; earlier sessions stay and are always
// candidates.
#include <gtest/gtest.h>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

KeyframeInfo placeAt(double stamp, double x, double y = 0.0) {
  KeyframeInfo info;
  info.stamp = stamp;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 0.0);
  info.pose = pose;
  return info;
}

Config descriptorOnlyKeepingRecent() {
  Config c;
  c.verification.enabled = false;
  c.exclude_recent_frames = 50;
  return c;
}

/// Session 1: `places` streets, 10 m apart, at stamps 100, 101, ...
void firstSession(KeyframePipeline* pipeline, int places) {
  for (int i = 0; i < places; ++i) {
    const Detection d = pipeline->process(viewOf(test::streetScene(100 + i)), placeAt(100.0 + i, 10.0 * i));
    ASSERT_TRUE(d.accepted) << d.error;
  }
}

TEST(Sessions, AJumpBackInTimeStartsASessionWhoseKeyframesFindTheEarlierOnes) {
  KeyframePipeline pipeline(descriptorOnlyKeepingRecent());
  firstSession(&pipeline, 5);
  // The same streets again: stamps from 0 (a bag played again), another odometry frame far away. The
  // recent-keyframe window (50) would hide all five, and the odometry gate (20 m) would too, within one
  // session.
  const auto again = test::rotateTranslate(test::streetScene(102), 3.0 * M_PI / 180.0);
  const Detection d = pipeline.process(viewOf(again), placeAt(0.5, 5000.0, -300.0));
  ASSERT_TRUE(d.accepted) << d.error;
  EXPECT_TRUE(d.new_session);
  EXPECT_EQ(pipeline.detector().database().session(), 1u);
  EXPECT_EQ(pipeline.detector().database().sessionStart(), 5u);
  EXPECT_EQ(pipeline.detector().database().keyframe(5).session, 1u);
  EXPECT_EQ(pipeline.detector().database().keyframe(4).session, 0u);
  EXPECT_DOUBLE_EQ(pipeline.detector().database().keyframe(5).path_length, 0.0);
  ASSERT_EQ(d.loops.size(), 1u);
  EXPECT_EQ(d.loops.front().match, 2u);
  EXPECT_EQ(d.query.eligible, 5u);

  // Within the new session, stamps go on from the new start and the window applies again.
  const Detection next = pipeline.process(viewOf(test::streetScene(7)), placeAt(1.5, 5010.0, -300.0));
  EXPECT_TRUE(next.accepted) << next.error;
  EXPECT_FALSE(next.new_session);
  EXPECT_EQ(next.query.eligible, 5u) << "the new session's own keyframe is still recent";
}

TEST(Sessions, ASingleStampBackIsRefusedAndTheSessionKeepsItsWindowsAndGate) {
  KeyframePipeline pipeline(descriptorOnlyKeepingRecent());
  firstSession(&pipeline, 5);
  // Stamped 5 s back, the odometry where it was: a bad stamp, not another run. Twice, with a normal
  // keyframe between: glitches apart do not add up to a new session.
  for (int glitch = 0; glitch < 2; ++glitch) {
    const double stamp = 104.0 + 2.0 * glitch;
    const KeyframeInfo back = placeAt(stamp - 5.0, 40.0 + 10.0 * glitch);  // at the last keyframe's pose
    const Detection d = pipeline.process(viewOf(test::streetScene(20 + glitch)), back);
    EXPECT_FALSE(d.accepted);
    EXPECT_FALSE(d.new_session);
    EXPECT_NE(d.error.find("out of order"), std::string::npos) << d.error;
    EXPECT_EQ(pipeline.detector().database().session(), 0u);
    const KeyframeInfo on = placeAt(stamp + 1.0, 50.0 + 10.0 * glitch);
    const Detection next = pipeline.process(viewOf(test::streetScene(30 + glitch)), on);
    ASSERT_TRUE(next.accepted) << next.error;
    EXPECT_FALSE(next.new_session);
  }
  EXPECT_EQ(pipeline.detector().database().size(), 7u);
  EXPECT_EQ(pipeline.detector().database().session(), 0u);
  // The place of keyframe 2 again: within the session the recent-keyframe window (50) hides it.
  const auto again = test::rotateTranslate(test::streetScene(102), 3.0 * M_PI / 180.0);
  const Detection d = pipeline.process(viewOf(again), placeAt(108.0, 80.0));
  ASSERT_TRUE(d.accepted) << d.error;
  EXPECT_EQ(d.query.eligible, 0u);
  EXPECT_TRUE(d.loops.empty());

  // And the odometry gate: without the window, keyframe 2 (60 m away by odometry) is gated out.
  Config c = descriptorOnlyKeepingRecent();
  c.exclude_recent_frames = 0;
  KeyframePipeline gated(c);
  firstSession(&gated, 5);
  EXPECT_FALSE(gated.process(viewOf(test::streetScene(20)), placeAt(99.0, 40.0)).accepted);
  const Detection g = gated.process(viewOf(again), placeAt(105.0, 80.0));
  ASSERT_TRUE(g.accepted) << g.error;
  EXPECT_EQ(g.query.eligible, 5u);
  EXPECT_TRUE(g.loops.empty()) << "matched " << g.loops.front().match;
}

TEST(Sessions, ABagPlayedAgainFromWhereItEndedStartsASessionAtTheThirdKeyframe) {
  KeyframePipeline pipeline(descriptorOnlyKeepingRecent());
  firstSession(&pipeline, 5);
  // The drive ended where it began (keyframe 4 at x = 40): replayed, its stamps start again from 0 but
  // the odometry does not jump. Three keyframes in a row, in order, make a new session.
  for (int k = 0; k < 2; ++k) {
    const Detection d = pipeline.process(viewOf(test::streetScene(100 + k)), placeAt(0.5 + k, 40.0 + k));
    EXPECT_FALSE(d.accepted);
    EXPECT_NE(d.error.find("out of order"), std::string::npos) << d.error;
  }
  EXPECT_EQ(pipeline.detector().database().session(), 0u);
  const auto again = test::rotateTranslate(test::streetScene(102), 3.0 * M_PI / 180.0);
  const Detection d = pipeline.process(viewOf(again), placeAt(2.5, 42.0));
  ASSERT_TRUE(d.accepted) << d.error;
  EXPECT_TRUE(d.new_session);
  EXPECT_EQ(pipeline.detector().database().session(), 1u);
  EXPECT_EQ(pipeline.detector().database().sessionStart(), 5u);
  EXPECT_EQ(d.query.eligible, 5u);
  ASSERT_EQ(d.loops.size(), 1u);
  EXPECT_EQ(d.loops.front().match, 2u);
  const Detection next = pipeline.process(viewOf(test::streetScene(103)), placeAt(3.5, 44.0));
  ASSERT_TRUE(next.accepted) << next.error;
  EXPECT_FALSE(next.new_session);
  EXPECT_EQ(pipeline.detector().database().keyframe(6).session, 1u);
}

TEST(Sessions, AFarFutureStampIsRefusedAndTheNextOnesStayInTheSession) {
  KeyframePipeline pipeline(descriptorOnlyKeepingRecent());
  firstSession(&pipeline, 5);
  const Detection far = pipeline.process(viewOf(test::streetScene(20)), placeAt(104.0 + 1e9, 45.0));
  EXPECT_FALSE(far.accepted);
  EXPECT_NE(far.error.find("far ahead"), std::string::npos) << far.error;
  for (int k = 0; k < 4; ++k) {
    const Detection d = pipeline.process(viewOf(test::streetScene(30 + k)), placeAt(104.5 + k, 50.0 + 10.0 * k));
    ASSERT_TRUE(d.accepted) << d.error;
    EXPECT_FALSE(d.new_session);
  }
  EXPECT_EQ(pipeline.detector().database().size(), 9u);
  EXPECT_EQ(pipeline.detector().database().session(), 0u);

  // Clouds back after more than max_stamp_step without any: three in a row take the new time, same session.
  for (int k = 0; k < 3; ++k) {
    const Detection d = pipeline.process(viewOf(test::streetScene(40 + k)), placeAt(2e7 + k, 90.0 + 10.0 * k));
    EXPECT_EQ(d.accepted, k == 2) << d.error;
    EXPECT_FALSE(d.new_session);
  }
  EXPECT_EQ(pipeline.detector().database().size(), 10u);
  EXPECT_EQ(pipeline.detector().database().session(), 0u);
}

TEST(Sessions, TheCallerCanStartASessionWhoseStampsGoOn) {
  KeyframePipeline pipeline(descriptorOnlyKeepingRecent());
  pipeline.startSession();  // nothing to close yet
  firstSession(&pipeline, 5);
  EXPECT_EQ(pipeline.detector().database().session(), 0u);
  // Another run whose stamps carry on (another day's recording): without the new session the window
  // and the odometry gate would hide the first five.
  pipeline.startSession();
  pipeline.startSession();  // the new session is still empty: no second one
  const auto again = test::rotateTranslate(test::streetScene(102), 3.0 * M_PI / 180.0);
  const Detection d = pipeline.process(viewOf(again), placeAt(5000.0, 5000.0, -300.0));
  ASSERT_TRUE(d.accepted) << d.error;
  EXPECT_EQ(pipeline.detector().database().session(), 1u);
  EXPECT_EQ(pipeline.detector().database().keyframe(5).session, 1u);
  EXPECT_EQ(d.query.eligible, 5u);
  ASSERT_EQ(d.loops.size(), 1u);
  EXPECT_EQ(d.loops.front().match, 2u);
}

TEST(Sessions, ASmallStepBackIsRefusedAsOutOfOrder) {
  KeyframePipeline pipeline(descriptorOnlyKeepingRecent());
  firstSession(&pipeline, 3);
  const Detection d = pipeline.process(viewOf(test::streetScene(9)), placeAt(101.5, 50.0));
  EXPECT_FALSE(d.accepted);
  EXPECT_FALSE(d.new_session);
  EXPECT_NE(d.error.find("earlier"), std::string::npos) << d.error;
  EXPECT_EQ(pipeline.detector().database().size(), 3u);
  EXPECT_EQ(pipeline.detector().database().session(), 0u);
}

TEST(Sessions, WithoutNewSessionsEveryStepBackIsRefused) {
  Config c = descriptorOnlyKeepingRecent();
  c.new_session_jump = 0.0;
  KeyframePipeline pipeline(c);
  firstSession(&pipeline, 3);
  const Detection d = pipeline.process(viewOf(test::streetScene(9)), placeAt(1.0, 50.0));
  EXPECT_FALSE(d.accepted);
  EXPECT_EQ(pipeline.detector().database().size(), 3u);
}

TEST(Sessions, TheOdometryGateAndPathLengthStayWithinASession) {
  Config c = descriptorOnlyKeepingRecent();
  c.exclude_recent_frames = 0;
  Database db(c);
  Descriptor d = makeDescriptor(viewOf(test::streetScene(1)), c);
  ASSERT_TRUE(db.add(placeAt(10.0, 0.0), d));
  ASSERT_TRUE(db.add(placeAt(11.0, 30.0), d));
  EXPECT_DOUBLE_EQ(db.keyframe(1).path_length, 30.0);
  // Same session, 1000 m from both by odometry: the gate (20 m + 10 % of the path) excludes them.
  EXPECT_TRUE(db.query(d, placeAt(12.0, 1000.0)).candidates.empty());
  db.startSession();
  db.startSession();  // no keyframe yet: still session 1
  EXPECT_EQ(db.session(), 1u);
  // Another session: its odometry frame is unrelated, so nothing is gated.
  EXPECT_EQ(db.query(d, placeAt(1.0, 1000.0)).candidates.size(), 2u);
  ASSERT_TRUE(db.add(placeAt(1.0, 1000.0), d));
  EXPECT_DOUBLE_EQ(db.keyframe(2).path_length, 0.0);
  EXPECT_FALSE(db.sameSession(1, 2));
  EXPECT_TRUE(db.sameSession(0, 1));
}

TEST(Sessions, AppendedSessionsFollowTheRunningOnesInOrderOrNothingChanges) {
  Config c = descriptorOnlyKeepingRecent();
  c.exclude_recent_frames = 0;
  Database db(c);
  const Descriptor d = makeDescriptor(viewOf(test::streetScene(1)), c);
  ASSERT_TRUE(db.add(placeAt(10.0, 0.0), d));
  const auto keyframes = [&](std::vector<std::uint32_t> sessions, std::vector<double> stamps) {
    std::vector<Keyframe> out;
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      Keyframe k;
      k.info = placeAt(stamps[i], 0.0);
      k.descriptor = d;
      k.session = sessions[i];
      out.push_back(k);
    }
    return out;
  };
  std::string error;
  EXPECT_FALSE(db.appendSessions(keyframes({0, 2}, {1.0, 2.0}), &error));
  EXPECT_NE(error.find("session 2 follows session 0"), std::string::npos) << error;
  EXPECT_FALSE(db.appendSessions(keyframes({1}, {1.0}), &error));
  EXPECT_NE(error.find("not 0"), std::string::npos) << error;
  EXPECT_FALSE(db.appendSessions(keyframes({0, 0}, {5.0, 4.0}), &error));
  EXPECT_NE(error.find("keyframe 1: keyframe stamp 4 is earlier"), std::string::npos) << error;
  Descriptor small = d;
  small.sector_key.pop_back();
  auto bad_grid = keyframes({0}, {1.0});
  bad_grid[0].descriptor = small;
  EXPECT_FALSE(db.appendSessions(bad_grid, &error));
  EXPECT_NE(error.find("grid size"), std::string::npos) << error;
  EXPECT_EQ(db.size(), 1u);
  EXPECT_EQ(db.session(), 0u);

  // Stamps restart in a new session; the appended ones follow session 0 and a new one begins.
  ASSERT_TRUE(db.appendSessions(keyframes({0, 0, 1}, {5.0, 6.0, 1.0}), &error)) << error;
  ASSERT_EQ(db.size(), 4u);
  EXPECT_EQ(db.keyframe(1).session, 1u);
  EXPECT_EQ(db.keyframe(3).session, 2u);
  EXPECT_EQ(db.session(), 3u);
  EXPECT_EQ(db.sessionStart(), 4u);
  EXPECT_EQ(db.indexedCount(), 4u);
  // A query at the new session's start sees all four, whatever its stamp.
  EXPECT_EQ(db.query(d, placeAt(0.0, 0.0)).eligible, 4u);
}

}  // namespace
}  // namespace scan_context_loop
