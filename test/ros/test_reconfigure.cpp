// rostest: the node's dynamic_reconfigure server. A refused value leaves the settings in force; a strict
// threshold set while running stops the loops of a whole drive, and the default set back finds them
// again against the keyframes already stored.
#include <map>
#include <string>

#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>

#include "harness.h"

namespace scan_context_loop {
namespace test {
namespace {

/// Sets one number through loop_closure/set_parameters; returns the values in force afterwards.
std::map<std::string, double> setNumber(const std::string& key, double value) {
  dynamic_reconfigure::Reconfigure call;
  dynamic_reconfigure::DoubleParameter p;
  p.name = key;
  p.value = value;
  call.request.config.doubles.push_back(p);
  std::map<std::string, double> in_force;
  EXPECT_TRUE(ros::service::call("loop_closure/set_parameters", call)) << key;
  for (const auto& d : call.response.config.doubles) in_force[d.name] = d.value;
  return in_force;
}

TEST(Reconfigure, ThresholdsChangeWhileRunningAndTheDatabaseStays) {
  ros::NodeHandle nh;
  Harness harness(nh);
  ASSERT_TRUE(harness.waitForNode(30.0));
  ASSERT_TRUE(ros::service::waitForService("loop_closure/set_parameters", ros::Duration(20.0)));

  // Refused (a match needs a distance above 0): the default stays in force.
  EXPECT_DOUBLE_EQ(setNumber("distance_threshold", 0.0).at("distance_threshold"), 0.21);
  // Strict: no descriptor match of this drive is that close (its loops lie at 0.0005-0.01: the same
  // simulated world seen from the same spots).
  EXPECT_DOUBLE_EQ(setNumber("distance_threshold", 1e-5).at("distance_threshold"), 1e-5);
  double on_server = 0.0;
  EXPECT_TRUE(ros::param::get("loop_closure/distance_threshold", on_server));
  EXPECT_DOUBLE_EQ(on_server, 1e-5);

  const Drive drive = blockDrive(true, 7);  // lap 2 drives lap 1 in reverse
  harness.publish(drive, 0, drive.truth.size(), 15.0);
  ASSERT_TRUE(harness.waitForKeyframes(drive.truth.size(), 60.0));
  for (const auto& loop : harness.loops()) ADD_FAILURE() << "a loop at distance " << loop.distance << " under 1e-5";

  // The default again: the same drive a second time (later stamps) closes loops against both passes.
  EXPECT_DOUBLE_EQ(setNumber("distance_threshold", 0.21).at("distance_threshold"), 0.21);
  const ros::Time first_base = harness.base;
  harness.base = first_base + ros::Duration(drive.times.back() + 10.0);
  harness.publish(drive, 0, drive.truth.size(), 15.0);
  harness.settle(3.0, 30.0);
  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u);
  std::size_t into_first_pass = 0;
  for (const auto& loop : loops) {
    const int q = keyframeAt(drive, harness.base, loop.query_stamp);
    int m = keyframeAt(drive, harness.base, loop.match_stamp);
    if (m < 0) {
      m = keyframeAt(drive, first_base, loop.match_stamp);
      ++into_first_pass;
    }
    ASSERT_GE(q, 0) << "a loop from the first pass, while the threshold was 1e-5";
    ASSERT_GE(m, 0);
    expectTrueLoop(drive, q, m, loop);
  }
  EXPECT_GT(into_first_pass, 0u) << "the keyframes stored under the strict threshold are still searched";
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_reconfigure"); }
