// rostest: poses from tf and clouds registered in the odometry frame (pose_source: tf,
// cloud_in_world_frame: true) give the same true revisits as clouds in the sensor frame.
#include <cmath>

#include <gtest/gtest.h>


#include "harness.h"
#include "scan_context_loop/core/alignment.h"

namespace scan_context_loop {
namespace test {
namespace {

TEST(LoopClosureNode, PosesFromTfAndRegisteredClouds) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(30.0, false));
  const Drive drive = blockDrive(true, 7);
  harness.publishTfAndWorldClouds(drive, 12.0);
  harness.settle(3.0, 30.0);
  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u);
  expectTrueLoops(drive, harness.base, loops, false);
  for (const auto& loop : loops) {
    const int q = keyframeAt(drive, harness.base, loop.query_stamp);
    const int m = keyframeAt(drive, harness.base, loop.match_stamp);
    if (q < 0 || m < 0) continue;  // reported above
    const Eigen::Isometry3d truth = drive.truth[q].inverse() * drive.truth[m];
    // Back in the sensor frame, the yaw prior is the sensor's again.
    EXPECT_LT(std::fabs(wrapAngle(loop.yaw - std::atan2(truth(1, 0), truth(0, 0)))), 6.0 * M_PI / 180.0);
  }
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_tf_world"); }
