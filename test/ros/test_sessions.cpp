// rostest: a drive played twice with the same stamps, as `rosbag play` twice would: the node starts a
// second session instead of refusing the keyframes (from the third on), and closes verified loops into
// the first.
#include <gtest/gtest.h>

#include "harness.h"

namespace scan_context_loop {
namespace test {
namespace {

TEST(Sessions, ADriveReplayedWithTheSameStampsClosesLoopsIntoTheFirstPass) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(30.0));
  const Drive drive = blockDrive(true, 7);
  harness.publish(drive, 0, drive.truth.size(), 12.0);
  harness.settle(3.0, 40.0);
  const std::size_t first_pass = harness.loops().size();
  for (const auto& loop : harness.loops()) {
    EXPECT_EQ(loop.query_session, 0u);
    EXPECT_EQ(loop.match_session, 0u);
  }
  // Again, same stamps: the drive ends where it began, so only the stamps say another pass begins, and
  // a new session needs three keyframes in a row stamped back (keyframes.h): the first two are refused,
  // every one from the third on is a new keyframe of session 1.
  constexpr std::size_t kRefusedAtTheStart = 2;
  harness.publish(drive, 0, drive.truth.size(), 12.0);
  harness.settle(3.0, 40.0);
  const auto loops = harness.loops();
  std::size_t across = 0;
  for (std::size_t i = first_pass; i < loops.size(); ++i) {
    const auto& loop = loops[i];
    EXPECT_EQ(loop.query_session, 1u);
    EXPECT_TRUE(loop.verified);
    const int q = keyframeAt(drive, harness.base, loop.query_stamp);
    const int m = keyframeAt(drive, harness.base, loop.match_stamp);
    ASSERT_GE(q, static_cast<int>(kRefusedAtTheStart));
    ASSERT_GE(m, 0);
    EXPECT_EQ(loop.query_id, drive.truth.size() + q - kRefusedAtTheStart)
        << "every keyframe of the first pass, and of the second from its third on, is kept";
    expectTrueLoop(drive, q, m, loop);
    if (loop.match_session == 0) ++across;
  }
  // The first pass closed its loops only on the second lap; the replay finds its places from the start.
  EXPECT_GE(across, drive.truth.size() / 4) << loops.size() - first_pass << " loops in the second pass";
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_sessions"); }
