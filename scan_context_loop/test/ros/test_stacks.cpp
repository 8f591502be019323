// The launch files next to each odometry stack, fed that stack's topics: every loop must be a true,
// verified one.
#include <string>

#include <gtest/gtest.h>

#include "harness.h"

namespace scan_context_loop {
namespace test {
namespace {

TEST(Stacks, TrueVerifiedLoopsFromTheStacksTopics) {
  ros::NodeHandle nh, pnh("~");
  std::string shape;
  pnh.param("shape", shape, shape);
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(20.0));
  Harness::StackShape stack;
  ASSERT_TRUE(Harness::stackShape(shape, &stack)) << "unknown stack '" << shape << "'";
  const Drive drive = blockDrive(true, 7);
  harness.publishShaped(drive, stack, 12.0);
  harness.settle(3.0, 40.0);
  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u);
  expectTrueLoops(drive, harness.base, loops, true);
  bool expect_lio = false;
  pnh.param("expect_lio", expect_lio, expect_lio);
  if (expect_lio) {
    // LIO-SAM's hook gets verified loops, one per keyframe, at most one a second.
    const auto lio = harness.lioLoops();
    ASSERT_FALSE(lio.empty());
    EXPECT_LT(lio.size(), loops.size());
  }
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_stacks"); }
