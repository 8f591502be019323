#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "scan_context_loop/alignment.h"
#include "scan_context_loop/sim/sensor.h"
#include "scan_context_loop/sim/trajectory.h"

namespace scan_context_loop {
namespace sim {
namespace {

Hit castOne(const World& world, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, bool* found) {
  std::vector<std::uint32_t> visit(world.size(), 0);
  Hit hit;
  *found = world.cast(origin, direction.normalized(), 200.0f, 0.0, 1, &visit, &hit);
  return hit;
}

TEST(World, RaysHitBoxesCylindersAndEllipsoidsWhereExpected) {
  Primitive box;
  box.kind = Primitive::Kind::kBox;
  box.center = Eigen::Vector3f(20, 0, 0);
  box.half = Eigen::Vector3f(2, 5, 0);
  box.yaw = static_cast<float>(M_PI / 2);  // now 10 m along x, 4 m along y
  box.z0 = 0;
  box.z1 = 10;
  Primitive pole;
  pole.kind = Primitive::Kind::kCylinder;
  pole.material = Material::kPole;
  pole.center = Eigen::Vector3f(0, 10, 0);
  pole.half = Eigen::Vector3f::Constant(0.5f);
  pole.z0 = 0;
  pole.z1 = 6;
  Primitive canopy;
  canopy.kind = Primitive::Kind::kEllipsoid;
  canopy.material = Material::kFoliage;
  canopy.center = Eigen::Vector3f(-10, 0, 5);
  canopy.half = Eigen::Vector3f(2, 2, 1);
  const World world({box, pole, canopy}, Eigen::Vector3d::Zero());
  const Eigen::Vector3f origin(0, 0, 2);
  bool found = false;
  Hit h = castOne(world, origin, Eigen::Vector3f(1, 0, 0), &found);
  ASSERT_TRUE(found);
  EXPECT_NEAR(h.range, 15.0f, 1e-4f);  // the rotated box's near face is at x = 20 - 5
  EXPECT_EQ(h.material, Material::kBuilding);
  EXPECT_NEAR(h.normal.x(), -1.0f, 1e-5f);
  h = castOne(world, origin, Eigen::Vector3f(0, 1, 0), &found);
  ASSERT_TRUE(found);
  EXPECT_NEAR(h.range, 9.5f, 1e-4f);
  EXPECT_EQ(h.material, Material::kPole);
  h = castOne(world, origin, Eigen::Vector3f(-10, 0, 3), &found);  // towards the canopy centre
  ASSERT_TRUE(found);
  EXPECT_EQ(h.material, Material::kFoliage);
  // Along s in [0, 1] from the origin to the centre: (10 (1 - s) / 2)^2 + (3 (1 - s) / 1)^2 = 1.
  EXPECT_NEAR(h.range, std::sqrt(109.0f) * (1.0f - 1.0f / std::sqrt(34.0f)), 1e-3f);
  // Over the pole's top: nothing but the ground far away.
  h = castOne(world, Eigen::Vector3f(0, 0, 8), Eigen::Vector3f(0, 1, 0), &found);
  EXPECT_FALSE(found);
  h = castOne(world, origin, Eigen::Vector3f(0, -1, -1), &found);
  ASSERT_TRUE(found);
  EXPECT_EQ(h.material, Material::kGround);
  EXPECT_NEAR(h.range, 2.0f * std::sqrt(2.0f), 1e-4f);
}

TEST(World, AbsentCarsAreNotSeen) {
  Primitive car;
  car.kind = Primitive::Kind::kBox;
  car.material = Material::kCar;
  car.center = Eigen::Vector3f(5, 0, 0);
  car.half = Eigen::Vector3f(2, 1, 0);
  car.z0 = 0;
  car.z1 = 1.5f;
  car.present_from = 10.0;
  car.present_to = 20.0;
  const World world({car}, Eigen::Vector3d(0, 0, -5));
  std::vector<std::uint32_t> visit(1, 0);
  Hit hit;
  EXPECT_TRUE(world.cast(Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(1, 0, 0), 100, 15.0, 1, &visit, &hit));
  EXPECT_FALSE(world.cast(Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(1, 0, 0), 100, 25.0, 2, &visit, &hit));
}

TEST(Sensor, Hdl64BeamPatternOnFlatGround) {
  SensorModel hdl;
  ASSERT_TRUE(sensorPreset("hdl64", &hdl));
  ASSERT_EQ(hdl.elevations_deg.size(), 64u);
  EXPECT_FLOAT_EQ(hdl.elevations_deg.front(), 2.0f);
  EXPECT_FLOAT_EQ(hdl.elevations_deg.back(), -24.9f);
  hdl.range_noise = 0.0f;
  hdl.dropout = 0.0f;
  const World flat({}, Eigen::Vector3d::Zero());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().z() = hdl.mount_height;
  const auto cloud = scan(flat, hdl, pose, 0.0, 1);
  // Beams at or above the horizon never reach flat ground; the others all do (ranges under 100 m).
  std::set<int> rings;
  double nearest = 1e9;
  for (const auto& p : cloud) {
    const double r = std::hypot(p.x, p.y);
    nearest = std::min(nearest, r);
    rings.insert(static_cast<int>(std::lround(std::atan2(p.z, r) * 180.0 / M_PI * 100)));
    EXPECT_NEAR(p.z, -hdl.mount_height, 1e-3);
  }
  // The -24.9 degree beam meets the ground 1.73 / tan(24.9 deg) = 3.73 m away.
  EXPECT_NEAR(nearest, 1.73 / std::tan(24.9 * M_PI / 180.0), 0.01);
  int reaching = 0;
  for (float e : hdl.elevations_deg) reaching += (e < 0 && hdl.mount_height / std::tan(-e * M_PI / 180) < 100);
  EXPECT_EQ(static_cast<int>(rings.size()), reaching);
  EXPECT_EQ(cloud.size(), static_cast<std::size_t>(reaching * hdl.columns));
  SensorModel vlp;
  EXPECT_TRUE(sensorPreset("vlp16", &vlp));
  EXPECT_EQ(vlp.elevations_deg.size(), 16u);
  EXPECT_TRUE(sensorPreset("os1-64", &vlp));
  EXPECT_FALSE(sensorPreset("hdl32e", &vlp));
}

TEST(Trajectory, KeyframeSpacingAndProceduralDrive) {
  const auto path = proceduralPath();
  const auto keys = keyframesEvery(path, 2.0);
  for (std::size_t k = 1; k < keys.size(); ++k) {
    double travelled = 0.0;
    for (std::size_t i = keys[k - 1] + 1; i <= keys[k]; ++i) {
      travelled += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
    }
    EXPECT_GE(travelled, 2.0 - 1e-9);
    EXPECT_LT(travelled, 2.6);  // path points are 0.5 m apart
  }
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  EXPECT_GT(length, 2000.0);
  EXPECT_LT(length, 2300.0);
}

TEST(Trajectory, DriftGrowsWithTheConfiguredRate) {
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < 500; ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = 2.0 * k;
    truth.push_back(pose);
  }
  DriftOptions none;
  none.translation_per_metre = none.yaw_per_metre = none.yaw_per_degree = 0.0;
  const auto exact = driftedOdometry(truth, none);
  EXPECT_TRUE(exact.back().isApprox(truth.back(), 1e-9));
  double previous = 0.0;
  for (double rate : {0.002, 0.02}) {
    DriftOptions drift;
    drift.translation_per_metre = rate;
    drift.yaw_per_metre = rate;
    double sum = 0.0;
    for (std::uint32_t seed = 1; seed <= 5; ++seed) {
      drift.seed = seed;
      sum += (driftedOdometry(truth, drift).back().translation() - truth.back().translation()).norm();
    }
    EXPECT_GT(sum / 5, 0.0);
    EXPECT_GT(sum / 5, 3.0 * previous) << rate;
    previous = sum / 5;
  }
}

TEST(WorldGeneration, SeededStreetsWithNothingOnTheRoad) {
  const auto path = proceduralPath();
  WorldOptions options;
  options.seed = 3;
  const World a = generateWorld(path, options);
  const World b = generateWorld(path, options);
  options.seed = 4;
  const World c = generateWorld(path, options);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a.primitives()[i].center, b.primitives()[i].center);
  EXPECT_TRUE(a.size() != c.size() || a.primitives()[5].center != c.primitives()[5].center);
  int buildings = 0, trees = 0, cars = 0, poles = 0;
  for (const auto& p : a.primitives()) {
    buildings += p.material == Material::kBuilding;
    trees += p.material == Material::kTrunk;
    cars += p.material == Material::kCar;
    poles += p.material == Material::kPole;
  }
  EXPECT_GT(buildings, 50);
  EXPECT_GT(trees, 40);
  EXPECT_GT(cars, 100);
  EXPECT_GT(poles, 20);
  // A vertical ray down at every 10th path point sees the ground: nothing stands on the road.
  std::vector<std::uint32_t> visit(a.size(), 0);
  std::uint32_t ray = 0;
  for (std::size_t k = 0; k < path.size(); k += 10) {
    Hit hit;
    ASSERT_TRUE(a.cast(Eigen::Vector3f(path[k].x, path[k].y, 40.0f), Eigen::Vector3f(0, 0, -1), 100, 0.0, ++ray,
                       &visit, &hit));
    EXPECT_EQ(hit.material, Material::kGround) << "path point " << k;
  }
}

TEST(Simulation, SamePlaceScansAreCloserThanScansFarApart) {
  const auto path = proceduralPath();
  WorldOptions options;
  const World world = generateWorld(path, options);
  SensorModel hdl;
  ASSERT_TRUE(sensorPreset("hdl64", &hdl));
  hdl.columns = 900;  // coarser, faster; enough for the descriptor
  // Path index 100 is 50 m into the first loop; the second loop passes 3 m further out.
  const Eigen::Isometry3d here = sensorPose(world, path[100], hdl.mount_height);
  Eigen::Isometry3d nearby = sensorPose(world, path[104], hdl.mount_height);  // 2 m on
  const Eigen::Isometry3d far = sensorPose(world, path[220], hdl.mount_height);  // 60 m on
  Config config;
  const Descriptor a = makeDescriptor(scan(world, hdl, here, 0.0, 1), config);
  const double same = align(a, makeDescriptor(scan(world, hdl, nearby, 0.0, 2), config), config).distance;
  const double apart = align(a, makeDescriptor(scan(world, hdl, far, 0.0, 3), config), config).distance;
  EXPECT_LT(same, 0.35);
  EXPECT_GT(apart, 1.5 * same);
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
