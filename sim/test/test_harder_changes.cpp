// The harder changes between visits: leaf-off, building sites, moved street furniture, a different
// density on each pass; and thin branches as a beam sees them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "footprint.h"

#include "scan_context_sim/sensor.h"
#include "scan_context_sim/trajectory.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {
namespace {

using test::always;
using test::present;
using test::sameShape;

using test::distanceTo;

const std::vector<PathPoint>& drive() {
  static const std::vector<PathPoint> path = proceduralPath();
  return path;
}

/// The procedural drive at 10 m/s, its changes as `set` makes them.
template <typename Set>
WorldOptions changed(Set set) {
  WorldOptions options;
  const auto& path = drive();
  options.times.assign(path.size(), 0.0);
  for (std::size_t k = 1; k < path.size(); ++k) {
    options.times[k] = options.times[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y) / 10.0;
  }
  options.duration = options.times.back();
  set(&options);
  return options;
}

TEST(HarderChanges, EachLeavesTheWorldAndTheOtherChangesAsTheyWereAndRepeatsForASeed) {
  const WorldOptions plain = changed([](WorldOptions* o) { o->changed_world = 1.0; });
  const World base = generateWorld(drive(), plain);
  for (int kind = 0; kind < 3; ++kind) {
    const WorldOptions harder = changed([kind](WorldOptions* o) {
      o->changed_world = 1.0;
      (kind == 0 ? o->season : kind == 1 ? o->construction : o->furniture) = 1.0;
    });
    const World world = generateWorld(drive(), harder);
    ASSERT_GT(world.size(), base.size()) << kind;
    // Every solid of the changed world is still there, the same shape (only its times may differ).
    for (std::size_t i = 0; i < base.size(); ++i) ASSERT_TRUE(sameShape(base.primitives()[i], world.primitives()[i]));
    // The same seed gives the same world, solid for solid.
    const World again = generateWorld(drive(), harder);
    ASSERT_EQ(again.size(), world.size());
    for (std::size_t i = 0; i < world.size(); ++i) {
      ASSERT_TRUE(sameShape(world.primitives()[i], again.primitives()[i]));
      ASSERT_EQ(world.primitives()[i].present_from, again.primitives()[i].present_from);
      ASSERT_EQ(world.primitives()[i].present_to, again.primitives()[i].present_to);
    }
  }
}

/// Rays from 12 m away at a canopy's centre height, spread over its outline: how many come back from
/// the canopy (foliage or branches) at time t.
int canopyReturns(const World& world, const Primitive& canopy, double t) {
  std::vector<std::uint32_t> visit(world.size(), 0);
  std::uint32_t ray = 0;
  int hits = 0;
  const Eigen::Vector3f c = canopy.center;
  for (int a = 0; a < 8; ++a) {
    const float angle = static_cast<float>(a * M_PI / 4);
    const Eigen::Vector3f from = c + 12.0f * Eigen::Vector3f(std::cos(angle), std::sin(angle), 0.0f);
    for (int i = -4; i <= 4; ++i) {
      for (int j = -4; j <= 4; ++j) {
        const Eigen::Vector3f side(-std::sin(angle), std::cos(angle), 0.0f);
        const Eigen::Vector3f target = c + side * (0.2f * i * canopy.half.x()) + Eigen::Vector3f::UnitZ() * (0.2f * j * canopy.half.z());
        Hit hit;
        if (!world.cast(from, (target - from).normalized(), 30.0f, t, ++ray, &visit, &hit)) continue;
        const Eigen::Vector3f at = from + hit.range * (target - from).normalized();
        const bool in_crown = ((at - c).cwiseQuotient(canopy.half * 1.05f)).norm() <= 1.0f;
        hits += in_crown && (hit.material == Material::kFoliage || hit.material == Material::kBranch);
      }
    }
  }
  return hits;
}

TEST(HarderChanges, LeafOffCrownsReturnFarFewerRaysAndConifersKeepTheirNeedles) {
  const World summer = generateWorld(drive(), changed([](WorldOptions*) {}));
  const World winter = generateWorld(drive(), changed([](WorldOptions* o) { o->season = 1.0; }));
  const double end = changed([](WorldOptions*) {}).duration;
  int canopies = 0, bare = 0, evergreen = 0, summer_hits = 0, winter_hits = 0, limbs = 0;
  for (std::size_t i = 0; i < summer.size(); ++i) {
    const Primitive& canopy = summer.primitives()[i];
    if (canopy.kind != Primitive::Kind::kEllipsoid || canopy.free_path < 0.7f) continue;
    ++canopies;
    const bool leaf_off = !always(winter.primitives()[i]);
    bare += leaf_off;
    // Conifers (tall and narrow) keep theirs.
    evergreen += !leaf_off;
    if (!leaf_off || canopies > 400) continue;
    summer_hits += canopyReturns(summer, canopy, end + 1.0);
    winter_hits += canopyReturns(winter, canopy, end + 1.0);
  }
  for (const auto& p : winter.primitives()) {
    if (p.material != Material::kBranch || p.kind != Primitive::Kind::kCylinder) continue;
    ++limbs;
    EXPECT_LE(p.half.x(), 0.09f);
    EXPECT_GT(p.present_from, -1e299);  // from the tree's own time on
  }
  std::printf("canopies %d, leaf-off %d, returns from them at the end: %d with leaves, %d bare\n", canopies, bare,
              summer_hits, winter_hits);
  ASSERT_GT(canopies, 50);
  EXPECT_GT(bare, canopies * 3 / 4);  // all but the conifers (about 12 %)
  EXPECT_GT(evergreen, 0);
  EXPECT_GT(limbs, 3 * bare);
  EXPECT_LT(winter_hits, summer_hits / 2);
  EXPECT_GT(winter_hits, summer_hits / 20);  // the twigs and limbs still return some
}

TEST(HarderChanges, ThinBranchesFadeWithRangeAsTheirShareOfTheBeamShrinks) {
  // One 4 cm branch or pole, 30 m tall, seen from 6 m and from 75 m by an HDL-64E with fine columns.
  SensorModel sensor;
  ASSERT_TRUE(sensorPreset("hdl64", &sensor));
  sensor.columns = 20000;
  sensor.dropout = 0.0f;
  const auto returns = [&](Material material, double distance) {
    Primitive p;
    p.kind = Primitive::Kind::kCylinder;
    p.material = material;
    p.center = Eigen::Vector3f(static_cast<float>(distance), 0.0f, 0.0f);
    p.half = Eigen::Vector3f::Constant(0.02f);
    p.z0 = -5.0f;
    p.z1 = 30.0f;
    const World world({p}, Eigen::Vector3d(0.0, 0.0, -10.0));
    int n = 0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (const auto& q : scan(world, sensor, pose, 0.0, 3)) {
      n += std::fabs(q.x - distance) < 1.0 && std::fabs(q.y) < 1.0 && q.z > -9.0f;  // not the ground
    }
    return n;
  };
  const int pole_near = returns(Material::kPole, 6.0), branch_near = returns(Material::kBranch, 6.0);
  const int pole_far = returns(Material::kPole, 75.0), branch_far = returns(Material::kBranch, 75.0);
  std::printf("returns of a 4 cm pole / branch: at 6 m %d / %d, at 75 m %d / %d\n", pole_near, branch_near, pole_far,
              branch_far);
  ASSERT_GT(pole_near, 50);
  ASSERT_GT(pole_far, 10);
  // Near, the beam's footprint (1.2 cm) is narrower than the branch: it returns like the pole.
  EXPECT_GT(branch_near, pole_near * 9 / 10);
  // At 75 m the footprint is 15 cm, the branch covers a quarter of it: a dim return, mostly lost.
  EXPECT_LT(branch_far, pole_far / 2);
}

TEST(HarderChanges, BuildingSitesStandClearOfTheRoadFromTheirTimeOn) {
  const WorldOptions options = changed([](WorldOptions* o) { o->construction = 1.0; });
  const World world = generateWorld(drive(), options);
  int containers = 0, stacked = 0, panels = 0;
  std::set<double> sites;
  double nearest = 1e9;
  for (const auto& p : world.primitives()) {
    const bool container = p.material == Material::kContainer;
    const bool panel = p.material == Material::kWall && p.free_path > 0.07f && p.free_path < 0.09f &&
                       std::fabs(p.z1 - p.z0 - 2.0f) < 1e-3f && p.present_from > -1e299;
    if (!container && !panel) continue;
    containers += container, panels += panel;
    stacked += container && p.z0 > world.groundZ(p.center.x(), p.center.y()) + 2.0;
    EXPECT_GE(p.present_from, 0.0);
    EXPECT_LE(p.present_from, options.duration);
    EXPECT_GT(p.present_to, 1e299);  // they stay
    sites.insert(p.present_from);
    for (std::size_t k = 0; k < drive().size(); k += 4) {
      nearest = std::min(nearest, distanceTo(p, Eigen::Vector2d(drive()[k].x, drive()[k].y)));
    }
  }
  std::printf("%zu sites: %d containers (%d stacked on others), %d fence panels; nearest to the path %.2f m\n",
              sites.size(), containers, stacked, panels, nearest);
  EXPECT_GE(sites.size(), 10u);  // about one per 100 m of the 2.1 km drive, where there is room
  EXPECT_GT(containers, 2);
  EXPECT_GT(stacked, 0);
  EXPECT_GT(panels, 20);
  EXPECT_GT(nearest, 3.0);  // in the parking lane at the nearest (its kerb 6 m from the path)
}

TEST(HarderChanges, StreetFurnitureMovesAlongThePavementOrGoes) {
  const World before = generateWorld(drive(), changed([](WorldOptions*) {}));
  const World after = generateWorld(drive(), changed([](WorldOptions* o) { o->furniture = 1.0; }));
  // Benches, bins, cabinets: small boxes on the pavement.
  int pieces = 0, timed = 0, moved = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const Primitive& a = before.primitives()[i];
    const bool small = a.kind == Primitive::Kind::kBox && a.material == Material::kWall && a.half.x() <= 0.95f &&
                       a.half.y() <= 0.35f && a.z1 - a.z0 < 1.6f && a.free_path == 0.0f;
    if (!small || !always(a)) continue;
    ++pieces;
    const Primitive& b = after.primitives()[i];
    if (always(b)) continue;
    ++timed;
    for (std::size_t j = before.size(); j < after.size(); ++j) {
      const Primitive& c = after.primitives()[j];
      if (c.present_from != b.present_to || c.half != b.half || c.z1 - c.z0 != b.z1 - b.z0) continue;
      const double shift = (c.center - b.center).head<2>().norm();
      if (shift < 1.9 || shift > 12.5) continue;
      ++moved;
      break;
    }
  }
  std::printf("%d pieces of furniture: %d changed, %d of them moved\n", pieces, timed, moved);
  ASSERT_GT(pieces, 30);
  EXPECT_GT(timed, pieces * 9 / 10);  // strength 1: every piece moves or goes
  EXPECT_GT(moved, timed / 4);
  EXPECT_LT(moved, timed * 3 / 4);  // a third goes, and some find no room
}

