// The base station's list of robots: a non-empty list of distinct valid robot ids, or a reason.
#include <gtest/gtest.h>

#include "team/team_base_ros.h"

namespace scan_context_loop {
namespace {

XmlRpc::XmlRpcValue listOf(const std::vector<std::string>& items) {
  XmlRpc::XmlRpcValue value;
  value.setSize(static_cast<int>(items.size()));
  for (std::size_t i = 0; i < items.size(); ++i) value[static_cast<int>(i)] = items[i];
  return value;
}

TEST(TeamBase, RobotListMustBeDistinctValidIds) {
  std::vector<std::string> robots;
  std::string error;
  XmlRpc::XmlRpcValue good = listOf({"robot1", "robot_2", "R3"});
  ASSERT_TRUE(parseRobotList(good, &robots, &error)) << error;
  EXPECT_EQ(robots, (std::vector<std::string>{"robot1", "robot_2", "R3"}));

  for (const auto& bad : std::vector<std::vector<std::string>>{{}, {"robot1", "robot1"}, {"robot 1"}, {"../x"}, {""}}) {
    XmlRpc::XmlRpcValue value = listOf(bad);
    robots.clear();
    error.clear();
    EXPECT_FALSE(parseRobotList(value, &robots, &error)) << (bad.empty() ? "empty list" : bad.front());
    EXPECT_FALSE(error.empty());
  }
  XmlRpc::XmlRpcValue text(" robot1  robot2 ");
  robots.clear();
  ASSERT_TRUE(parseRobotList(text, &robots, &error)) << error;
  EXPECT_EQ(robots, (std::vector<std::string>{"robot1", "robot2"}));
  XmlRpc::XmlRpcValue blank("  ");
  EXPECT_FALSE(parseRobotList(blank, &robots, &error));
  XmlRpc::XmlRpcValue numbers;
  numbers[0] = 1;
  EXPECT_FALSE(parseRobotList(numbers, &robots, &error));
}

}  // namespace
}  // namespace scan_context_loop
