// The suburb (WorldOptions::Style::kSuburb), built independently of the city's districts: plots of
// detached houses along both sides of every street, each with its front boundary, driveway, garage,
// side fence, garden and bins, trees on the grass verge, low lamp posts and few cars at the kerb.
#include <algorithm>
#include <cmath>
#include <utility>

#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

namespace {

class SuburbBuilder {
 public:
  explicit SuburbBuilder(StreetKit& kit) : kit_(kit), line_(kit.propertyLine(styleOf(District::kHouses))) {}

  StreetRecord build() {
    enum { kVerge, kPlot, kTree, kLamp, kKerbCar, kKinds };
    double next[kKinds][2] = {};
    double s = 0.0;
    const auto& dense = kit_.dense;
    for (std::size_t k = 0; k < dense.size(); ++k) {
      if (k > 0) s += std::hypot(dense[k].x - dense[k - 1].x, dense[k].y - dense[k - 1].y);
      const PathPoint& p = dense[k];
      for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0;
        if (s >= next[kVerge][side]) next[kVerge][side] = s + verge(p, sign);
        if (s >= next[kPlot][side]) next[kPlot][side] = s + plot(p, sign);
        if (s >= next[kTree][side]) next[kTree][side] = s + vergeTree(p, sign);
        if (s >= next[kLamp][side]) next[kLamp][side] = s + lamp(p, sign);
        if (s >= next[kKerbCar][side]) next[kKerbCar][side] = s + kerbCar(p, sign);
      }
    }
    return std::move(record_);
  }

 private:
  Eigen::Vector2d at(const PathPoint& p, double along, double lateral) const { return StreetKit::at(p, along, lateral); }
  double uniform(double a, double b) { return kit_.uniform(a, b); }
  bool chance(double p) { return kit_.chance(p); }

  /// A 2 m strip of grass verge and footpath, kerb to property line (raised like the city's pavement).
  double verge(const PathPoint& p, double sign) {
    const double width = line_ - kit_.kerb();
    const Eigen::Vector2d c = at(p, 1.0, sign * (kit_.kerb() + width / 2));
    const Primitive strip = kit_.box(c, p.heading, 1.05, width / 2, -0.3, 0.12, Material::kPavement);
    if (kit_.roads.clear(StreetKit::footprintOf(strip), kit_.kerb() - 0.15)) kit_.out.push_back(strip);
    return 2.0;
  }

  /// One plot, 15-24 m along the street: returns its frontage.
  double plot(const PathPoint& p, double sign) {
    const double width = uniform(15.0, 24.0);
    if (chance(0.08)) return width;  // a green or a gap between plots
    const bool drive_first = chance(0.5);  // the driveway at the plot's start or its end
    const double drive0 = drive_first ? 0.4 : width - 3.6;
    frontBoundary(p, sign, width, drive_first);
    const double setback = uniform(5.0, 9.0), front = line_ + setback;
    const double house_len = uniform(9.0, std::min(14.0, width - 5.5)), depth = uniform(8.0, 12.0);
    const double free_start = drive_first ? 4.3 : 1.0;
    const double h0 = free_start + uniform(0.0, std::max(0.0, width - 4.6 - house_len - 0.7));
    const double yaw = p.heading + uniform(-0.03, 0.03);
    const bool bungalow = chance(0.2);
    const double wall = bungalow ? uniform(2.8, 3.4) : uniform(5.2, 6.5);
    if (house(at(p, h0 + house_len / 2, sign * (front + depth / 2)), yaw, house_len, depth, wall)) {
      if (chance(0.6)) {  // a garage beside the house, at the driveway, set further back
        const Eigen::Vector2d g = at(p, drive0 + 1.6, sign * (front + uniform(1.0, 4.0) + 3.0));
        kit_.placeBox(kit_.box(g, yaw, 1.6, 3.0, 0.0, uniform(2.4, 2.8), Material::kBuilding), line_, 0.0);
      }
    }
    if (chance(0.55)) driveCar(p, sign, drive0 + 1.6);
    sideFence(p, sign, setback);
    garden(p, sign, h0, house_len, setback, front + depth);
    bins(p, sign, drive0);
    return width;
  }

