// Changing settings while running (KeyframePipeline::reconfigure, Setting::live).
#include <gtest/gtest.h>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/settings.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

KeyframeInfo along(double x, double stamp) {
  KeyframeInfo info;
  info.stamp = stamp;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = x;
  info.pose = pose;
  return info;
}

Config ungatedDescriptorOnly() {
  Config c;
  c.verification.enabled = false;
  c.exclude_recent_frames = 2;
  c.gate_odometry_distance = 0.0;
  c.gate_odometry_drift = 0.0;
  return c;
}

TEST(Reconfigure, RefusesSettingsThatShapeStoredDataAndKeepsTheOldOnes) {
  KeyframePipeline pipeline(ungatedDescriptorOnly());
  Config next = pipeline.config();
  next.num_rings = 30;
  next.distance_threshold = 0.1;
  next.verification.voxel_leaf = 0.5;
  const std::string error = pipeline.reconfigure(next);
  EXPECT_NE(error.find("num_rings"), std::string::npos) << error;
  EXPECT_NE(error.find("verify_voxel_leaf"), std::string::npos) << error;
  EXPECT_EQ(error.find("distance_threshold"), std::string::npos) << error;
  EXPECT_EQ(pipeline.config().num_rings, 20);
  EXPECT_DOUBLE_EQ(pipeline.config().distance_threshold, ungatedDescriptorOnly().distance_threshold);
}

TEST(Reconfigure, RefusesAnInvalidValue) {
  KeyframePipeline pipeline(ungatedDescriptorOnly());
  Config next = pipeline.config();
  next.distance_threshold = -1.0;
  EXPECT_NE(pipeline.reconfigure(next).find("distance_threshold"), std::string::npos);
  EXPECT_DOUBLE_EQ(pipeline.config().distance_threshold, ungatedDescriptorOnly().distance_threshold);
}

TEST(Reconfigure, ThresholdsApplyFromTheNextKeyframeAndTheDatabaseStays) {
  KeyframePipeline pipeline(ungatedDescriptorOnly());
  const auto place = test::streetScene(3);
  // The same place seen again, turned by half a sector: a small but non-zero descriptor distance.
  const auto again = test::rotateTranslate(place, 3.0 * M_PI / 180.0);
  double stamp = 0.0, x = 0.0;
  pipeline.process(viewOf(place), along(x, stamp += 1.0));
  for (std::uint32_t seed = 10; seed < 13; ++seed)
    pipeline.process(viewOf(test::streetScene(seed)), along(x += 3.0, stamp += 1.0));
  const Detection first = pipeline.process(viewOf(again), along(x += 3.0, stamp += 1.0));
  ASSERT_EQ(first.loops.size(), 1u);
  EXPECT_EQ(first.loops.front().match, 0u);
  const double distance = first.loops.front().alignment.distance;
  ASSERT_GT(distance, 0.0);

  // Below the distance of that match: the same revisit is no loop any more.
  Config strict = pipeline.config();
  strict.distance_threshold = 0.5 * distance;
  strict.verification.threshold = 0.5 * distance;
  ASSERT_EQ(pipeline.reconfigure(strict), "");
  const std::size_t size = pipeline.detector().database().size();
  const Detection second = pipeline.process(viewOf(again), along(x += 3.0, stamp += 1.0));
  EXPECT_TRUE(second.loops.empty());
  EXPECT_EQ(pipeline.detector().database().size(), size + 1);

  // Keyframe selection is live too: a keyframe 3 m on is passed over with a 10 m spacing.
  Config sparse = strict;
  sparse.keyframe_min_distance = 10.0;
  ASSERT_EQ(pipeline.reconfigure(sparse), "");
  EXPECT_FALSE(pipeline.process(viewOf(again), along(x += 3.0, stamp += 1.0)).selected);
}

TEST(Reconfigure, VerificationThresholdsReachTheVerifier) {
  Config c;
  KeyframePipeline pipeline(c);
  Config next = c;
  next.verification.min_inlier_ratio = 0.7;
  next.consistency_translation = 2.0;
  ASSERT_EQ(pipeline.reconfigure(next), "");
  EXPECT_DOUBLE_EQ(pipeline.detector().config().verification.min_inlier_ratio, 0.7);
  EXPECT_DOUBLE_EQ(pipeline.detector().config().consistency_translation, 2.0);
}

TEST(Reconfigure, LiveKeysAreTheOnesReadPerKeyframe) {
  // Every live key is a number: dynamic_reconfigure serves them as int_t / double_t.
  std::size_t live = 0;
  for (const auto& s : configSettings()) {
    if (!s.live) continue;
    ++live;
    EXPECT_TRUE(s.type == SettingType::kInt || s.type == SettingType::kDouble) << s.key;
  }
  EXPECT_GE(live, 10u);
  EXPECT_FALSE(findSetting(configSettings(), "num_sectors")->live);
  EXPECT_FALSE(findSetting(configSettings(), "exclude_recent_frames")->live);
}

}  // namespace
}  // namespace scan_context_loop
