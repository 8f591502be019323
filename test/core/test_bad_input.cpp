#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/settings.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

TEST(BadInput, NonFiniteAndOutOfRangePointsAreSkipped) {
  Config config;
  config.min_range = 2.0;
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(pcl::PointXYZ(10.0f, 0.0f, 1.0f));  // used
  cloud.push_back(pcl::PointXYZ(nan, 0.0f, 1.0f));
  cloud.push_back(pcl::PointXYZ(5.0f, nan, 1.0f));
  cloud.push_back(pcl::PointXYZ(5.0f, 1.0f, nan));
  cloud.push_back(pcl::PointXYZ(inf, 0.0f, 1.0f));
  cloud.push_back(pcl::PointXYZ(-inf, inf, 1.0f));
  cloud.push_back(pcl::PointXYZ(5.0f, 1.0f, -inf));
  cloud.push_back(pcl::PointXYZ(1e30f, 1e30f, 1.0f));  // overflows to inf in r^2
  cloud.push_back(pcl::PointXYZ(1.0f, 1.0f, 1.0f));    // inside min_range
  cloud.push_back(pcl::PointXYZ(80.5f, 0.0f, 1.0f));   // beyond max_radius
  cloud.push_back(pcl::PointXYZ(0.0f, 80.0f, 1.0f));   // exactly at max_radius: last ring
  const HeightGrid grid = makeHeightGrid(cloud, config);
  EXPECT_EQ(grid.points_used, 2u);
  EXPECT_EQ(grid.points_skipped, cloud.size() - 2);
  EXPECT_EQ(grid.occupied(2, 0), 1);
  EXPECT_EQ(grid.occupied(19, 15), 1);
  EXPECT_TRUE(grid.heights.allFinite());
}

TEST(BadInput, AbsurdHeightsAreSkippedAndNeverOverflowTheKeys) {
  Config config;
  config.exclude_recent_frames = 0;
  // A ring of points 1e38 m high (finite, but their sum overflows float) and one at 2e4 m, around a
  // street.
  auto scene = test::streetScene(3);
  const std::size_t good = scene.size();
  for (int s = 0; s < config.num_sectors; ++s) {
    const float a = (s + 0.5f) * 2.0f * static_cast<float>(M_PI) / config.num_sectors;
    scene.push_back(pcl::PointXYZ(30.0f * std::cos(a), 30.0f * std::sin(a), 1e38f));
  }
  scene.push_back(pcl::PointXYZ(20.0f, 5.0f, -2e4f));
  const HeightGrid grid = makeHeightGrid(scene, config);
  EXPECT_EQ(grid.points_skipped, makeHeightGrid(test::streetScene(3), config).points_skipped + scene.size() - good);
  const Descriptor d = makeDescriptor(grid, config);
  for (const auto* values : {&d.ring_key, &d.sector_key}) {
    for (float v : *values) ASSERT_TRUE(std::isfinite(v));
  }
  EXPECT_EQ(descriptorImplausibility(d, config.ring_key), "");
  // The keyframe is stored and the clean street still finds it.
  LoopDetector detector(config);
  KeyframeInfo info;
  info.stamp = 1.0;
  ASSERT_TRUE(detector.process(viewOf(scene), info).accepted);
  info.stamp = 2.0;
  const Detection again = detector.process(viewOf(test::streetScene(3)), info);
  ASSERT_TRUE(again.query.matched);
  EXPECT_EQ(again.query.best()->index, 0u);
}

TEST(BadInput, PointAtTheSensorOriginIsBinnedWithoutNaN) {
  Config config;  // min_range 0: r = 0 is in range
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(pcl::PointXYZ(0.0f, 0.0f, 0.5f));
  cloud.push_back(pcl::PointXYZ(-0.0f, -0.0f, 0.5f));
  const HeightGrid grid = makeHeightGrid(cloud, config);
  EXPECT_EQ(grid.points_used, 2u);
  EXPECT_EQ(grid.occupied(0, 0), 1);
}

TEST(BadInput, EmptyAndNullViewsGiveEmptyDescriptors) {
  Config config;
  const Descriptor a = makeDescriptor(PointView{}, config);
  EXPECT_TRUE(a.empty());
  PointView dangling;
  dangling.count = 100;  // data == nullptr must not be read
  const HeightGrid grid = makeHeightGrid(dangling, config);
  EXPECT_EQ(grid.points_used, 0u);
  pcl::PointCloud<pcl::PointXYZ> all_nan;
  for (int i = 0; i < 50; ++i) all_nan.push_back(pcl::PointXYZ(NAN, NAN, NAN));
  EXPECT_TRUE(makeDescriptor(all_nan, config).empty());
}

TEST(BadInput, DetectorRejectsOutOfOrderStampsAndKeepsItsDatabase) {
  Config config;
  config.exclude_recent_frames = 0;
  LoopDetector detector(config);
  KeyframeInfo info;
  info.stamp = 5.0;
  const auto scene = test::streetScene(2);
  ASSERT_TRUE(detector.process(viewOf(scene), info).accepted);
  info.stamp = 4.0;
  const Detection late = detector.process(viewOf(scene), info);
  EXPECT_FALSE(late.accepted);
  EXPECT_FALSE(late.error.empty());
  EXPECT_TRUE(late.query.candidates.empty()) << "a rejected keyframe is not even queried";
  info.stamp = 6.0;
  const Detection next = detector.process(viewOf(scene), info);
  EXPECT_TRUE(next.accepted);
  EXPECT_EQ(next.index, 1u);
  EXPECT_TRUE(next.query.matched);
}

