// The narrow walk: a campus or old-town path with revisits both ways, kept clear, between walls a
// few metres away.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "footprint.h"

#include "scan_context_sim/narrow_drive.h"
#include "scan_context_sim/sensor.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {
namespace {

double angleBetween(double a, double b) { return std::fabs(std::remainder(a - b, 2.0 * M_PI)); }

using test::distanceTo;

WorldOptions worldFor(const NarrowOptions& narrow, const TimedPath& drive) {
  WorldOptions world;
  world.seed = narrow.seed;
  world.duration = drive.times.back();
  world.times = drive.times;
  narrowWorld(narrow, &world);
  return world;
}

TEST(NarrowDrive, AWalkWithRevisitsBothWaysEndingAtTheStart) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    NarrowOptions options;
    options.seed = seed;
    const TimedPath drive = narrowDrive(options);
    const std::vector<PathPoint>& path = drive.path;
    ASSERT_EQ(drive.times.size(), path.size());
    const std::vector<double> s = distanceAlong(path);
    EXPECT_GT(s.back(), 1100.0) << "seed " << seed;
    EXPECT_LT(s.back(), 1500.0) << "seed " << seed;
    // Walking pace, and back where it started.
    EXPECT_NEAR(drive.times.back(), s.back() / 1.5, 1e-6);
    EXPECT_LT(std::hypot(path.back().x - path.front().x, path.back().y - path.front().y), 1.0) << "seed " << seed;
    // Metres walked again, at least 100 m of walking after an earlier visit within 1 m of it.
    double same = 0.0, reverse = 0.0;
    for (std::size_t k = 0; k < path.size(); k += 2) {
      bool same_here = false, reverse_here = false;
      for (std::size_t j = 0; j < k && s[j] < s[k] - 100.0; ++j) {
        if (std::hypot(path[k].x - path[j].x, path[k].y - path[j].y) > 1.0) continue;
        const double turn = angleBetween(path[k].heading, path[j].heading);
        same_here |= turn < 0.3;
        reverse_here |= turn > M_PI - 0.3;
      }
      same += same_here ? 1.0 : 0.0;  // points every 0.5 m, every second one checked
      reverse += reverse_here ? 1.0 : 0.0;
    }
    // About 140 m the same way (the loop's south lane, half its west lane) and 250 m the other way.
    EXPECT_GT(same, 120.0) << "seed " << seed;
    EXPECT_GT(reverse, 200.0) << "seed " << seed;
    // Deterministic from the seed.
    EXPECT_EQ(narrowDrive(options).path[300].x, path[300].x);
  }
}

TEST(NarrowDrive, NothingWithinOneAndAHalfMetresOfThePath) {
  for (double changed : {0.0, 1.0}) {
    NarrowOptions options;
    options.seed = changed > 0.0 ? 2 : 1;
    const TimedPath drive = narrowDrive(options);
    WorldOptions world_options = worldFor(options, drive);
    world_options.changed_world = changed;  // construction and pedestrians too
    const World world = generateWorld(drive.path, world_options);
    ASSERT_GT(world.size(), 500u);
    std::size_t vehicles = 0;
    for (const Primitive& p : world.primitives()) {
      vehicles += p.material == Material::kCar;
      double nearest = 1e9;
      for (const PathPoint& q : drive.path) nearest = std::min(nearest, distanceTo(p, Eigen::Vector2d(q.x, q.y)));
      // Lamp arms stop at 1.5 m exactly; the solids are stored in floats.
      EXPECT_GT(nearest, 1.5 - 1e-4) << "material " << static_cast<int>(p.material) << " changed " << changed;
    }
    EXPECT_EQ(vehicles, 0u);
  }
}

TEST(NarrowDrive, WallsAFewMetresAway) {
  NarrowOptions options;
  const TimedPath drive = narrowDrive(options);
  const World world = generateWorld(drive.path, worldFor(options, drive));
  SensorModel sensor;
  ASSERT_TRUE(sensorPreset("hdl64", &sensor));
  // Mid-lane points along the walk, away from the junctions.
  for (std::size_t k : {60u, 700u, 1300u, 1900u}) {
    const auto cloud = scan(world, sensor, sensorPose(world, drive.path[k], sensor.mount_height), drive.times[k], k);
    ASSERT_GT(cloud.size(), 50000u);
    std::vector<double> ranges;
    for (const auto& pt : cloud) ranges.push_back(std::hypot(pt.x, pt.y));
    std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
    EXPECT_LT(ranges[ranges.size() / 2], 10.0) << "path point " << k;
  }
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
