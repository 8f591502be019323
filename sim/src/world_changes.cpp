// Parked cars, vegetation and construction sites that change during the drive (the changed world).
#include "world_changes.h"

#include <algorithm>
#include <cmath>

namespace scan_context_loop {
namespace sim {

namespace {

/// How close to a road centre a grown canopy may reach [m] (street trees reach about 3.4 m).
constexpr double kKeepOffRoads = 3.0;

/// Solid `index` has stood unchanged all along so far (nothing made it come, go or change yet).
bool unchanged(const StreetKit& kit, std::size_t index) {
  return kit.out[index].present_from <= -1e300 && kit.out[index].present_to >= 1e300;
}

/// Whether a recorded thing may change now: with the chance, and, when the street was seen before, only
/// when it has not changed yet.
bool changes(StreetKit& kit, std::size_t index, const Changes& c) {
  if (c.seen_before && !unchanged(kit, index)) return false;
  return kit.chance(c.strength);
}

/// Grown or cut by 20-50 %.
double growthFactor(StreetKit& kit) {
  return kit.chance(0.5) ? 1.0 + kit.uniform(0.2, 0.5) : 1.0 - kit.uniform(0.2, 0.5);
}

/// An ellipsoid grown or shrunk by `factor`, standing on the same base height.
Primitive scaledEllipsoid(const Primitive& e, double factor, double base) {
  Primitive scaled = e;
  scaled.half *= static_cast<float>(factor);
  scaled.center.z() = static_cast<float>(base + (e.center.z() - base) * factor);
  return scaled;
}

/// The car leaves at `when`.
void carLeaves(StreetKit& kit, const StreetRecord::Car& car, double when) {
  removeAt(kit, car.body, when);
  if (car.cabin != car.body) removeAt(kit, car.cabin, when);
}

/// Another vehicle, no longer than the car, takes its space at `when`; otherwise the car just leaves.
void carReplaced(StreetKit& kit, const StreetRecord::Car& car, double when) {
  const Primitive& body = kit.out[car.body];
  const Eigen::Vector2d c(body.center.x(), body.center.y());
  const VehicleShape shape = kit.vehicleShape(styleOf(kit.districtAt(c)).industrial);
  carLeaves(kit, car, when);
  if (shape.length > 2.0 * body.half.x()) return;
  Vehicle v = kit.vehicleAt(shape, {c.x(), c.y(), static_cast<double>(body.yaw)}, -shape.length / 2, 0.0, body.yaw);
  v.body.present_from = v.cabin.present_from = when;
  kit.add(v);
}

/// About `strength` of the cars that stayed for the whole drive leave, arrive (seen before: are
/// replaced by another vehicle) or move to another space a car length or more along the kerb where there
/// is room; new cars take about 0.6 `strength` of the empty spaces.
void changeParkedCars(StreetKit& kit, const StreetRecord& record, const Changes& c) {
  const double strength = c.strength;
  for (const StreetRecord::Car& car : record.parked) {
    if (!changes(kit, car.body, c)) continue;
    const double when = changeTime(kit, c);
    const double kind = kit.uniform(0.0, 1.0);
    if (kind < 1.0 / 3.0) {
      carLeaves(kit, car, when);
    } else if (kind < 2.0 / 3.0) {
      if (c.seen_before)
        carReplaced(kit, car, when);
      else
        kit.out[car.body].present_from = kit.out[car.cabin].present_from = when;
    } else {
      const Primitive& body = kit.out[car.body];
      const double car_length = 2.0 * body.half.x();
      const double shift = kit.eitherWay(car_length + 1.0, car_length + 6.0);
      const Eigen::Vector3f offset(static_cast<float>(shift * std::cos(body.yaw)),
                                   static_cast<float>(shift * std::sin(body.yaw)), 0.0f);
      Primitive moved_body = body, moved_cabin = kit.out[car.cabin];
      moved_body.center += offset;
      moved_cabin.center += offset;
      const Footprint f = StreetKit::footprintOf(moved_body);
      if (kit.roads.clear(f, kit.parkingClearance()) && kit.occupied.free(f, 0.3)) {
        kit.occupied.mark(f);
        replaceAt(kit, car.body, moved_body, when);
        if (car.cabin != car.body) replaceAt(kit, car.cabin, moved_cabin, when);
      } else {  // no room there: it just leaves
        carLeaves(kit, car, when);
      }
    }
  }
  for (const StreetRecord::Space& space : record.empty_spaces) {
    if (!kit.chance(0.6 * strength)) continue;
    Vehicle v = kit.parkedVehicle(space.p, space.sign, 0.0, space.industrial);
    const Footprint f = StreetKit::footprintOf(v.body);
    const double when = changeTime(kit, c);
    if (!kit.roads.clear(f, kit.parkingClearance()) || !kit.occupied.free(f, 0.3)) continue;
    v.body.present_from = v.cabin.present_from = when;
    kit.occupied.mark(f);
    kit.add(v);
  }
}

/// About `strength` of the solids `items` change, each at its own time: a third are removed, the others
/// become resized(solid, factor) with a factor from growthFactor().
template <typename Resize>
void regrowOrRemove(StreetKit& kit, const std::vector<std::size_t>& items, const Changes& c, Resize resized) {
  for (const std::size_t item : items) {
    if (!changes(kit, item, c)) continue;
    const double when = changeTime(kit, c);
    if (kit.chance(1.0 / 3.0)) {
      removeAt(kit, item, when);
      continue;
    }
    const double factor = growthFactor(kit);
    replaceAt(kit, item, resized(kit.out[item], factor), when);
  }
}

/// About `strength` of the trees, bushes and hedges grow or are cut back by 20-50 %; a third of the
/// bushes and hedges that change are removed; new hedges appear along property lines.
void changeVegetation(StreetKit& kit, const StreetRecord& record, const Changes& c) {
  for (const StreetRecord::Tree& tree : record.trees) {
    if (!changes(kit, tree.canopy, c)) continue;
    const Primitive& canopy = kit.out[tree.canopy];
    double factor = growthFactor(kit);
    // Trees that would grow to reach over the road are cut back instead, as councils do.
    const Eigen::Vector2d centre(canopy.center.x(), canopy.center.y());
    const double radius = canopy.half.x() * factor;
    if (factor > 1.0 && !kit.roads.clear(StreetKit::footprintOf(centre, 0.0, radius, radius), kKeepOffRoads)) {
      factor = 2.0 - factor;
    }
    // The canopy keeps its bottom where the trunk holds it.
    const Primitive grown = scaledEllipsoid(canopy, factor, canopy.center.z() - canopy.half.z());
    replaceAt(kit, tree.canopy, grown, changeTime(kit, c));
  }
  regrowOrRemove(kit, record.bushes, c, [&](const Primitive& bush, double factor) {
    return scaledEllipsoid(bush, factor, kit.groundAt(Eigen::Vector2d(bush.center.x(), bush.center.y())));
  });
  regrowOrRemove(kit, record.hedges, c, [](Primitive hedge, double factor) {
    hedge.z1 = static_cast<float>(hedge.z0 + (hedge.z1 - hedge.z0) * factor);
    hedge.half.y() *= static_cast<float>(factor);
    return hedge;
  });
  // New hedges: about one per 100 m of drive at full strength, where the property line is free.
  placeSeveral(c.strength * static_cast<double>(kit.dense.size()) / 100.0, [&] {
    const PathPoint& p = randomPlace(kit);
    const double sign = kit.chance(0.5) ? 1.0 : -1.0;
    const Style& style = styleOf(kit.districtAt(StreetKit::at(p, 0.0, sign * 15.0)));
    const double length = kit.uniform(4.0, 12.0), thickness = kit.uniform(0.6, 1.0), height = kit.uniform(0.8, 1.6);
    Primitive hedge = kit.alongPropertyLine(p, sign, style, length, thickness, height, Material::kFoliage);
    hedge.free_path = 0.3f;
    hedge.present_from = changeTime(kit, c);
    return kit.placeBox(hedge, kit.propertyLine(style) - 0.3, 0.05);
  });
}

/// Construction sites, about one per 150 m of drive at full strength, from their time on: a site
/// hoarding or fence on the pavement, a skip in the parking lane, or a barrier fencing off the parking
/// lane.
void addConstruction(StreetKit& kit, const Changes& c) {
  placeSeveral(c.strength * static_cast<double>(kit.dense.size()) / 150.0, [&] {
    const PathPoint& p = randomPlace(kit);
    const double sign = kit.chance(0.5) ? 1.0 : -1.0;
    const Style& style = styleOf(kit.districtAt(StreetKit::at(p, 0.0, sign * 15.0)));
    const double kind = kit.uniform(0.0, 1.0);
    Primitive site;
    double clearance = kit.parkingClearance(), margin = 0.3;
    if (kind < 0.45) {  // hoarding or mesh fence along the pavement
      const double length = kit.uniform(4.0, 12.0);
      const double lateral = kit.kerb() + 0.3 + kit.uniform(0.0, std::max(0.0, style.pavement - 0.8));
      site = kit.box(StreetKit::at(p, length / 2, sign * lateral), p.heading, length / 2, 0.05, 0.0,
                     kit.uniform(1.0, 2.0), Material::kWall);
      site.free_path = kit.chance(0.5) ? 0.1f : 0.0f;
      clearance = kit.kerb() + 0.1;
      margin = 0.1;
    } else if (kind < 0.75) {  // a skip
      const double length = kit.uniform(3.5, 4.5), width = kit.uniform(1.7, 2.0);
      site = kit.box(StreetKit::at(p, length / 2, sign * (kit.kerb() - 0.3 - width / 2)), p.heading, length / 2,
                     width / 2, 0.0, kit.uniform(1.2, 1.7), Material::kWall);
    } else {  // barrier along the parking lane
      const double length = kit.uniform(6.0, 15.0);
      site = kit.box(StreetKit::at(p, length / 2, sign * (kit.kerb() - 1.0)), p.heading, length / 2, 0.05, 0.0,
                     kit.uniform(1.0, 2.0), Material::kWall);
    }
    site.present_from = changeTime(kit, c);
    return kit.placeBox(site, clearance, margin);
  });
}

}  // namespace

double changeTime(StreetKit& kit, const Changes& c) { return c.from + (c.to - c.from) * kit.uniform(0.0, 1.0); }

void removeAt(StreetKit& kit, std::size_t index, double when) {
  kit.out[index].present_to = std::min(kit.out[index].present_to, when);
}

void replaceAt(StreetKit& kit, std::size_t index, Primitive after, double when) {
  after.present_from = when;
  after.present_to = kit.out[index].present_to;
  removeAt(kit, index, when);
  kit.out.push_back(after);
}

const PathPoint& randomPlace(StreetKit& kit) {
  return kit.dense[static_cast<std::size_t>(kit.uniform(0.0, 1.0) * static_cast<double>(kit.dense.size() - 1))];
}

Changes duringDrive(const WorldOptions& options) {
  Changes c;
  c.strength = options.changed_world;
  c.to = options.duration;
  c.salt = 0xC4A1B3D5E7F90ull;
  c.traffic = !(options.pass_traffic > 0.0);
  return c;
}

void changeWorld(const std::vector<PathPoint>& path, const std::vector<double>& times, const StreetRecord& record,
                 const Changes& changes, StreetKit* kit) {
  std::mt19937 draws(static_cast<std::uint32_t>(mix(kit->options.seed ^ changes.salt)));
  const DrawFrom scoped(*kit, &draws);
  changeParkedCars(*kit, record, changes);
  changeVegetation(*kit, record, changes);
  addConstruction(*kit, changes);
  if (changes.traffic) addTraffic(path, times, changes.strength * kit->options.traffic, kit);
}

}  // namespace sim
}  // namespace scan_context_loop
