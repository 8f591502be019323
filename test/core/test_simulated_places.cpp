// Scan Context on simulated revisits: scans of the same place, driven past again after two loops, are
// closer than scans 60 m apart.
#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_sim/sensor.h"
#include "scan_context_sim/trajectory.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {
namespace {

TEST(Simulation, ScansOfTheSamePlaceAreCloserThanScansFarApart) {
  const auto path = proceduralPath();
  WorldOptions options;
  options.duration = 220.0;  // the drive at 10 m/s: some parked cars change between the visits
  const World world = generateWorld(path, options);
  SensorModel hdl;
  ASSERT_TRUE(sensorPreset("hdl64", &hdl));
  hdl.columns = 900;  // coarser, faster; enough for the descriptor
  // Path point 100 is 50 m into the first loop; find where the same-lane revisit passes it again (after
  // two loops, more than 1,500 m later) and a point 60 m further on in the first loop.
  const std::size_t here = 100, far = 220;
  std::size_t again = 0;
  double best = 1e9;
  for (std::size_t k = 3000; k < path.size(); ++k) {
    const double d = std::hypot(path[k].x - path[here].x, path[k].y - path[here].y);
    if (d < best && std::fabs(std::remainder(path[k].heading - path[here].heading, 2 * M_PI)) < 0.1) {
      best = d;
      again = k;
    }
  }
  ASSERT_LT(best, 0.5);
  again += 2;  // a metre further on: revisits never stop at exactly the same spot
  const double t_here = here * 0.05, t_again = again * 0.05;  // 0.5 m apart at 10 m/s
  Config config;
  const auto describe = [&](std::size_t k, double t, std::uint64_t seed) {
    return makeDescriptor(scan(world, hdl, sensorPose(world, path[k], hdl.mount_height), t, seed), config);
  };
  const Descriptor a = describe(here, t_here, 1);
  const double revisit = align(a, describe(again, t_again, 2), config).distance;
  const double apart = align(a, describe(far, far * 0.05, 3), config).distance;
  EXPECT_LT(revisit, 0.3);
  EXPECT_GT(apart, 1.5 * revisit);
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
