// The suburb: its drive (a ring of curving streets with cul-de-sacs, revisited both ways and a lane
// over) and its world (houses on plots, driveways, side fences, verge trees).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "footprint.h"
#include "../../test/common/planar.h"

#include "scan_context_sim/sensor.h"
#include "scan_context_sim/suburb_drive.h"
#include "scan_context_sim/trajectory.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {
namespace {

using test::distanceTo;

using scan_context_loop::test::headingGap;

/// The suburb's world, timed along `drive`.
WorldOptions suburbAlong(const TimedPath& drive) {
  WorldOptions options;
  suburbWorld(&options);
  options.times = drive.times;
  options.duration = drive.times.back();
  return options;
}

TEST(Suburb, TheDriveRevisitsItsStreetsTheSameWayALaneOverAndTheOtherWay) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    SuburbOptions options;
    options.seed = seed;
    const TimedPath drive = suburbDrive(options);
    ASSERT_EQ(drive.path.size(), drive.times.size());
    const std::vector<double> along = distanceAlong(drive.path);
    EXPECT_GT(along.back(), 2200.0) << seed;
    EXPECT_LT(along.back(), 3200.0) << seed;
    // The stop between the laps.
    std::size_t stop = 0;
    for (std::size_t k = 1; k < drive.times.size(); ++k) {
      if (drive.times[k] - drive.times[k - 1] > 1000.0) stop = k;
    }
    ASSERT_GT(stop, 0u) << seed;
    // Each point of lap 2, by the nearest lap 1 point: in the same lane the same way, a lane over
    // (2.5-4 m) the same way, or the other way.
    int same = 0, lane_over = 0, reverse = 0, lap2 = 0;
    for (std::size_t k = stop; k < drive.path.size(); k += 4, ++lap2) {
      const PathPoint& q = drive.path[k];
      double best = 1e9;
      std::size_t nearest = 0;
      for (std::size_t i = 0; i < stop; ++i) {
        const double d = std::hypot(drive.path[i].x - q.x, drive.path[i].y - q.y);
        if (d < best) best = d, nearest = i;
      }
      const double turn = headingGap(drive.path[nearest].heading, q.heading);
      same += best < 0.5 && turn < 0.3;
      lane_over += best > 2.5 && best < 4.0 && turn < 0.3;
      reverse += best < 4.0 && turn > M_PI - 0.3;
    }
    std::printf("seed %u: %.0f m, lap 2 points %d: same lane %d, a lane over %d, the other way %d\n", seed,
                along.back(), lap2, same, lane_over, reverse);
    EXPECT_GT(same, lap2 / 20) << seed;       // the cul-de-sac driven again
    EXPECT_GT(lane_over, lap2 / 6) << seed;   // half the ring a lane to the left
    EXPECT_GT(reverse, lap2 / 3) << seed;     // the whole ring the other way
    // Deterministic from the seed; another seed is another suburb.
    const TimedPath again = suburbDrive(options);
    ASSERT_EQ(again.path.size(), drive.path.size());
    EXPECT_EQ(again.path[500].x, drive.path[500].x);
    options.seed = seed + 10;
    EXPECT_NE(suburbDrive(options).path[500].x, drive.path[500].x);
  }
}

TEST(Suburb, HousesOnPlotsBehindGardensWithDrivewaysAndSideFencesAndTheRoadsOpen) {
  const TimedPath drive = suburbDrive(SuburbOptions());
  WorldOptions options = suburbAlong(drive);
  const World world = generateWorld(drive.path, options);
  int houses = 0, roofs = 0, side_fences = 0, driveway_cars = 0, trees = 0, kerb_cars = 0;
  double nearest_house = 1e9, nearest_solid = 1e9;
  const auto nearestPoint = [&](const Eigen::Vector2d& c) {
    std::size_t best = 0;
    double d = 1e9;
    for (std::size_t k = 0; k < drive.path.size(); k += 2) {
      const double e = std::hypot(drive.path[k].x - c.x(), drive.path[k].y - c.y());
      if (e < d) d = e, best = k;
    }
    return std::make_pair(best, d);
  };
  for (const auto& p : world.primitives()) {
    const Eigen::Vector2d c(p.center.x(), p.center.y());
    const double ground = world.groundZ(c.x(), c.y());
    if (p.material == Material::kBuilding) {
      (p.z0 > ground + 1.0 ? roofs : houses) += 1;
    }
    if (p.material == Material::kFoliage && p.kind == Primitive::Kind::kEllipsoid && p.free_path > 0.7f) ++trees;
    if (p.material == Material::kWall && p.kind == Primitive::Kind::kBox && p.half.x() < 0.05f && p.half.y() > 4.0f)
      ++side_fences;  // thin across the street, long away from it
    if (p.material == Material::kCar && p.z0 < ground + 0.5) {
      const auto near = nearestPoint(c);
      const double turn = headingGap(p.yaw, drive.path[near.first].heading);
      (std::fabs(turn - M_PI / 2) < 0.3 ? driveway_cars : kerb_cars) += 1;
    }
    if (p.material != Material::kPavement) {
      for (std::size_t k = 0; k < drive.path.size(); k += 3) {
        const double d = distanceTo(p, Eigen::Vector2d(drive.path[k].x, drive.path[k].y));
        nearest_solid = std::min(nearest_solid, d);
        if (p.material == Material::kBuilding) nearest_house = std::min(nearest_house, d);
      }
    }
  }
  std::printf("%d houses and garages, %d roof tiers, %d side fences, %d trees, cars: %d on driveways, %d at the kerb; "
              "nearest house %.1f m, nearest solid %.1f m from the path\n",
              houses, roofs, side_fences, trees, driveway_cars, kerb_cars, nearest_house, nearest_solid);
  EXPECT_GT(houses, 100);
  EXPECT_GT(roofs, houses);  // two tiers on every house, none on garages
  EXPECT_GT(side_fences, 50);
  EXPECT_GT(trees, 150);
  EXPECT_GT(driveway_cars, kerb_cars);
  EXPECT_GT(nearest_house, 6.9);   // behind the property line (kerb 4.5 m, verge 2.5 m) from every lane
  EXPECT_GT(nearest_solid, 1.4);   // a canopy reaching over the road keeps 1.5 m from the lane
  // A seed repeats the world exactly.
  const World again = generateWorld(drive.path, options);
  ASSERT_EQ(again.size(), world.size());
  for (std::size_t i = 0; i < world.size(); i += 7) {
    EXPECT_EQ(again.primitives()[i].center, world.primitives()[i].center);
    EXPECT_EQ(again.primitives()[i].half, world.primitives()[i].half);
  }
}

