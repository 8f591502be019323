// A second session of a drive: the same world on another day, driven back the other way in the other lane.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "footprint.h"
#include "scan_context_sim/second_session.h"
#include "scan_context_sim/sensor.h"
#include "scan_context_sim/trajectory.h"
#include "scan_context_sim/world.h"
#include "../../test/common/planar.h"

namespace scan_context_loop {
namespace sim {
namespace {

using test::always;
using test::present;
using test::sameShape;

using scan_context_loop::test::yawOf;

/// The procedural drive (2.1 km) at 10 m/s, and the world built along it with dynamic parked cars.
struct FirstDrive {
  std::vector<PathPoint> path = proceduralPath();
  WorldOptions options;
  FirstDrive() {
    options.times.assign(path.size(), 0.0);
    for (std::size_t k = 1; k < path.size(); ++k) {
      options.times[k] = options.times[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y) / 10.0;
    }
    options.duration = options.times.back();
    options.changed_world = 0.3;  // session 1 sees some changes of its own
  }
};

/// The procedural drive (corners rounded, 8 m radius) at 10 m/s.
std::vector<double> timesAt10(const std::vector<PathPoint>& path) {
  std::vector<double> times(path.size(), 0.0);
  for (std::size_t k = 1; k < path.size(); ++k) {
    times[k] = times[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y) / 10.0;
  }
  return times;
}

TEST(SecondSession, DrivesTheFirstBackwardsInTheOtherLaneWithItsOwnClock) {
  const std::vector<PathPoint> path = proceduralPath();
  const std::vector<double> times = timesAt10(path);
  SecondSessionOptions options;
  options.lane_offset = 3.0;
  const TimedPath second = secondSessionDrive(path, times, options);
  const std::size_t n = path.size();
  ASSERT_EQ(second.path.size(), n);
  ASSERT_EQ(second.times.size(), n);
  EXPECT_EQ(second.times.front(), 0.0);
  EXPECT_NEAR(second.times.back(), times.back(), 1e-9);
  for (std::size_t k = 0; k < n; ++k) {
    const PathPoint &a = path[n - 1 - k], &b = second.path[k];
    if (k > 0) {
      EXPECT_GE(second.times[k], second.times[k - 1]);
    }
    EXPECT_NEAR(std::hypot(b.x - a.x, b.y - a.y), 3.0, 1e-9);
    EXPECT_NEAR(std::fabs(std::remainder(b.heading - a.heading, 2.0 * M_PI)), M_PI, 1e-9);
    // To the left of the first drive's direction: the other lane of a street driven on the right.
    EXPECT_GT(std::cos(a.heading) * (b.y - a.y) - std::sin(a.heading) * (b.x - a.x), 2.99);
  }
}

TEST(SecondSession, TurnsInsideSharpCornersWithoutFoldingBack) {
  std::vector<PathPoint> lap = blockPath(false);  // square corners
  lap.resize(300);                                // three sides of the block: two corners
  const TimedPath second = secondSessionDrive(lap, timesAt10(lap), SecondSessionOptions());
  ASSERT_LT(second.path.size(), lap.size());
  ASSERT_GT(second.path.size(), lap.size() - 30);
  double longest = 0.0;
  for (std::size_t k = 0; k < second.path.size(); ++k) {
    const PathPoint& q = second.path[k];
    for (const PathPoint& p : lap) ASSERT_GE(std::hypot(p.x - q.x, p.y - q.y), 3.0 - 1e-6);
    if (k > 0) longest = std::max(longest, std::hypot(q.x - second.path[k - 1].x, q.y - second.path[k - 1].y));
  }
  EXPECT_LT(longest, 0.8);
  EXPECT_EQ(second.times.front(), 0.0);
}

TEST(SecondSession, SeesTheFirstSessionsWorldChangedOnlyFromItsStart) {
  const FirstDrive first;
  const SecondSessionOptions options;
  const TimedPath second = secondSessionDrive(first.path, first.options.times, options);
  const LaterDrive later = laterDrive(second, first.options.duration, options);
  EXPECT_NEAR(later.times.front(), first.options.duration + 86400.0, 1e-6);
  const World world1 = generateWorld(first.path, first.options);
  const World world2 = generateWorld(first.path, first.options, later);
  ASSERT_GT(world2.size(), world1.size() + 50);
  // Everything session 1 saw is there, the same shape, at the same times during session 1; what is new
  // comes after it.
  for (std::size_t i = 0; i < world1.size(); ++i) {
    const Primitive &a = world1.primitives()[i], &b = world2.primitives()[i];
    ASSERT_TRUE(sameShape(a, b)) << i;
    for (std::size_t k = 0; k < first.options.times.size(); k += 50) {
      ASSERT_EQ(present(a, first.options.times[k]), present(b, first.options.times[k])) << i;
    }
    if (a.material == Material::kBuilding || a.material == Material::kPole || a.material == Material::kTrunk) {
      EXPECT_TRUE(always(b)) << i;
    }
  }
  for (std::size_t i = world1.size(); i < world2.size(); ++i) {
    EXPECT_GE(world2.primitives()[i].present_from, later.times.front()) << i;
  }
  // Ray cast from one pose: session 2's world with nothing changed since is session 1's after its end.
  LaterDrive unchanged = later;
  unchanged.changed = 0.0;
  const World same = generateWorld(first.path, first.options, unchanged);
  SensorModel sensor;
  ASSERT_TRUE(sensorPreset("vlp16", &sensor));
  const Eigen::Isometry3d pose = sensorPose(world1, second.path[200], sensor.mount_height);
  const auto a = scan(world1, sensor, pose, first.options.duration + 100.0, 7);
  const auto b = scan(same, sensor, pose, later.times.front(), 7);
  ASSERT_GT(a.size(), 5000u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].getVector3fMap(), b[i].getVector3fMap()) << i;
}

TEST(SecondSession, ParkedCarsAndVegetationChangedByTheNextDay) {
  const FirstDrive first;
  const SecondSessionOptions options;  // changed 1: every car and plant that stood unchanged changes
  const LaterDrive later =
      laterDrive(secondSessionDrive(first.path, first.options.times, options), first.options.duration, options);
  const World world1 = generateWorld(first.path, first.options);
  const World world2 = generateWorld(first.path, first.options, later);
  const double end = first.options.duration, day2 = later.times.front();
  int cars = 0, cars_gone = 0, canopies = 0, canopies_changed = 0;
  for (std::size_t i = 0; i < world1.size(); ++i) {
    const Primitive &a = world1.primitives()[i], &b = world2.primitives()[i];
    if (!always(a)) continue;  // changed during session 1 already
    const bool body = a.material == Material::kCar && a.z0 < world1.groundZ(a.center.x(), a.center.y()) + 0.5;
    const bool canopy = a.kind == Primitive::Kind::kEllipsoid && a.free_path > 0.7f;
    cars += body, cars_gone += body && present(a, end) && !present(b, day2);
    canopies += canopy, canopies_changed += canopy && !present(b, day2);
  }
  ASSERT_GT(cars, 50);
  ASSERT_GT(canopies, 30);
  // Those that move or are replaced are gone from their place too; only the few parked cars the first
  // drive left in place when they had no room to move stay.
  EXPECT_GT(cars_gone, 0.9 * cars);
  EXPECT_EQ(canopies_changed, canopies);
  int arrived = 0, passing = 0;
  for (std::size_t i = world1.size(); i < world2.size(); ++i) {
    const Primitive& p = world2.primitives()[i];
    arrived += p.material == Material::kCar && p.present_from == day2 && p.present_to > 1e299;
    passing += p.material == Material::kCar && p.present_to - p.present_from <= 1.0;
  }
  EXPECT_GT(arrived, cars / 4);
  EXPECT_GT(passing, 10);  // traffic during session 2
}

TEST(SecondSession, TruthIsInTheFirstSessionsFrame) {
  const std::vector<PathPoint> path = proceduralPath();
  const TimedPath second = secondSessionDrive(path, timesAt10(path), SecondSessionOptions());
  const World world = generateWorld(path, WorldOptions());
  const std::size_t n = path.size();
  ASSERT_EQ(second.path.size(), n);
  for (std::size_t k = 0; k < n; k += 40) {
    const Eigen::Isometry3d a = sensorPose(world, path[n - 1 - k], 1.73);
    const Eigen::Isometry3d b = sensorPose(world, second.path[k], 1.73);
    // The same place in one frame: a lane apart, at the same height over the same ground, facing back.
    const Eigen::Vector3d in_a = a.inverse() * b.translation();
    EXPECT_NEAR(in_a.x(), 0.0, 0.05);
    EXPECT_NEAR(in_a.y(), 3.0, 0.05);
    EXPECT_NEAR(in_a.z(), 0.0, 0.05);
    EXPECT_NEAR(std::fabs(yawOf(a.inverse() * b)), M_PI, 1e-3);
  }
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