  /// Hedge, picket fence or low wall along the property line with the driveway left open; or none.
  void frontBoundary(const PathPoint& p, double sign, double width, bool drive_first) {
    if (chance(0.25)) return;  // an open lawn
    const double kind = uniform(0.0, 1.0);
    double thickness = 0.04, height = uniform(0.9, 1.2), free_path = 0.15;
    Material material = Material::kWall;
    if (kind < 0.4) {
      material = Material::kFoliage, thickness = uniform(0.6, 1.0), height = uniform(0.9, 1.8), free_path = 0.3;
    } else if (kind > 0.75) {
      thickness = 0.25, height = uniform(0.5, 0.9), free_path = 0.0;
    }
    const double from = drive_first ? 4.0 : 0.2, length = width - 4.2;
    const PathPoint start{at(p, from, 0.0).x(), at(p, from, 0.0).y(), p.heading};
    Primitive b = kit_.box(at(start, length / 2, sign * (line_ + 0.1 + thickness / 2)), p.heading, length / 2,
                           thickness / 2, 0.0, height, material);
    b.free_path = static_cast<float>(free_path);
    if (kit_.placeBox(b, line_ - 0.3, 0.05) && material == Material::kFoliage) {
      record_.hedges.push_back(kit_.out.size() - 1);
    }
  }

  /// A detached house: walls and a hipped roof as two shrinking tiers.
  bool house(const Eigen::Vector2d& c, double yaw, double length, double depth, double wall) {
    if (!kit_.placeBox(kit_.box(c, yaw, length / 2, depth / 2, 0.0, wall, Material::kBuilding), line_, 0.3)) {
      return false;
    }
    const double rise = uniform(1.0, 1.5);
    for (int tier = 1; tier <= 2; ++tier) {
      const double inset = 0.9 * tier;
      kit_.out.push_back(kit_.box(c, yaw, length / 2 - inset, std::max(0.5, depth / 2 - inset),
                                  wall + (tier - 1) * rise, wall + tier * rise, Material::kBuilding));
    }
    return true;
  }

  /// A car on the driveway, nose to the house.
  void driveCar(const PathPoint& p, double sign, double along) {
    const VehicleShape shape = kit_.vehicleShape(false);
    const Eigen::Vector2d c = at(p, along, sign * (line_ + 1.0 + shape.length / 2));
    const double yaw = p.heading + sign * M_PI / 2;
    const Vehicle v = kit_.vehicleAt(shape, {c.x(), c.y(), yaw}, -shape.length / 2, 0.0, yaw);
    const Footprint f = StreetKit::footprintOf(v.body);
    if (!kit_.roads.clear(f, line_ - 0.3) || !kit_.occupied.free(f, 0.2)) return;
    kit_.occupied.mark(f);
    record_.parked.push_back(kit_.add(v));
  }

  /// A close-boarded fence (1.6-1.9 m, opaque) down the side of the plot, from beside the house front
  /// to the back garden.
  void sideFence(const PathPoint& p, double sign, double setback) {
    if (!chance(0.7)) return;
    const double near = line_ + uniform(0.5, setback), far = line_ + uniform(24.0, 32.0);
    const Eigen::Vector2d c = at(p, 0.0, sign * (near + far) / 2);
    kit_.placeBox(kit_.box(c, p.heading, 0.03, (far - near) / 2, 0.0, uniform(1.6, 1.9), Material::kWall), line_ - 0.3,
                  0.0);
  }

  /// A front-garden tree and bushes, and now and then a tree in the back garden seen over the fences.
  void garden(const PathPoint& p, double sign, double h0, double length, double setback, double back) {
    if (chance(0.45)) kit_.tree(at(p, h0 + uniform(1.0, length - 1.0), sign * (line_ + setback / 2)), line_, 0.8, &record_);
    const int bushes = static_cast<int>(uniform(0.0, 4.0));
    for (int b = 0; b < bushes; ++b) {
      const double r = uniform(0.5, 1.2);
      const Eigen::Vector2d c = at(p, h0 + uniform(0.0, length), sign * (line_ + uniform(0.8, setback - 0.5)));
      if (kit_.place(kit_.ellipsoid(c, 0.5 * r, Eigen::Vector3d(r, r, 0.8 * r), Material::kFoliage, 0.35),
                     StreetKit::footprintOf(c, 0.0, r, r), line_ - 0.3, 0.0)) {
        record_.bushes.push_back(kit_.out.size() - 1);
      }
    }
    if (chance(0.4)) kit_.tree(at(p, h0 + uniform(0.0, length), sign * (back + uniform(3.0, 8.0))), line_, 1.0, &record_);
  }

