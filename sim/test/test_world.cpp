// Ray casting through the world's solids, and the generated streets.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "scan_context_sim/trajectory.h"
#include "scan_context_sim/world.h"

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
  // Over the box's top edge (z = 10 at x = 15) a ray climbing 8 m in 15 m misses it; one climbing 7.9 hits.
  castOne(world, origin, Eigen::Vector3f(15, 0, 8.1f), &found);
  EXPECT_FALSE(found);
  h = castOne(world, origin, Eigen::Vector3f(15, 0, 7.9f), &found);
  ASSERT_TRUE(found);
  EXPECT_NEAR(h.range, std::sqrt(15.0f * 15.0f + 7.9f * 7.9f), 1e-3f);
  h = castOne(world, origin, Eigen::Vector3f(0, 1, 0), &found);
  ASSERT_TRUE(found);
  EXPECT_NEAR(h.range, 9.5f, 1e-4f);
  EXPECT_EQ(h.material, Material::kPole);
  EXPECT_NEAR(h.normal.y(), -1.0f, 1e-5f);
  h = castOne(world, origin, Eigen::Vector3f(-10, 0, 3), &found);  // towards the canopy centre
  ASSERT_TRUE(found);
  EXPECT_EQ(h.material, Material::kFoliage);
  // Along s in [0, 1] from the origin to the centre: (10 (1 - s) / 2)^2 + (3 (1 - s) / 1)^2 = 1.
  EXPECT_NEAR(h.range, std::sqrt(109.0f) * (1.0f - 1.0f / std::sqrt(34.0f)), 1e-3f);
  // Over the pole's top: nothing but the ground far away.
  castOne(world, Eigen::Vector3f(0, 0, 8), Eigen::Vector3f(0, 1, 0), &found);
  EXPECT_FALSE(found);
  h = castOne(world, origin, Eigen::Vector3f(0, -1, -1), &found);
  ASSERT_TRUE(found);
  EXPECT_EQ(h.material, Material::kGround);
  EXPECT_NEAR(h.range, 2.0f * std::sqrt(2.0f), 1e-4f);
  // From inside a solid nothing of it is seen.
  Hit inside;
  EXPECT_FALSE(intersect(box, Eigen::Vector3f(20, 0, 5), Eigen::Vector3f(1, 0, 0), 100.0f, 0.0f, &inside));
}

TEST(World, SlopedGroundIsHitWhereThePlaneIs) {
  const World world({}, Eigen::Vector3d(0.05, 0.0, 1.0));  // z = 0.05 x + 1
  bool found = false;
  // From (0, 0, 3) straight down: the plane is at z = 1, 2 m below.
  Hit h = castOne(world, Eigen::Vector3f(0, 0, 3), Eigen::Vector3f(0, 0, -1), &found);
  ASSERT_TRUE(found);
  EXPECT_NEAR(h.range, 2.0f, 1e-5f);
  // Level ray towards +x meets the rising plane where 0.05 x + 1 = 3: x = 40.
  h = castOne(world, Eigen::Vector3f(0, 0, 3), Eigen::Vector3f(1, 0, 0), &found);
  ASSERT_TRUE(found);
  EXPECT_NEAR(h.range, 40.0f, 1e-3f);
  castOne(world, Eigen::Vector3f(0, 0, 3), Eigen::Vector3f(-1, 0, 0), &found);
  EXPECT_FALSE(found);  // the plane falls away
}

TEST(World, PorousCanopiesReturnFromTheirDepthAndLetSomeRaysThrough) {
  Primitive canopy;
  canopy.kind = Primitive::Kind::kEllipsoid;
  canopy.material = Material::kFoliage;
  canopy.center = Eigen::Vector3f(10, 0, 10);
  canopy.half = Eigen::Vector3f(2, 2, 2);
  canopy.free_path = 2.0f;
  Hit hit;
  // Entry at x = 8: scatter 0 returns at the surface; a scatter past exp(-4 / 2) passes the 4 m chord.
  ASSERT_TRUE(intersect(canopy, Eigen::Vector3f(0, 0, 10), Eigen::Vector3f(1, 0, 0), 100.0f, 0.0f, &hit));
  EXPECT_NEAR(hit.range, 8.0f, 1e-4f);
  ASSERT_TRUE(intersect(canopy, Eigen::Vector3f(0, 0, 10), Eigen::Vector3f(1, 0, 0), 100.0f, 0.5f, &hit));
  EXPECT_NEAR(hit.range, 8.0f + 2.0f * std::log(2.0f), 1e-4f);
  EXPECT_FALSE(intersect(canopy, Eigen::Vector3f(0, 0, 10), Eigen::Vector3f(1, 0, 0), 100.0f, 0.9f, &hit));

  // Through the world, each ray draws its own depth: the pass-through fraction is exp(-chord / free
  // path) and the mean depth of the returns is that of an exponential cut at the chord.
  const World world({canopy}, Eigen::Vector3d(0, 0, -100));
  std::vector<std::uint32_t> visit(1, 0);
  int passed = 0, returned = 0;
  double depth = 0.0;
  const int rays = 20000;
  for (int r = 1; r <= rays; ++r) {
    if (world.cast(Eigen::Vector3f(0, 0, 10), Eigen::Vector3f(1, 0, 0), 50.0f, 0.0, r, &visit, &hit)) {
      ++returned;
      depth += hit.range - 8.0f;
    } else {
      ++passed;
    }
  }
  const double through = std::exp(-2.0);
  EXPECT_NEAR(static_cast<double>(passed) / rays, through, 0.01);
  EXPECT_NEAR(depth / returned, 2.0 - 4.0 * through / (1.0 - through), 0.05);
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
  EXPECT_FALSE(world.cast(Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(1, 0, 0), 100, 5.0, 3, &visit, &hit));
}

