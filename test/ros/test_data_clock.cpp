// The data's time for the backend's tf: the newest stamp advanced by the clock's run, never back except
// at a jump of the data, and never the same stamp twice.
#include <gtest/gtest.h>

#include "shared/data_clock.h"

namespace scan_context_loop {
namespace {

const ros::Time kWall(1.7e9);  // the wall clock of a replay without --clock
const ros::Time kBag(1000.0);  // the bag's stamps

TEST(DataClock, FollowsTheDataNotTheClockInAReplayOnTheWallClock) {
  DataClock clock;
  EXPECT_FALSE(clock.started());
  EXPECT_EQ(clock.at(kWall), kWall);  // nothing seen yet: the clock itself
  clock.observe(kBag, kWall);
  EXPECT_TRUE(clock.started());
  EXPECT_NEAR((clock.at(kWall + ros::Duration(0.25)) - kBag).toSec(), 0.25, 1e-9);
  // A newer stamp moves it; one a little older (another topic, a little late) does not.
  clock.observe(kBag + ros::Duration(2.0), kWall + ros::Duration(1.0));
  EXPECT_NEAR((clock.at(kWall + ros::Duration(1.0)) - kBag).toSec(), 2.0, 1e-9);
  clock.observe(kBag + ros::Duration(1.5), kWall + ros::Duration(1.0));
  EXPECT_NEAR((clock.at(kWall + ros::Duration(1.5)) - kBag).toSec(), 2.5, 1e-9);
}

TEST(DataClock, IsTheClockItselfLive) {
  DataClock clock;
  clock.observe(kWall - ros::Duration(0.05), kWall);  // a message 50 ms old
  EXPECT_NEAR((clock.at(kWall + ros::Duration(3.0)) - kWall).toSec(), 2.95, 1e-6);
}

TEST(DataClock, NeverHandsOutTheSameStampTwice) {
  DataClock clock;
  clock.observe(kBag, kWall);
  ros::Time first, second;
  ASSERT_TRUE(clock.next(kWall, &first));
  EXPECT_EQ(first, kBag);
  EXPECT_FALSE(clock.next(kWall, &second));  // a paused replay: the clock stood still
  ASSERT_TRUE(clock.next(kWall + ros::Duration(0.1), &second));
  EXPECT_GT(second, first);
  // A clock that goes back (sim time restarted) adds nothing and hands out nothing older.
  EXPECT_FALSE(clock.next(kWall - ros::Duration(5.0), &second));
}

TEST(DataClock, RestartsWhenTheDataJumpBack) {
  DataClock clock;
  clock.observe(kBag + ros::Duration(600.0), kWall);  // the end of a bag
  ros::Time stamp;
  ASSERT_TRUE(clock.next(kWall, &stamp));
  const ros::Time later = kWall + ros::Duration(1.0);
  // Older by less than the limit: kept; by more (the bag again from its start): the clock restarts there.
  clock.observe(kBag + ros::Duration(600.0 - DataClock::kJumpBackSeconds * 0.5), later);
  EXPECT_NEAR((clock.at(later) - kBag).toSec(), 601.0, 1e-6);
  clock.observe(kBag, later);
  EXPECT_EQ(clock.at(later), kBag);
  ASSERT_TRUE(clock.next(later, &stamp));  // earlier than the last output, allowed after a jump
  EXPECT_EQ(stamp, kBag);
}

TEST(DataClock, IgnoresUnstampedMessages) {
  DataClock clock;
  clock.observe(ros::Time(), kWall);
  EXPECT_FALSE(clock.started());
}

}  // namespace
}  // namespace scan_context_loop
