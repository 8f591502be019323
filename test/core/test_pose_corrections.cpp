// Corrected keyframe poses: a session holding corrections is carried wholly into the corrected frame
// (corrected keyframes take theirs, the others the newest correction before them, or the first), and
// sessions without one keep their poses.
#include <gtest/gtest.h>

#include "scan_context_loop/core/pose_corrections.h"

namespace scan_context_loop {
namespace {

Eigen::Isometry3d poseAt(double x, double y, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, 0.2);
  return pose;
}

void expectNear(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, std::size_t i) {
  EXPECT_LT((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 1e-12) << "keyframe " << i;
}

/// Session 0: keyframes 0-3; session 1: 4-10, keyframe 7 without a pose.
std::vector<Keyframe> twoSessions() {
  std::vector<Keyframe> keyframes(11);
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    keyframes[i].session = i < 4 ? 0 : 1;
    if (i != 7) keyframes[i].info.pose = poseAt(3.0 * i, 0.1 * i * i, 0.05 * i);
  }
  return keyframes;
}

std::vector<const Keyframe*> pointers(const std::vector<Keyframe>& keyframes) {
  std::vector<const Keyframe*> out;
  for (const Keyframe& k : keyframes) out.push_back(&k);
  return out;
}

TEST(PoseCorrections, ASessionWithCorrectionsIsCarriedWhollyIntoTheCorrectedFrame) {
  const std::vector<Keyframe> keyframes = twoSessions();
  const Eigen::Isometry3d first = poseAt(5.0, -2.0, 0.3), second = poseAt(-1.0, 4.0, -0.2);
  PoseCorrections corrections;
  corrections[5] = first * *keyframes[5].info.pose;
  corrections[8] = second * *keyframes[8].info.pose;
  corrections[42] = poseAt(0, 0, 0);  // past the keyframes: ignored
  const auto poses = correctedSessionPoses(pointers(keyframes), corrections);
  ASSERT_EQ(poses.size(), keyframes.size());
  for (std::size_t i = 0; i < 4; ++i) EXPECT_FALSE(poses[i]) << "session 0 has no correction: keyframe " << i;
  // Before the first correction: the first's; the corrected keyframes: theirs; after one: the newest's.
  const std::vector<std::pair<std::size_t, Eigen::Isometry3d>> expected = {{4, first},  {5, first},  {6, first},
                                                                           {8, second}, {9, second}, {10, second}};
  for (const auto& [i, correction] : expected) {
    ASSERT_TRUE(poses[i]) << "keyframe " << i;
    expectNear(*poses[i], correction * *keyframes[i].info.pose, i);
  }
  EXPECT_FALSE(poses[7]) << "a keyframe without a pose stays without";
}

TEST(PoseCorrections, ACorrectedKeyframeWithoutAnOdometryPoseKeepsItsPoseButMovesNoOther) {
  const std::vector<Keyframe> keyframes = twoSessions();
  const Eigen::Isometry3d shift = poseAt(1.0, 1.0, 0.1);
  PoseCorrections corrections;
  corrections[7] = poseAt(9.0, 9.0, 0.0);
  corrections[9] = shift * *keyframes[9].info.pose;
  const auto poses = correctedSessionPoses(pointers(keyframes), corrections);
  ASSERT_TRUE(poses[7]);
  expectNear(*poses[7], corrections[7], 7);
  for (std::size_t i : {4, 5, 6, 8, 9, 10}) {
    ASSERT_TRUE(poses[i]) << i;
    expectNear(*poses[i], shift * *keyframes[i].info.pose, i);
  }
}

TEST(PoseCorrections, NoCorrectionsChangeNothing) {
  const std::vector<Keyframe> keyframes = twoSessions();
  for (const auto& pose : correctedSessionPoses(pointers(keyframes), PoseCorrections())) EXPECT_FALSE(pose);
  EXPECT_TRUE(correctedSessionPoses({}, PoseCorrections{{0, poseAt(1, 2, 3)}}).empty());
}

}  // namespace
}  // namespace scan_context_loop
