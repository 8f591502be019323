// The stamps the database keeps for the node: a ROS stamp comes back to the nanosecond, a keyframe of
// another origin (no tag, or a tag that is no stamp) as its stamp in seconds.
#include <limits>

#include <gtest/gtest.h>

#include "shared/stored_keyframe.h"

namespace scan_context_loop {
namespace {

TEST(StoredKeyframe, StampComesBackToTheNanosecond) {
  // At today's Unix times a double holds a stamp to about 0.2 us: seconds alone lose the last digits.
  bool seconds_lose_some = false;
  for (std::uint32_t nsec : {0u, 1u, 123456789u, 999999999u, 500000001u, 333333333u}) {
    const ros::Time stamp(1700000000u, nsec);
    KeyframeInfo info;
    setKeyframeStamp(stamp, &info);
    EXPECT_EQ(info.stamp, stamp.toSec());
    EXPECT_EQ(keyframeStamp(info), stamp) << nsec;
    seconds_lose_some = seconds_lose_some || ros::Time(info.stamp) != stamp;
  }
  EXPECT_TRUE(seconds_lose_some);
  // A bag's time from 0.
  const ros::Time early(12u, 345678901u);
  KeyframeInfo info;
  setKeyframeStamp(early, &info);
  EXPECT_EQ(keyframeStamp(info), early);
}

TEST(StoredKeyframe, WithoutAStampInTheTagTheSecondsAreTaken) {
  KeyframeInfo info;
  info.stamp = 1700000000.25;
  EXPECT_EQ(keyframeStamp(info), ros::Time(1700000000.25));  // tag -1: unset
  info.tag = 42;                                             // the evaluator's frame index
  EXPECT_EQ(keyframeStamp(info), ros::Time(1700000000.25));
  info.tag = 1700000000250000000 + 2000;  // nanoseconds 2 us off the stamp: not its stamp
  EXPECT_EQ(keyframeStamp(info), ros::Time(1700000000.25));
  info.tag = 1700000000250000000 + 500;  // within a microsecond: the stamp exactly
  EXPECT_EQ(keyframeStamp(info), ros::Time(1700000000u, 250000500u));
}

TEST(StoredKeyframe, StampOutOfRosTimeIsZero) {
  KeyframeInfo info;
  for (double stamp : {-1.0, 5e9, std::numeric_limits<double>::quiet_NaN()}) {
    info.stamp = stamp;
    info.tag = -1;
    EXPECT_TRUE(keyframeStamp(info).isZero()) << stamp;
  }
}

TEST(StoredKeyframe, PoseOrIdentity) {
  Keyframe keyframe;
  EXPECT_TRUE(keyframePose(keyframe).isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(keyframePosition(keyframe), Eigen::Vector3d::Zero());
  keyframe.info.pose = Eigen::Isometry3d(Eigen::Translation3d(1.0, 2.0, 3.0));
  EXPECT_EQ(keyframePose(keyframe).translation(), Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_EQ(keyframePosition(keyframe), Eigen::Vector3d(1.0, 2.0, 3.0));
}

}  // namespace
}  // namespace scan_context_loop