TEST(Suburb, AScanHasReturnsAboveTheGroundFromHousesFencesCarsAndTrees) {
  const TimedPath drive = suburbDrive(SuburbOptions());
  WorldOptions options = suburbAlong(drive);
  const World world = generateWorld(drive.path, options);
  SensorModel hdl;
  ASSERT_TRUE(sensorPreset("hdl64", &hdl));
  hdl.columns = 1000;
  std::size_t points = 0;
  for (std::size_t k : {400u, 1500u, 2600u}) {
    const Eigen::Isometry3d pose = sensorPose(world, drive.path[k], hdl.mount_height);
    const auto cloud = scan(world, hdl, pose, drive.times[k], 5);
    points += cloud.size();
    std::size_t above = 0;  // returns above the ground: houses, fences, cars, trees
    for (const auto& p : cloud) above += p.z > -1.2f;
    EXPECT_GT(above, cloud.size() / 8) << k;  // open streets: most returns are ground
  }
  EXPECT_GT(points, 3u * 20000u);
}

/// Rays of the sensor's pattern from `pose` at time t, by the material they first hit (no noise,
/// dropout or fading: what is there to see).
std::map<Material, int> returnsByClass(const World& world, const SensorModel& sensor, const Eigen::Isometry3d& pose,
                                       double t) {
  std::map<Material, int> count;
  std::vector<std::uint32_t> visit(world.size(), 0);
  std::uint32_t ray = 0;
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  const Eigen::Vector3f origin = pose.translation().cast<float>();
  for (const Eigen::Vector3f& local : rayDirections(sensor, t)) {
    Hit hit;
    if (world.cast(origin, rotation * local, sensor.max_range, t, ++ray, &visit, &hit)) ++count[hit.material];
  }
  return count;
}

TEST(Suburb, EveryHarderChangeShowsInAScanOfTheSecondLap) {
  const TimedPath drive = suburbDrive(SuburbOptions());
  WorldOptions options = suburbAlong(drive);
  options.changed_world = 1.0;
  const World before = generateWorld(drive.path, options);
  options.season = options.construction = options.furniture = options.pass_traffic = 1.0;
  const World after = generateWorld(drive.path, options);
  SensorModel vlp;
  ASSERT_TRUE(sensorPreset("vlp16", &vlp));
  const char* names[] = {"ground", "pavement", "building", "wall", "car", "trunk", "foliage", "pole", "sign",
                         "person", "branch", "container"};
  std::map<Material, int> total_before, total_after;
  // Every 150th point of the second lap.
  std::size_t stop = 0;
  for (std::size_t k = 1; k < drive.times.size(); ++k) stop = drive.times[k] - drive.times[k - 1] > 1000.0 ? k : stop;
  for (std::size_t k = stop; k < drive.path.size(); k += 150) {
    const Eigen::Isometry3d pose = sensorPose(after, drive.path[k], vlp.mount_height);
    for (const auto& c : returnsByClass(before, vlp, pose, drive.times[k])) total_before[c.first] += c.second;
    for (const auto& c : returnsByClass(after, vlp, pose, drive.times[k])) total_after[c.first] += c.second;
  }
  for (int m = 0; m <= static_cast<int>(Material::kContainer); ++m) {
    const Material material = static_cast<Material>(m);
    std::printf("%-9s %7d -> %7d\n", names[m], total_before[material], total_after[material]);
  }
  EXPECT_LT(total_after[Material::kFoliage], total_before[Material::kFoliage] * 3 / 4);  // leaf-off
  EXPECT_GT(total_after[Material::kBranch], 0);
  EXPECT_GT(total_after[Material::kBuilding], total_before[Material::kBuilding] / 2);  // the houses stay
  EXPECT_EQ(total_before[Material::kBranch] + total_before[Material::kContainer], 0);
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