bool samePrimitive(const Primitive& a, const Primitive& b) {
  return a.kind == b.kind && a.material == b.material && a.center == b.center && a.half == b.half && a.yaw == b.yaw &&
         a.z0 == b.z0 && a.z1 == b.z1 && a.free_path == b.free_path && a.present_from == b.present_from &&
         a.present_to == b.present_to;
}

TEST(WorldGeneration, SeededStreetsWithNothingOnTheRoad) {
  const auto path = proceduralPath();
  WorldOptions options;
  options.seed = 3;
  const World a = generateWorld(path, options);
  const World b = generateWorld(path, options);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(samePrimitive(a.primitives()[i], b.primitives()[i])) << i;
  options.seed = 4;
  const World c = generateWorld(path, options);
  std::size_t differ = a.size() != c.size() ? 1 : 0;
  for (std::size_t i = 0; i < std::min(a.size(), c.size()); ++i)
    differ += !samePrimitive(a.primitives()[i], c.primitives()[i]);
  EXPECT_GT(differ, a.size() / 2);

  // A gentle slope of the configured steepness.
  const double rise_x = a.groundZ(1.0, 0.0) - a.groundZ(0.0, 0.0), rise_y = a.groundZ(0.0, 1.0) - a.groundZ(0.0, 0.0);
  EXPECT_NEAR(std::hypot(rise_x, rise_y), options.ground_slope, 1e-9);

  std::map<Material, int> count;
  float lowest = 1e9f, highest = 0.0f;
  for (const auto& p : a.primitives()) {
    ++count[p.material];
    if (p.material == Material::kBuilding && p.z0 <= a.groundZ(p.center.x(), p.center.y()) + 1e-3) {
      lowest = std::min(lowest, p.z1 - p.z0);
      highest = std::max(highest, p.z1 - p.z0);
    }
  }
  // The drive covers about 950 m of distinct streets, 1.9 km of kerb: a 2 m pavement strip along
  // nearly all of it, and facades, parked cars, trees, lights, walls and signs. (The lower bounds hold
  // for every seed from 1 to 20; how much of each depends on the districts a seed draws.)
  EXPECT_GT(count[Material::kBuilding], 70);
  EXPECT_GT(count[Material::kCar], 150);
  EXPECT_GT(count[Material::kTrunk], 20);
  EXPECT_GT(count[Material::kFoliage], count[Material::kTrunk]);  // canopies plus hedges and bushes
  EXPECT_GT(count[Material::kPole], 150);
  EXPECT_GT(count[Material::kPavement], 800);
  EXPECT_GT(count[Material::kWall], 80);
  EXPECT_GT(count[Material::kSign], 10);
  // Heights from small houses to towers, within 4-30 m (bays and annexes a little lower).
  EXPECT_LT(lowest, 7.0f);
  EXPECT_GT(highest, 18.0f);
  EXPECT_LE(highest, 30.0f);
  // A vertical ray down at every 10th path point sees the road: nothing stands, hangs or parks on it.
  std::vector<std::uint32_t> visit(a.size(), 0);
  std::uint32_t ray = 0;
  for (std::size_t k = 0; k < path.size(); k += 10) {
    Hit hit;
    ASSERT_TRUE(
        a.cast(Eigen::Vector3f(path[k].x, path[k].y, 40.0f), Eigen::Vector3f(0, 0, -1), 100, 0.0, ++ray, &visit, &hit));
    EXPECT_EQ(hit.material, Material::kGround) << "path point " << k;
  }
}

TEST(WorldGeneration, SomeCarsLeaveArriveOrMoveBetweenVisits) {
  const auto path = proceduralPath();
  WorldOptions options;
  options.duration = 1000.0;
  options.dynamic_car_fraction = 0.6;
  const World world = generateWorld(path, options);
  int always = 0, leaving = 0, arriving = 0, moved = 0;
  std::vector<const Primitive*> left, came;
  for (const auto& p : world.primitives()) {
    // Car bodies only (cabins sit on them, higher up).
    if (p.material != Material::kCar || p.z0 > world.groundZ(p.center.x(), p.center.y()) + 0.5) continue;
    const bool from = p.present_from > -1e299, to = p.present_to < 1e299;
    always += !from && !to;
    if (to) left.push_back(&p);
    if (from) came.push_back(&p);
    leaving += to;
    arriving += from;
    if (from || to) {
      EXPECT_GE(from ? p.present_from : p.present_to, 0.0);
      EXPECT_LE(from ? p.present_from : p.present_to, options.duration);
    }
  }
  // A car that moves leaves one spot when it appears in another a few metres along the kerb.
  for (const Primitive* a : left) {
    for (const Primitive* b : came) {
      if (a->present_to == b->present_from && (a->center - b->center).norm() < 6.5f) ++moved;
    }
  }
  EXPECT_GT(always, 0);
  const double dynamic = static_cast<double>(leaving + arriving - moved) / (always + leaving + arriving - moved);
  EXPECT_NEAR(dynamic, options.dynamic_car_fraction, 0.1);
  EXPECT_GT(leaving - moved, 10);
  EXPECT_GT(arriving - moved, 10);
  EXPECT_GT(moved, 10);

  // Without a duration every car stays.
  options.duration = 0.0;
  const World still = generateWorld(path, options);
  for (const auto& p : still.primitives()) {
    EXPECT_TRUE(p.present_from < -1e299 && p.present_to > 1e299);
  }
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