TEST(BadInput, ConfigValidationNamesEachImpossibleValue) {
  EXPECT_TRUE(Config().validate().empty());
  struct Case {
    void (*breakIt)(Config*);
    const char* key;
  };
  const Case cases[] = {
      {[](Config* c) { c->num_rings = 0; }, "num_rings"},
      {[](Config* c) { c->num_sectors = 2; }, "num_sectors"},
      {[](Config* c) { c->max_radius = -1; }, "max_radius"},
      {[](Config* c) { c->max_radius = NAN; }, "max_radius"},
      {[](Config* c) { c->min_range = 100; }, "min_range"},
      {[](Config* c) { c->lidar_height = INFINITY; }, "lidar_height"},
      {[](Config* c) { c->num_candidates = 0; }, "num_candidates"},
      {[](Config* c) { c->search_ratio = 1.5; }, "search_ratio"},
      {[](Config* c) { c->distance_threshold = 0; }, "distance_threshold"},
      {[](Config* c) { c->exclude_recent_frames = -1; }, "exclude_recent_frames"},
      {[](Config* c) { c->exclude_recent_seconds = -1; }, "exclude_recent_seconds"},
      {[](Config* c) { c->exclude_recent_distance = NAN; }, "exclude_recent_distance"},
      {[](Config* c) { c->lateral_offset_step = -2; }, "lateral_offset_step"},
      {[](Config* c) { c->lateral_offset_count = 0; }, "lateral_offset_count"},
      {[](Config* c) { c->consistency_min_support = -1; }, "consistency_min_support"},
      {[](Config* c) { c->gate_odometry_drift = -0.1; }, "gate_odometry_drift"},
      {[](Config* c) { c->consistency_window = 0; }, "consistency_window"},
      {[](Config* c) { c->consistency_drift = NAN; }, "consistency_drift"},
  };
  for (const auto& c : cases) {
    Config config;
    c.breakIt(&config);
    const auto errors = config.validate();
    ASSERT_FALSE(errors.empty()) << c.key;
    EXPECT_EQ(errors[0].rfind(c.key, 0), 0u) << errors[0];
  }
  RingKeyType type;
  EXPECT_TRUE(parseRingKeyType("mean_height", &type));
  EXPECT_EQ(type, RingKeyType::kMeanHeight);
  EXPECT_FALSE(parseRingKeyType("bogus", &type));
  RegistrationMethod method;
  for (auto m : {RegistrationMethod::kGicp, RegistrationMethod::kIcp, RegistrationMethod::kNdt}) {
    EXPECT_TRUE(parseRegistrationMethod(registrationMethodName(m), &method));
    EXPECT_EQ(method, m);
  }
  EXPECT_FALSE(parseRegistrationMethod("GICP ", &method));
}

}  // namespace
}  // namespace scan_context_loop

namespace scan_context_loop {
namespace {

TEST(ConfigKeys, EveryKeyIsSettableAndBadValuesLeaveTheConfigAlone) {
  Config config;
  for (const auto& setting : configSettings()) {
    // A value of the key's type: its last choice, true, or 3.
    const std::string value = setting.type == SettingType::kChoice ? setting.choices.back()
                              : setting.type == SettingType::kBool ? "true"
                                                                   : "3";
    std::string error;
    EXPECT_TRUE(setConfigValue(&config, setting.key, value, &error)) << setting.key << ": " << error;
  }
  EXPECT_EQ(configKeys().size(), configSettings().size());
  EXPECT_EQ(config.num_rings, 3);
  EXPECT_EQ(config.distance_threshold, 3.0);
  EXPECT_EQ(config.ring_key, RingKeyType::kOccupancy);
  EXPECT_EQ(config.verification.method, RegistrationMethod::kNdt);
  EXPECT_EQ(config.lateral_offset_step, 3.0);
  EXPECT_EQ(config.gravity_alignment, GravityAlignmentMode::kOff);
  EXPECT_EQ(config.verification.max_violation, 3.0);
  EXPECT_TRUE(config.verification.allow_degenerate);
  const Config before = config;
  std::string error;
  EXPECT_FALSE(setConfigValue(&config, "num_rings", "20.5", &error));
  EXPECT_FALSE(setConfigValue(&config, "max_radius", "far", &error));
  EXPECT_NE(error.find("max_radius"), std::string::npos);
  EXPECT_FALSE(setConfigValue(&config, "ring_key", "median", &error));
  EXPECT_FALSE(setConfigValue(&config, "verify_method", "sift", &error));
  EXPECT_FALSE(setConfigValue(&config, "gravity_alignment", "gravity", &error));
  EXPECT_FALSE(setConfigValue(&config, "rings", "20", &error));
  EXPECT_NE(error.find("unknown"), std::string::npos);
  EXPECT_EQ(config.num_rings, before.num_rings);
  EXPECT_EQ(config.max_radius, before.max_radius);
}

}  // namespace
}  // namespace scan_context_loop
