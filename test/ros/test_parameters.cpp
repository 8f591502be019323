// The node's parameter reader: every key of the settings tables, with its type checked, and unknown
// private parameters refused by name.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include "child_process.h"
#include "shared/parameters.h"
#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {
namespace {

/// Reads the parameters set under namespace `ns` (standing in for a node's private one).
std::vector<std::string> readIn(const std::string& ns, Config* config, NodeOptions* options) {
  ros::NodeHandle pnh(ns);
  return readParameters(pnh, config, options);
}

bool mentions(const std::vector<std::string>& problems, const std::string& key) {
  return std::any_of(problems.begin(), problems.end(), [&](const std::string& p) {
    return p.compare(0, key.size() + 1, key + ":") == 0 || p.compare(0, key.size() + 3, key + " = ") == 0;
  });
}

TEST(Parameters, DefaultsWhenNothingIsSetAndEveryKeyIsRead) {
  Config config;
  NodeOptions options;
  EXPECT_TRUE(readIn("/empty", &config, &options).empty());
  EXPECT_EQ(config.num_rings, Config().num_rings);
  ros::NodeHandle pnh("/typed");
  pnh.setParam("num_sectors", 90);
  pnh.setParam("verify_min_inlier_ratio", 0.6);
  pnh.setParam("verify", false);
  pnh.setParam("ring_key", std::string("occupancy"));
  pnh.setParam("keyframe_min_distance", 2);  // an integer where a number is wanted: fine
  pnh.setParam("pose_source", std::string("tf"));
  pnh.setParam("fixed_frame", std::string("map"));
  const auto problems = readIn("/typed", &config, &options);
  EXPECT_TRUE(problems.empty()) << problems.front();
  EXPECT_EQ(config.num_sectors, 90);
  EXPECT_DOUBLE_EQ(config.verification.min_inlier_ratio, 0.6);
  EXPECT_FALSE(config.verification.enabled);
  EXPECT_EQ(config.ring_key, RingKeyType::kOccupancy);
  EXPECT_DOUBLE_EQ(config.keyframe_min_distance, 2.0);
  EXPECT_EQ(options.fixed_frame, "map");
}

TEST(Parameters, DeprecatedKeyNamesSetTheNewKeysWithAWarning) {
  ros::NodeHandle old_names("/old_names"), new_names("/new_names");
  old_names.setParam("levelling", std::string("ground"));
  old_names.setParam("levelling_max_tilt", 12.0);
  new_names.setParam("gravity_alignment", std::string("ground"));
  new_names.setParam("gravity_alignment_max_tilt", 12.0);
  Config old_config, new_config;
  NodeOptions old_options, new_options;
  std::vector<std::string> old_warnings, new_warnings;
  const auto old_problems = readParameters(old_names, &old_config, &old_options, &old_warnings);
  const auto new_problems = readParameters(new_names, &new_config, &new_options, &new_warnings);
  EXPECT_TRUE(old_problems.empty()) << old_problems.front();
  EXPECT_TRUE(new_problems.empty()) << new_problems.front();
  EXPECT_EQ(old_config.gravity_alignment, GravityAlignmentMode::kGround);
  for (const auto& s : configSettings()) EXPECT_EQ(s.get(old_config), s.get(new_config)) << s.key;
  EXPECT_TRUE(new_warnings.empty());
  ASSERT_EQ(old_warnings.size(), 2u);
  EXPECT_EQ(old_warnings[0], "levelling is deprecated, use gravity_alignment");
  EXPECT_EQ(old_warnings[1], "levelling_max_tilt is deprecated, use gravity_alignment_max_tilt");
}

TEST(Parameters, WrongTypesUnknownKeysAndBadValuesAreNamed) {
  ros::NodeHandle pnh("/bad");
  pnh.setParam("verify", 1);                       // an integer for a boolean
  pnh.setParam("exclude_recent_frames", 0.4);      // a number for an integer
  pnh.setParam("max_radius", std::string("far"));  // a string for a number
  pnh.setParam("ring_key", std::string("median"));
  pnh.setParam("distance_treshold", 0.3);  // misspelt
  pnh.setParam("num_rings", 0);            // out of range
  Config config;
  NodeOptions options;
  const auto problems = readIn("/bad", &config, &options);
  for (const char* key :
       {"verify", "exclude_recent_frames", "max_radius", "ring_key", "distance_treshold", "num_rings"}) {
    EXPECT_TRUE(mentions(problems, key)) << key << " not reported";
  }
  EXPECT_EQ(problems.size(), 6u);
  const auto misspelt = std::find_if(problems.begin(), problems.end(), [](const std::string& p) {
    return p.find("unknown parameter") != std::string::npos;
  });
  ASSERT_NE(misspelt, problems.end());
  EXPECT_NE(misspelt->find("did you mean distance_threshold?"), std::string::npos) << *misspelt;
}

TEST(Parameters, AnUnknownKeyComesWithItsFix) {
  const std::vector<std::string> keys = {"distance_threshold", "num_rings", "num_sectors", "max_radius"};
  EXPECT_EQ(unknownKeyHint("num_ring", keys), "did you mean num_rings?");
  EXPECT_EQ(unknownKeyHint("Max_Radius", keys), "did you mean max_radius?");  // two edits
  EXPECT_EQ(unknownKeyHint("laserCloudSurroundResolution", keys), "");          // another program's key: nothing near
  EXPECT_NE(unknownKeyHint("use_sim_time", keys).find("outside the node tag"), std::string::npos);
  // In the node's parameters: use_sim_time inside the node tag is refused with where it belongs.
  ros::NodeHandle pnh("/sim_time_inside");
  pnh.setParam("use_sim_time", true);
  Config config;
  NodeOptions options;
  const auto problems = readIn("/sim_time_inside", &config, &options);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("global parameter"), std::string::npos) << problems[0];
}

