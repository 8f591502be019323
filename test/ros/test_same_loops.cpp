// The node and the evaluator run the same code: one simulated drive through the running node and,
// written as a KITTI-format sequence, through eval::evaluate with the node's own parameters.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <tuple>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <tf2_eigen/tf2_eigen.h>

#include "harness.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/kitti_io.h"
#include "shared/parameters.h"

namespace scan_context_loop {
namespace test {
namespace {

/// Writes the drive in the KITTI layout (odometry = truth, as the harness publishes it).
std::string writeDrive(const Drive& drive) {
  const std::string dir = testing::TempDir() + "/scl_same_loops";
  mkdir(dir.c_str(), 0755);
  mkdir((dir + "/velodyne").c_str(), 0755);
  std::string error;
  for (std::size_t k = 0; k < drive.truth.size(); ++k) {
    EXPECT_TRUE(kitti::writeScan(kitti::scanPath(dir, static_cast<int>(k)), drive.scan(k), &error)) << error;
  }
  EXPECT_TRUE(kitti::writePoses(dir + "/poses.txt", drive.truth, &error)) << error;
  EXPECT_TRUE(kitti::writePoses(dir + "/odom_poses.txt", drive.truth, &error)) << error;
  std::ofstream(dir + "/calib.txt") << "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  std::ofstream times(dir + "/times.txt");
  times.precision(9);
  for (double t : drive.times) times << t << "\n";
  return dir;
}

TEST(SameLoops, NodeAndEvaluatorReportTheSameLoops) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(20.0));
  const Drive drive = blockDrive(true, 11);
  harness.publish(drive, 0, drive.truth.size(), 15.0);
  harness.settle(3.0, 60.0);
  const auto node_loops = harness.loops();

  Config config;
  NodeOptions options;
  const auto problems = readParameters(ros::NodeHandle("/loop_closure"), &config, &options);
  ASSERT_TRUE(problems.empty()) << problems.front();
  eval::Sequence sequence;
  std::string error;
  ASSERT_TRUE(eval::loadSequence(writeDrive(drive), eval::SequenceOptions(), &sequence, &error)) << error;
  const eval::Evaluation evaluation = eval::evaluate(sequence, config, 5.0);
  ASSERT_TRUE(evaluation.errors.empty()) << evaluation.errors.front();

  ASSERT_GE(node_loops.size(), 5u) << "too few loops to compare";
  ASSERT_EQ(node_loops.size(), evaluation.loops.size());
  using Key = std::tuple<std::size_t, std::size_t, bool>;
  std::vector<Key> from_node, from_evaluator;
  for (const auto& l : node_loops) from_node.emplace_back(l.query_id, l.match_id, l.verified);
  for (const auto& l : evaluation.loops) from_evaluator.emplace_back(l.query, l.match, l.verified);
  EXPECT_EQ(from_node, from_evaluator);
  for (std::size_t i = 0; i < node_loops.size() && i < evaluation.loops.size(); ++i) {
    Eigen::Isometry3d relative;
    tf2::fromMsg(node_loops[i].relative_pose, relative);
    const Eigen::Isometry3d other = evaluation.loops[i].relative();
    EXPECT_LT((relative.translation() - other.translation()).norm(), 1e-3) << "loop " << i;
    EXPECT_LT(Eigen::AngleAxisd(relative.linear().transpose() * other.linear()).angle(), 1e-4) << "loop " << i;
  }
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_same_loops"); }
