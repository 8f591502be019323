// The dynamic_reconfigure description (cfg/LoopClosure.cfg) against the settings tables, and the
// conversion of its messages; the standard-type copy of a loop. No ROS master needed.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_loop/LoopClosureConfig.h"
#include "scan_context_loop/core/settings.h"
#include "loop_closure/live_settings.h"
#include "loop_closure/loop_pair.h"

namespace scan_context_loop {
namespace {

std::map<std::string, double> valuesOf(const dynamic_reconfigure::Config& message) {
  std::map<std::string, double> values;
  for (const auto& p : message.ints) values[p.name] = p.value;
  for (const auto& p : message.doubles) values[p.name] = p.value;
  for (const auto& p : message.bools) values[p.name] = p.value;
  return values;
}

/// The cfg's name for a row's type (ParamDescription::type), "" for one dynamic_reconfigure cannot carry.
std::string reconfigureType(SettingType type) {
  switch (type) {
    case SettingType::kInt:
      return "int";
    case SettingType::kDouble:
      return "double";
    case SettingType::kBool:
      return "bool";
    case SettingType::kString:
    case SettingType::kChoice:
      return "str";
  }
  return "";
}

/// The live row of `key` in either table: its type, default and range; false when there is none.
struct LiveRow {
  SettingType type;
  double default_value;
  SettingRange range;
};

template <typename T>
bool findLive(const std::vector<Setting<T>>& table, const std::string& key, LiveRow* row) {
  const Setting<T>* s = findSetting(table, key);
  if (s == nullptr || s->key != key || !s->live) return false;
  *row = {s->type, s->number ? s->number(T()) : 0.0, s->range};
  return true;
}

// The rule between a table's range and the cfg's slider: a bound the table sets is the cfg's bound (an
// open one too: a slider cannot leave out its end, the node refuses it); a side the table leaves
// unbounded is dynamic_reconfigure's widest (the bound left out of the .cfg: -inf / inf for a double,
// INT_MIN / INT_MAX for an int).
double expectedBound(const LiveRow& row, bool low) {
  const bool bounded = low ? row.range.boundedBelow() : row.range.boundedAbove();
  if (bounded) return low ? row.range.low : row.range.high;
  if (row.type == SettingType::kInt) {
    return low ? double(std::numeric_limits<std::int32_t>::min()) : double(std::numeric_limits<std::int32_t>::max());
  }
  return low ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
}

TEST(LiveSettings, TheReconfigureDescriptionIsTheLiveRowsWithTheirTypesDefaultsAndRanges) {
  dynamic_reconfigure::Config generated, low, high;
  LoopClosureConfig::__getDefault__().__toMessage__(generated);
  LoopClosureConfig::__getMin__().__toMessage__(low);
  LoopClosureConfig::__getMax__().__toMessage__(high);
  const auto defaults = valuesOf(generated), lows = valuesOf(low), highs = valuesOf(high);
  std::vector<std::string> described;
  for (const auto& d : LoopClosureConfig::__getParamDescriptions__()) {
    const std::string& key = d->name;
    described.push_back(key);
    LiveRow row;
    ASSERT_TRUE(findLive(configSettings(), key, &row) || findLive(nodeSettings(), key, &row))
        << key << " in cfg/LoopClosure.cfg is not a live key of the settings tables";
    EXPECT_EQ(d->type, reconfigureType(row.type)) << key;
    EXPECT_DOUBLE_EQ(defaults.at(key), row.default_value) << key << ": the cfg's default is not the table's";
    EXPECT_EQ(lows.at(key), expectedBound(row, true))
        << key << ": the cfg's min is not the table's " << row.range.interval();
    EXPECT_EQ(highs.at(key), expectedBound(row, false))
        << key << ": the cfg's max is not the table's " << row.range.interval();
  }
  // Every live row is in the cfg.
  const auto expectDescribed = [&](const std::string& key, bool live) {
    if (!live) return;
    EXPECT_NE(std::find(described.begin(), described.end(), key), described.end())
        << key << " is live but not in cfg/LoopClosure.cfg";
  };
  for (const auto& s : configSettings()) expectDescribed(s.key, s.live);
  for (const auto& s : nodeSettings()) expectDescribed(s.key, s.live);
  // The message of the live values carries the same keys.
  EXPECT_EQ(valuesOf(liveSettingsMessage(Config(), NodeOptions())).size(), described.size());
}

dynamic_reconfigure::Config withDouble(const std::string& key, double value) {
  dynamic_reconfigure::Config message = liveSettingsMessage(Config(), NodeOptions());
  for (auto& p : message.doubles) {
    if (p.name == key) p.value = value;
  }
  return message;
}

TEST(LiveSettings, AppliesLiveValuesAndRefusesBadOnesWhole) {
  Config config;
  NodeOptions options;
  std::string error;
  ASSERT_TRUE(applyLiveSettings(withDouble("distance_threshold", 0.15), &config, &options, &error)) << error;
  EXPECT_DOUBLE_EQ(config.distance_threshold, 0.15);
  ASSERT_TRUE(applyLiveSettings(withDouble("lio_sam_min_interval", 2.5), &config, &options, &error)) << error;
  EXPECT_DOUBLE_EQ(options.lio_sam_min_interval, 2.5);
  const auto changed = liveSettingsChanged(Config(), NodeOptions(), config, options);
  ASSERT_EQ(changed.size(), 1u);  // the second message carried the defaults again for distance_threshold
  EXPECT_NE(changed.front().find("lio_sam_min_interval"), std::string::npos);

  // Out of range: nothing changes, and the error names the key.
  const Config before = config;
  EXPECT_FALSE(applyLiveSettings(withDouble("distance_threshold", 0.0), &config, &options, &error));
  EXPECT_NE(error.find("distance_threshold"), std::string::npos) << error;
  EXPECT_DOUBLE_EQ(config.distance_threshold, before.distance_threshold);

  // A key that shapes stored data is refused by name, even with a valid value.
  dynamic_reconfigure::Config fixed;
  dynamic_reconfigure::IntParameter rings;
  rings.name = "num_rings";
  rings.value = 30;
  fixed.ints.push_back(rings);
  EXPECT_FALSE(applyLiveSettings(fixed, &config, &options, &error));
  EXPECT_NE(error.find("num_rings cannot change while running"), std::string::npos) << error;
  EXPECT_EQ(config.num_rings, Config().num_rings);
}

TEST(LoopPair, MatchAndQueryPosesGiveBackTheLoopsRelativePose) {
  scan_context_loop::LoopClosure loop;
  loop.header.frame_id = "odom";
  loop.query_stamp = ros::Time(120.5);
  loop.match_stamp = ros::Time(20.25);
  Eigen::Isometry3d query_from_match = Eigen::Isometry3d::Identity();
  query_from_match.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  query_from_match.translation() = Eigen::Vector3d(1.5, -0.5, 0.1);
  loop.relative_pose = tf2::toMsg(query_from_match);
  // Variances 1..6 on the diagonal: x 1, y 2 in the query's axes.
  for (int i = 0; i < 6; ++i) loop.covariance[i * 7] = i + 1.0;
  Eigen::Isometry3d world_from_match = Eigen::Isometry3d::Identity();
  world_from_match.linear() = Eigen::AngleAxisd(M_PI / 2 + 0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_from_match.translation() = Eigen::Vector3d(10.0, 20.0, 1.0);

  const auto pair = loopPair(loop, world_from_match);
  EXPECT_EQ(pair[0].header.stamp, loop.match_stamp);
  EXPECT_EQ(pair[1].header.stamp, loop.query_stamp);
  EXPECT_EQ(pair[1].header.frame_id, "odom");
  Eigen::Isometry3d match, query;
  tf2::fromMsg(pair[0].pose.pose, match);
  tf2::fromMsg(pair[1].pose.pose, query);
  EXPECT_TRUE((match.inverse() * query).isApprox(query_from_match.inverse(), 1e-9));
  // The query keyframe faces +90 deg in the world: its x variance becomes the world's y and vice versa.
  EXPECT_NEAR(pair[1].pose.covariance[0], 2.0, 1e-9);
  EXPECT_NEAR(pair[1].pose.covariance[7], 1.0, 1e-9);
  EXPECT_NEAR(pair[1].pose.covariance[35], 6.0, 1e-9);
  for (double v : pair[0].pose.covariance) EXPECT_EQ(v, 0.0);
}

TEST(LoopArray, OneMessageHoldsBothKeyframesAndThePoseWithItsCovariance) {
  scan_context_loop::LoopClosure loop;
  loop.query_id = 4000;
  loop.match_id = 17;
  loop.query_session = 2;
  loop.match_session = 0;
  loop.query_stamp = ros::Time(1700000000, 123456789);
  loop.match_stamp = ros::Time(20, 250000000);
  loop.verified = true;
  loop.fitness = 0.004;
  loop.distance = 0.18;
  loop.relative_pose.position.x = 1.5;
  loop.relative_pose.orientation.z = std::sin(0.2);
  loop.relative_pose.orientation.w = std::cos(0.2);
  for (int i = 0; i < 36; ++i) loop.covariance[i] = 0.01 * i;
  const std_msgs::Float64MultiArray a = loopArray(loop);
  ASSERT_EQ(a.data.size(), kLoopArraySize);
  ASSERT_EQ(a.layout.dim.size(), 1u);
  EXPECT_EQ(a.layout.dim[0].size, kLoopArraySize);
  EXPECT_EQ(a.layout.dim[0].label, kLoopArrayLayout);
  EXPECT_EQ(a.data[0], 4000.0);
  EXPECT_EQ(a.data[1], 17.0);
  EXPECT_EQ(a.data[2], 2.0);
  EXPECT_EQ(a.data[3], 0.0);
  EXPECT_NEAR(a.data[4], loop.query_stamp.toSec(), 1e-6);  // a double holds today's Unix time to 0.25 us
  EXPECT_EQ(ros::Time(a.data[5]), loop.match_stamp);
  EXPECT_EQ(a.data[6], 1.0);
  EXPECT_EQ(a.data[7], 0.004);
  EXPECT_EQ(a.data[8], 0.18);
  EXPECT_EQ(a.data[9], 1.5);
  EXPECT_EQ(a.data[14], std::sin(0.2));
  EXPECT_EQ(a.data[15], std::cos(0.2));
  for (int i = 0; i < 36; ++i) EXPECT_EQ(a.data[16 + i], 0.01 * i);
}

}  // namespace
}  // namespace scan_context_loop

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