/// Sets every key of `table` to its value in `defaults`, with the parameter type the key wants.
template <typename T>
void setAll(ros::NodeHandle& pnh, const std::vector<Setting<T>>& table, const T& defaults) {
  for (const auto& s : table) {
    const std::string text = s.get(defaults);
    if (s.type == SettingType::kInt)
      pnh.setParam(s.key, std::stoi(text));
    else if (s.type == SettingType::kDouble)
      pnh.setParam(s.key, std::stod(text));
    else if (s.type == SettingType::kBool)
      pnh.setParam(s.key, text == "true");
    else
      pnh.setParam(s.key, text);
  }
}

TEST(Parameters, EveryTableKeyIsAcceptedWithItsDefault) {
  // Writing each key's default back is accepted: the reader and the table agree on every type.
  ros::NodeHandle pnh("/round_trip");
  setAll(pnh, configSettings(), Config());
  setAll(pnh, nodeSettings(), NodeOptions());
  Config config;
  NodeOptions options;
  const auto problems = readIn("/round_trip", &config, &options);
  EXPECT_TRUE(problems.empty()) << problems.front();
}

TEST(Parameters, ANodeletWithBadParametersDoesNotStartAndItsManagerLivesOn) {
  // parameters.test loads two nodelets into one manager: /with_defaults with the defaults,
  // /with_bad_parameters with num_rings 0
  // and a string for max_radius. The good one subscribes to its clouds; the bad one never does.
  ros::NodeHandle nh;
  ros::Publisher good = nh.advertise<sensor_msgs::PointCloud2>("/with_defaults/keyframe_cloud", 1);
  ros::Publisher bad = nh.advertise<sensor_msgs::PointCloud2>("/with_bad_parameters/keyframe_cloud", 1);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(40.0);
  while (good.getNumSubscribers() == 0 && ros::WallTime::now() < end) ros::WallDuration(0.1).sleep();
  ASSERT_GT(good.getNumSubscribers(), 0u) << "the good nodelet never started";
  ros::WallDuration(3.0).sleep();  // both were loaded at once: the bad one has had its chance
  EXPECT_EQ(bad.getNumSubscribers(), 0u) << "a nodelet with bad parameters started";
  EXPECT_GT(good.getNumSubscribers(), 0u) << "the manager went down";
}

/// Waits up to `seconds` for `child` to exit by itself; false when it still runs.
bool exits(test::Child* child, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (child->running() && ros::WallTime::now() < end) ros::WallDuration(0.1).sleep();
  return !child->running();
}

TEST(Parameters, ABadConfigurationEndsTheProcessThatStartsTheNode) {
  // `nodelet load` of a nodelet with a bad parameter into the running manager: the load fails, so the
  // loader (the process roslaunch watches) exits with a non-zero status; the manager runs on.
  test::Child loader({"nodelet", "nodelet", "load", "scan_context_loop/LoopClosureNodelet", "/manager",
                      "__ns:=loaded_bad", "__name:=loop_closure", "_num_ring:=20"});
  ASSERT_GT(loader.pid(), 0);
  ASSERT_TRUE(exits(&loader, 60.0)) << "nodelet load still runs with a bad parameter";
  EXPECT_FALSE(loader.exitedCleanly()) << loader.how();
  // A standalone node the same: exit status 1.
  test::Child node({"scan_context_loop", "loop_closure_node", "__ns:=standalone_bad", "__name:=loop_closure",
                    "_num_rings:=0"});
  ASSERT_GT(node.pid(), 0);
  ASSERT_TRUE(exits(&node, 60.0)) << "a standalone node with a bad parameter still runs";
  EXPECT_EQ(node.how(), "exit status 1");
  // The manager and its good nodelet live on.
  ros::NodeHandle nh;
  ros::Publisher good = nh.advertise<sensor_msgs::PointCloud2>("/with_defaults/keyframe_cloud", 1);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(20.0);
  while (good.getNumSubscribers() == 0 && ros::WallTime::now() < end) ros::WallDuration(0.1).sleep();
  EXPECT_GT(good.getNumSubscribers(), 0u) << "the manager went down";
}

}  // namespace
}  // namespace scan_context_loop

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_parameters");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
