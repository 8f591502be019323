// Real KITTI scans from ../shared/data, read in place.
#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

using test::kittiScan;

constexpr double kDeg = M_PI / 180.0;

Alignment alignScans(const std::string& sequence, int query, int match, const Config& config) {
  return align(makeDescriptor(kittiScan(sequence, query), config),
               makeDescriptor(kittiScan(sequence, match), config), config);
}

TEST(RealData, ConsecutiveFramesMatchAndDistantPlacesDoNot) {
  Config config;
  const Alignment same = alignScans("00", 94, 95, config);
  const Alignment same2 = alignScans("00", 198, 199, config);
  const Alignment apart = alignScans("00", 94, 198, config);
  EXPECT_LT(same.distance, config.distance_threshold);
  EXPECT_LT(same2.distance, config.distance_threshold);
  EXPECT_GT(apart.distance, config.distance_threshold);
  EXPECT_GT(apart.distance, 3.0 * same.distance);
  // Small true yaws: -1.2 and +2.8 degrees.
  EXPECT_NEAR(same.yaw, test::kittiTrueYaw("00", 94, 95), 3.0 * kDeg);
  EXPECT_NEAR(same2.yaw, test::kittiTrueYaw("00", 198, 199), 3.0 * kDeg);
}

TEST(RealData, ReverseRevisitYawWithinOneSector) {
  for (RingKeyType key : {RingKeyType::kOccupancy, RingKeyType::kMeanHeight}) {
    Config config;
    config.ring_key = key;
    const Alignment a = alignScans("08", 720, 1500, config);
    const double truth = test::kittiTrueYaw("08", 720, 1500);
    EXPECT_NEAR(truth, -148.5 * kDeg, 0.1 * kDeg) << "oracle from ../shared/data/README.md";
    EXPECT_LT(std::fabs(wrapAngle(a.yaw - truth)), 6.0 * kDeg) << "yaw " << a.yaw / kDeg;
    // The reverse direction is seen as a rotation of about 25 sectors either way.
    EXPECT_EQ(alignScans("08", 1500, 720, config).shift, -a.shift);
  }
}

}  // namespace
}  // namespace scan_context_loop