TEST(HarderChanges, EachPassHasItsOwnDensityOfParkedCarsAndTraffic) {
  const auto make = [](double strength) {
    return changed([strength](WorldOptions* o) {
      o->pass_traffic = strength;
      o->pass_seconds = 50.0;
    });
  };
  const WorldOptions options = make(1.0);
  const World still = generateWorld(drive(), make(0.0)), world = generateWorld(drive(), options);
  // Parked cars present in each pass (a pass every 50 s of the 210 s drive), by where they stand.
  std::vector<double> middles;
  for (double t = 25.0; t < options.duration; t += 50.0) middles.push_back(t);
  std::vector<std::set<std::pair<float, float>>> parked(middles.size());
  std::vector<int> passing(middles.size(), 0);
  for (const auto& p : world.primitives()) {
    if (p.material != Material::kCar) continue;
    for (std::size_t m = 0; m < middles.size(); ++m) {
      const double from = m * 50.0, to = from + 50.0;
      if (p.present_to - p.present_from <= 0.5 + 1e-9) {
        passing[m] += p.present_from >= from && p.present_from < to;
      } else if (present(p, middles[m]) && p.z0 < world.groundZ(p.center.x(), p.center.y()) + 0.5) {
        parked[m].insert({p.center.x(), p.center.y()});
      }
    }
  }
  int built = 0;
  for (const auto& p : still.primitives()) built += p.material == Material::kCar && always(p) && p.z0 < still.groundZ(p.center.x(), p.center.y()) + 0.5;
  std::size_t fewest = parked[0].size(), most = parked[0].size();
  int least = passing[0], busiest = passing[0];
  for (std::size_t m = 0; m < middles.size(); ++m) {
    std::printf("pass %zu: %zu parked cars (of %d built), %d traffic steps\n", m, parked[m].size(), built, passing[m]);
    fewest = std::min(fewest, parked[m].size()), most = std::max(most, parked[m].size());
    least = std::min(least, passing[m]), busiest = std::max(busiest, passing[m]);
  }
  ASSERT_GE(middles.size(), 4u);
  EXPECT_GT(most, fewest + fewest / 10);  // the passes differ
  EXPECT_GT(busiest, 3 * least / 2);
  // The cars that stay when few are parked stay when more are: the emptier pass's cars are (nearly all)
  // among the fuller one's (the new ones in empty spaces aside).
  for (std::size_t m = 1; m < middles.size(); ++m) {
    const auto& fuller = parked[m].size() > parked[0].size() ? parked[m] : parked[0];
    const auto& emptier = parked[m].size() > parked[0].size() ? parked[0] : parked[m];
    int missing = 0;
    for (const auto& c : emptier) missing += !fuller.count(c);
    EXPECT_LT(missing, static_cast<int>(emptier.size()) / 3) << m;
  }
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
