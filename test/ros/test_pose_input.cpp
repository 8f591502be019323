// Odometry and tf orientations: unit quaternions are taken (normalised within the tolerance), others
// refused. No ROS master needed.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "shared/pose_input.h"

namespace scan_context_loop {
namespace {

geometry_msgs::Pose poseWith(double x, double y, double z, double w) {
  geometry_msgs::Pose msg;
  msg.position.x = 1.0;
  msg.position.y = -2.0;
  msg.position.z = 0.5;
  msg.orientation.x = x;
  msg.orientation.y = y;
  msg.orientation.z = z;
  msg.orientation.w = w;
  return msg;
}

bool isRotation(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d r = pose.linear();
  return (r.transpose() * r).isIdentity(1e-12) && r.determinant() > 0.0;
}

TEST(PoseInput, AUnitOrSlightlyOffQuaternionIsTakenAndNormalised) {
  const double s = std::sin(0.2), c = std::cos(0.2);  // 0.4 rad about z
  Eigen::Isometry3d pose;
  std::string why;
  ASSERT_TRUE(poseFromMsg(poseWith(0.0, 0.0, s, c), &pose, &why)) << why;
  EXPECT_TRUE(isRotation(pose));
  EXPECT_NEAR(std::atan2(pose(1, 0), pose(0, 0)), 0.4, 1e-12);
  EXPECT_DOUBLE_EQ(pose.translation().y(), -2.0);
  const double off = 1.0 + 0.5 * kQuaternionNormTolerance;
  ASSERT_TRUE(poseFromMsg(poseWith(0.0, 0.0, off * s, off * c), &pose, &why)) << why;
  EXPECT_TRUE(isRotation(pose)) << pose.linear();
  EXPECT_NEAR(std::atan2(pose(1, 0), pose(0, 0)), 0.4, 1e-12);
}

TEST(PoseInput, AZeroNaNOrBadlyScaledQuaternionIsRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double off = 1.0 + 2.0 * kQuaternionNormTolerance;
  for (const auto& msg : {poseWith(0.0, 0.0, 0.0, 0.0), poseWith(nan, 0.0, 0.0, 1.0), poseWith(0.0, 0.0, 0.0, 2.0),
                          poseWith(0.0, 0.0, 0.0, off)}) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::string why;
    EXPECT_FALSE(poseFromMsg(msg, &pose, &why)) << msg;
    EXPECT_NE(why.find("quaternion"), std::string::npos) << why;
    EXPECT_TRUE(pose.isApprox(Eigen::Isometry3d::Identity())) << "left alone";
  }
}

TEST(PoseInput, ANonFinitePositionIsRefused) {
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), HUGE_VAL, -HUGE_VAL}) {
    geometry_msgs::Pose msg = poseWith(0.0, 0.0, 0.0, 1.0);
    msg.position.y = bad;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::string why;
    EXPECT_FALSE(poseFromMsg(msg, &pose, &why));
    EXPECT_NE(why.find("position"), std::string::npos) << why;
    EXPECT_TRUE(pose.isApprox(Eigen::Isometry3d::Identity())) << "left alone";
  }
}

TEST(PoseInput, TfTransformsAreCheckedAlike) {
  geometry_msgs::Transform msg;
  msg.translation.x = 3.0;
  msg.rotation.w = 1.0 - 0.5 * kQuaternionNormTolerance;
  Eigen::Isometry3d pose;
  std::string why;
  ASSERT_TRUE(poseFromMsg(msg, &pose, &why)) << why;
  EXPECT_TRUE(isRotation(pose));
  EXPECT_DOUBLE_EQ(pose.translation().x(), 3.0);
  msg.rotation.w = 0.0;
  EXPECT_FALSE(poseFromMsg(msg, &pose, &why));
  EXPECT_NE(why.find("quaternion"), std::string::npos) << why;
}

}  // namespace
}  // namespace scan_context_loop
