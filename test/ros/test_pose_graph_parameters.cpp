// The reference backend's parameter reader (built with the backend, into test_ros_parameters): defaults,
// types, unknown keys and ranges.
#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "pose_graph/pose_graph_parameters.h"

namespace scan_context_loop {
namespace {

TEST(PoseGraphParameters, DefaultsTypesUnknownKeysAndRangesAreChecked) {
  PoseGraphConfig graph;
  KeyframeMapConfig map;
  PoseGraphOptions options;
  EXPECT_TRUE(readPoseGraphParameters(ros::NodeHandle("/empty"), &graph, &map, &options).empty());
  EXPECT_EQ(options.map_frame, "map");
  EXPECT_TRUE(options.map_directory.empty() && options.map_save.empty()) << "nothing is saved unless asked";
  ros::NodeHandle good("/graph_good");
  good.setParam("map_voxel", 1);  // an integer where a number is wanted: fine
  good.setParam("verified_only", false);
  good.setParam("map_frame", std::string("world"));
  good.setParam("map_keyframe_stride", 3);
  good.setParam("map_directory", std::string("/data/maps"));
  good.setParam("map_save", std::string("last_run"));
  auto problems = readPoseGraphParameters(good, &graph, &map, &options);
  EXPECT_TRUE(problems.empty()) << problems.front();
  EXPECT_DOUBLE_EQ(map.voxel, 1.0);
  EXPECT_FALSE(options.verified_only);
  EXPECT_EQ(options.map_frame, "world");
  EXPECT_EQ(map.keyframe_stride, 3);
  EXPECT_EQ(options.map_directory, "/data/maps");
  EXPECT_EQ(options.map_save, "last_run");

  ros::NodeHandle bad("/graph_bad");
  bad.setParam("publish_tf", 1);          // an integer for a boolean
  bad.setParam("max_iterations", 2.5);    // a number for an integer
  bad.setParam("map_frame", 3);           // a number for a string
  bad.setParam("loop_robust_scal", 1.0);  // misspelt
  bad.setParam("tf_rate", 0.0);           // out of range
  bad.setParam("odometry_translation_floor", -1.0);
  PoseGraphOptions bad_options;
  problems = readPoseGraphParameters(bad, &graph, &map, &bad_options);
  for (const std::string key :
       {"publish_tf", "max_iterations", "map_frame", "loop_robust_scal", "tf_rate", "odometry_translation_floor"}) {
    EXPECT_TRUE(std::any_of(problems.begin(), problems.end(),
                            [&](const std::string& p) { return p.compare(0, key.size(), key) == 0; }))
        << key << " not reported";
  }
  EXPECT_EQ(problems.size(), 6u);
}

TEST(PoseGraphParameters, RobotsAreAListOfIdsAndTheAnchorOneOfThem) {
  PoseGraphConfig graph;
  KeyframeMapConfig map;
  PoseGraphOptions options;
  EXPECT_TRUE(robotIds(options).empty()) << "one robot by default";
  ros::NodeHandle team("/graph_team");
  team.setParam("robots", std::vector<std::string>{"robot1", "robot2", "robot_3"});
  team.setParam("anchor_robot", std::string("robot2"));
  auto problems = readPoseGraphParameters(team, &graph, &map, &options);
  EXPECT_TRUE(problems.empty()) << problems.front();
  EXPECT_EQ(robotIds(options), (std::vector<std::string>{"robot2", "robot1", "robot_3"})) << "the anchor is chain 0";
  ros::NodeHandle spaced("/graph_spaced");
  spaced.setParam("robots", std::string("a b"));
  PoseGraphOptions spaced_options;
  problems = readPoseGraphParameters(spaced, &graph, &map, &spaced_options);
  EXPECT_TRUE(problems.empty()) << problems.front();
  EXPECT_EQ(robotIds(spaced_options), (std::vector<std::string>{"a", "b"})) << "the first anchors by default";

  const std::vector<std::pair<std::string, std::function<void(ros::NodeHandle&)>>> bad = {
      {"robots",
       [](ros::NodeHandle& nh) {
         nh.setParam("robots", std::vector<std::string>{"a", "../b"});
       }},
      {"robots",
       [](ros::NodeHandle& nh) {
         nh.setParam("robots", std::vector<std::string>{"a", "a"});
       }},
      {"robots",
       [](ros::NodeHandle& nh) {
         nh.setParam("robots", std::vector<int>{1, 2});
       }},
      {"anchor_robot",
       [](ros::NodeHandle& nh) {
         nh.setParam("robots", std::vector<std::string>{"a", "b"});
         nh.setParam("anchor_robot", std::string("c"));
       }},
  };
  int n = 0;
  for (const auto& [key, set] : bad) {
    ros::NodeHandle nh("/graph_bad_robots_" + std::to_string(n++));
    set(nh);
    PoseGraphOptions o;
    problems = readPoseGraphParameters(nh, &graph, &map, &o);
    ASSERT_EQ(problems.size(), 1u) << key;
    EXPECT_EQ(problems[0].compare(0, key.size(), key), 0) << problems[0];
  }
}

}  // namespace
}  // namespace scan_context_loop
