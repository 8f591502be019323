// Real KITTI scans from ../shared/data, read in place.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "test_scenes.h"
#include "../common/planar.h"

namespace scan_context_loop {
namespace {

using test::kDeg;

using test::kittiScan;

Alignment alignScans(const std::string& sequence, int query, int match, const Config& config) {
  return align(makeDescriptor(kittiScan(sequence, query), config), makeDescriptor(kittiScan(sequence, match), config),
               config);
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

/// The distance at `shift` computed in float from the grids, as the descriptor held it before its unit
/// columns were quantised: the mean of the cosines over the columns occupied in both.
double floatDistanceAtShift(const HeightGrid& query, const HeightGrid& match, int shift) {
  const int sectors = static_cast<int>(query.heights.cols());
  double similarity = 0.0;
  int shared = 0;
  for (int j = 0; j < sectors; ++j) {
    const int k = ((j - shift) % sectors + sectors) % sectors;
    if (!query.occupied.col(j).any() || !match.occupied.col(k).any()) continue;
    ++shared;
    const float nq = query.heights.col(j).norm(), nm = match.heights.col(k).norm();
    if (nq > 0.0f && nm > 0.0f) similarity += query.heights.col(j).dot(match.heights.col(k)) / (nq * nm);
  }
  return shared == 0 ? 1.0 : 1.0 - similarity / shared;
}

TEST(RealData, QuantisedDistancesStayCloseToFloat) {
  // Every pair of the six real scans (consecutive frames, places apart, a reverse revisit), at every shift.
  constexpr double kBound = 0.002;  // the bound doc/core_library.md states
  const std::vector<std::pair<std::string, int>> scans = {{"00", 94},  {"00", 95},  {"00", 198},
                                                          {"00", 199}, {"08", 720}, {"08", 1500}};
  Config config;
  std::vector<HeightGrid> grids;
  std::vector<Descriptor> descriptors;
  for (const auto& [sequence, frame] : scans) {
    grids.push_back(makeHeightGrid(kittiScan(sequence, frame), config));
    descriptors.push_back(makeDescriptor(grids.back(), config));
  }
  double worst = 0.0;
  for (std::size_t a = 0; a < scans.size(); ++a) {
    for (std::size_t b = 0; b < scans.size(); ++b) {
      for (int shift = 0; shift < config.num_sectors; ++shift) {
        const double quantised = distanceAtShift(descriptors[a], descriptors[b], shift);
        const double exact = floatDistanceAtShift(grids[a], grids[b], shift);
        worst = std::max(worst, std::fabs(quantised - exact));
        ASSERT_NEAR(quantised, exact, kBound) << "scans " << a << " and " << b << ", shift " << shift;
      }
    }
  }
  // Not a vacuous comparison: the distances do differ, by rounding.
  EXPECT_GT(worst, 0.0);
  std::printf("largest difference between quantised and float distances: %.5f\n", worst);
}

}  // namespace
}  // namespace scan_context_loop