  /// Wheelie bins at the kerb by the driveway, and sometimes a letterbox on a post.
  void bins(const PathPoint& p, double sign, double drive0) {
    if (chance(0.35)) {
      const std::size_t first = kit_.out.size();
      const int count = 1 + static_cast<int>(uniform(0.0, 2.0));
      for (int i = 0; i < count; ++i) {
        kit_.placeBox(kit_.box(at(p, drive0 + 3.8 + 0.75 * i, sign * (kit_.kerb() + 0.5)), p.heading, 0.3, 0.36, 0.0,
                               1.05, Material::kWall),
                      kit_.kerb() + 0.1, 0.05);
      }
      furniture(first, p.heading);
    }
    if (chance(0.2)) {
      const std::size_t first = kit_.out.size();
      const Eigen::Vector2d post = at(p, drive0 - 0.3, sign * (line_ - 0.3));
      if (kit_.place(kit_.cylinder(post, 0.05, 0.0, 1.1, Material::kPole), StreetKit::footprintOf(post, 0.0, 0.1, 0.1),
                     kit_.kerb() + 0.1, 0.1)) {
        kit_.out.push_back(kit_.box(post, p.heading, 0.2, 0.15, 1.1, 1.4, Material::kWall));
      }
      furniture(first, p.heading);
    }
  }

  void furniture(std::size_t first, double heading) {
    if (kit_.out.size() == first) return;
    record_.furniture.push_back({{}, heading});
    for (std::size_t i = first; i < kit_.out.size(); ++i) record_.furniture.back().solids.push_back(i);
  }

  double vergeTree(const PathPoint& p, double sign) {
    if (chance(0.6)) kit_.tree(at(p, 0.0, sign * (kit_.kerb() + 1.2)), kit_.kerb() + 0.5, 0.9, &record_);
    return uniform(10.0, 18.0);
  }

  /// A low lamp post (4.5-6 m, a lantern on top) at the verge.
  double lamp(const PathPoint& p, double sign) {
    const Eigen::Vector2d c = at(p, 0.0, sign * (kit_.kerb() + 0.4));
    const double height = uniform(4.5, 6.0);
    if (kit_.place(kit_.cylinder(c, 0.07, 0.0, height, Material::kPole), StreetKit::footprintOf(c, 0.0, 0.15, 0.15),
                   kit_.kerb() + 0.1, 0.3)) {
      kit_.out.push_back(kit_.box(c, p.heading, 0.25, 0.25, height, height + 0.5, Material::kPole));
    }
    return uniform(30.0, 45.0);
  }

  /// Now and then a car at the kerb; the other spaces are where the changes park new ones.
  double kerbCar(const PathPoint& p, double sign) {
    if (!chance(0.12)) {
      record_.empty_spaces.push_back({p, sign, false});
      return uniform(6.0, 12.0);
    }
    const Vehicle v = kit_.parkedVehicle(p, sign, 0.0, false);
    const Footprint f = StreetKit::footprintOf(v.body);
    if (kit_.roads.clear(f, kit_.parkingClearance()) && kit_.occupied.free(f, 0.3)) {
      kit_.occupied.mark(f);
      record_.parked.push_back(kit_.add(v));
    }
    return v.length + uniform(3.0, 10.0);
  }

  StreetKit& kit_;
  const double line_;  ///< kerb to property line: grass verge and footpath
  StreetRecord record_;
};

}  // namespace

StreetRecord buildSuburb(StreetKit* kit) { return SuburbBuilder(*kit).build(); }

}  // namespace sim
}  // namespace scan_context_loop
