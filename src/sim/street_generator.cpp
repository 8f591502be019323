// Builds the street world along a driven path: every side of every street is furnished as the path is
// walked, in the character of the district it runs through.
#include <algorithm>
#include <cmath>
#include <random>

#include "placement.h"
#include "scan_context_loop/sim/world.h"

namespace scan_context_loop {
namespace sim {

namespace {

enum class District : std::uint8_t { kTerrace, kHouses, kAvenue, kIndustrial };

/// What a street looks like in one kind of district. Lengths in metres, chances in [0, 1].
struct Style {
  double pavement;                  ///< kerb to property line
  double frontage;                  ///< chance a stretch of property line has a hedge, wall or fence
  double setback_min, setback_max;  ///< property line to facade
  double length_min, length_max;    ///< facade length
  double depth_min, depth_max;
  double height_min, height_max;
  double tower;                     ///< chance of a building 20-30 m tall
  double adjoining;                 ///< chance the next building shares a wall with this one
  double gap_min, gap_max;          ///< otherwise the gap between buildings
  double open_lot;                  ///< chance of a longer opening: a yard, car park or side lane
  double back_row;                  ///< chance of a second building behind the first
  double street_tree;               ///< chance each tree pit holds a tree
  double tree_min, tree_max;        ///< tree pit spacing
  double parking;                   ///< chance a parking space holds a car
  double garden;                    ///< chance of trees and bushes in a front garden
  bool industrial;                  ///< wire-mesh fences, lorries among the parked vehicles
};

const Style& styleOf(District d) {
  // clang-format off
  //                                pave  front setback     length      depth       height      tower adjoin gap        open  back  tree  pits        park  garden industrial
  static const Style kTerrace    = {4.0, 0.1,  0.5, 1.5,  10.0, 24.0, 10.0, 16.0,  9.0, 20.0, 0.12, 0.75, 1.0,  4.0, 0.05, 0.5,  0.45, 8.0, 14.0, 0.8,  0.0, false};
  static const Style kHouses     = {2.5, 0.85, 2.5, 6.0,   8.0, 15.0,  8.0, 12.0,  5.0, 11.0, 0.0,  0.3,  2.0,  6.0, 0.05, 0.6,  0.6,  8.0, 14.0, 0.7,  0.7, false};
  static const Style kAvenue     = {4.5, 0.4,  2.0, 8.0,  14.0, 30.0, 10.0, 18.0,  8.0, 22.0, 0.2,  0.3,  3.0, 10.0, 0.06, 0.5,  0.95, 7.0, 10.0, 0.55, 0.5, false};
  static const Style kIndustrial = {2.0, 0.8,  3.0, 10.0, 20.0, 45.0, 12.0, 30.0,  6.0, 12.0, 0.05, 0.1,  4.0, 12.0, 0.1,  0.3,  0.25, 10.0, 20.0, 0.35, 0.0, true};
  // clang-format on
  switch (d) {
    case District::kTerrace: return kTerrace;
    case District::kHouses: return kHouses;
    case District::kAvenue: return kAvenue;
    case District::kIndustrial: return kIndustrial;
  }
  return kTerrace;
}

std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// The ground plane (slope_x, slope_y, offset): the configured slope, downhill in a direction drawn
/// from the seed.
Eigen::Vector3d groundPlane(const WorldOptions& options) {
  const double direction = 2.0 * M_PI * static_cast<double>(mix(options.seed) >> 11) / 9007199254740992.0;
  return {options.ground_slope * std::cos(direction), options.ground_slope * std::sin(direction), 0.0};
}

/// Places things along both sides of the path as it walks it.
class StreetBuilder {
 public:
  StreetBuilder(const std::vector<PathPoint>& dense, const WorldOptions& options)
      : dense_(dense), options_(options), ground_(groundPlane(options)), roads_(dense), rng_(options.seed) {}

  std::vector<Primitive> build() {
    // Each side of the road keeps, per kind of thing, the arc length up to which it is furnished.
    enum { kPavement, kFrontage, kBuilding, kTree, kLight, kFurniture, kCar, kKinds };
    double next[kKinds][2] = {};
    double s = 0.0;
    for (std::size_t k = 0; k < dense_.size(); ++k) {
      if (k > 0) s += std::hypot(dense_[k].x - dense_[k - 1].x, dense_[k].y - dense_[k - 1].y);
      const PathPoint& p = dense_[k];
      for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0;  // left, right of the direction of travel
        const Style& style = styleOf(districtAt(at(p, 0.0, sign * 15.0)));
        if (s >= next[kPavement][side]) next[kPavement][side] = s + pavement(p, sign, style);
        if (s >= next[kFrontage][side]) next[kFrontage][side] = s + frontage(p, sign, style);
        if (s >= next[kBuilding][side]) next[kBuilding][side] = s + building(p, sign, style);
        if (s >= next[kTree][side]) next[kTree][side] = s + streetTree(p, sign, style);
        if (s >= next[kLight][side]) next[kLight][side] = s + streetLight(p, sign);
        if (s >= next[kFurniture][side]) next[kFurniture][side] = s + streetFurniture(p, sign, style);
        if (s >= next[kCar][side]) next[kCar][side] = s + parkedCar(p, sign, style);
      }
    }
    return std::move(out_);
  }

 private:
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  double kerb() const { return options_.road_half_width; }

  /// The district a point lies in: a repeatable draw per district-sized square of the map.
  District districtAt(const Eigen::Vector2d& q) const {
    const auto i = static_cast<std::int64_t>(std::floor(q.x() / options_.district_size));
    const auto j = static_cast<std::int64_t>(std::floor(q.y() / options_.district_size));
    const double u = static_cast<double>(mix(mix(options_.seed ^ static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^
                                             static_cast<std::uint64_t>(j)) >> 11) / 9007199254740992.0;
    if (u < 0.3) return District::kTerrace;
    if (u < 0.65) return District::kHouses;
    if (u < 0.85) return District::kAvenue;
    return District::kIndustrial;
  }

  /// Point at along-track offset `along` and lateral offset `lateral` (positive = left) from p.
  Eigen::Vector2d at(const PathPoint& p, double along, double lateral) const {
    const double c = std::cos(p.heading), s = std::sin(p.heading);
    return {p.x + c * along - s * lateral, p.y + s * along + c * lateral};
  }

  double groundAt(const Eigen::Vector2d& c) const { return ground_.x() * c.x() + ground_.y() * c.y() + ground_.z(); }

  static Footprint footprintOf(const Eigen::Vector2d& c, double yaw, double hx, double hy) {
    Footprint f;
    f.center = c;
    f.yaw = yaw;
    f.half = Eigen::Vector2d(hx, hy);
    return f;
  }

  Primitive box(const Eigen::Vector2d& c, double yaw, double hx, double hy, double z0, double z1, Material m) const {
    Primitive b;
    b.kind = Primitive::Kind::kBox;
    b.material = m;
    b.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()), 0.0f);
    b.half = Eigen::Vector3f(static_cast<float>(hx), static_cast<float>(hy), 0.0f);
    b.yaw = static_cast<float>(yaw);
    const double g = groundAt(c);
    b.z0 = static_cast<float>(g + z0);
    b.z1 = static_cast<float>(g + z1);
    return b;
  }

  Primitive cylinder(const Eigen::Vector2d& c, double radius, double z0, double z1, Material m) const {
    Primitive p;
    p.kind = Primitive::Kind::kCylinder;
    p.material = m;
    p.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()), 0.0f);
    p.half = Eigen::Vector3f::Constant(static_cast<float>(radius));
    const double g = groundAt(c);
    p.z0 = static_cast<float>(g + z0);
    p.z1 = static_cast<float>(g + z1);
    return p;
  }

  Primitive ellipsoid(const Eigen::Vector2d& c, double z, const Eigen::Vector3d& radii, Material m,
                      double free_path) const {
    Primitive e;
    e.kind = Primitive::Kind::kEllipsoid;
    e.material = m;
    e.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(groundAt(c) + z));
    e.half = radii.cast<float>();
    e.free_path = static_cast<float>(free_path);
    return e;
  }

  /// Adds the solid when its footprint keeps `clearance` from every road and, grown by `margin`,
  /// overlaps nothing placed; marks it as taken.
  bool place(const Primitive& prim, const Footprint& f, double clearance, double margin) {
    if (!roads_.clear(f, clearance) || !occupied_.free(f, margin)) return false;
    occupied_.mark(f);
    out_.push_back(prim);
    return true;
  }

  bool placeBox(const Primitive& b, double clearance, double margin) {
    const Eigen::Vector2d c(b.center.x(), b.center.y());
    return place(b, footprintOf(c, b.yaw, b.half.x(), b.half.y()), clearance, margin);
  }

  /// A 2 m strip of raised pavement from the kerb to the property line. Other things stand on it, so it
  /// takes no room; it only has to keep off every road.
  double pavement(const PathPoint& p, double sign, const Style& style) {
    const double step = 2.0;
    const Eigen::Vector2d c = at(p, step / 2, sign * (kerb() + style.pavement / 2));
    const Primitive strip =
        box(c, p.heading, step / 2 + 0.05, style.pavement / 2, -0.3, 0.13, Material::kPavement);
    if (roads_.clear(footprintOf(c, p.heading, strip.half.x(), strip.half.y()), kerb() - 0.15)) out_.push_back(strip);
    return step;
  }

  double propertyLine(const Style& style) const { return kerb() + style.pavement; }

  /// A hedge, a wall or a fence along the property line, up to a driveway.
  double frontage(const PathPoint& p, double sign, const Style& style) {
    if (!chance(style.frontage)) return uniform(5.0, 15.0);
    const double length = uniform(6.0, 18.0);
    double thickness, height, free_path = 0.0;
    Material material = Material::kWall;
    const double kind = uniform(0.0, 1.0);
    if (style.industrial) {
      thickness = 0.05, height = uniform(1.8, 2.5), free_path = 0.08;  // wire mesh: half the rays pass
    } else if (kind < 0.45) {
      material = Material::kFoliage, thickness = uniform(0.6, 1.2), height = uniform(0.8, 2.0), free_path = 0.3;
    } else if (kind < 0.75) {
      thickness = 0.05, height = uniform(1.0, 1.6), free_path = 0.12;  // wooden or metal bars
    } else {
      thickness = 0.3, height = uniform(0.6, 2.2);
    }
    const Eigen::Vector2d c = at(p, length / 2, sign * (propertyLine(style) + 0.1 + thickness / 2));
    Primitive wall = box(c, p.heading, length / 2, thickness / 2, 0.0, height, material);
    wall.free_path = static_cast<float>(free_path);
    placeBox(wall, propertyLine(style) - 0.3, 0.05);
    return length + uniform(2.5, 5.0);
  }

  /// A building set back from the property line, sometimes with an annex, bays and a second row behind;
  /// returns how far along the street the next one starts.
  double building(const PathPoint& p, double sign, const Style& style) {
    if (chance(style.open_lot)) return uniform(8.0, 20.0);
    const double length = uniform(style.length_min, style.length_max);
    const double depth = uniform(style.depth_min, style.depth_max);
    const double height =
        chance(style.tower) ? uniform(20.0, 30.0) : uniform(style.height_min, style.height_max);
    const double setback = uniform(style.setback_min, style.setback_max);
    const double front = propertyLine(style) + setback;
    // Buildings that mostly stand alone are not quite square to the street; terraces are.
    const double yaw = p.heading + (style.adjoining < 0.5 ? uniform(-0.05, 0.05) : 0.0);
    const Eigen::Vector2d c = at(p, length / 2, sign * (front + depth / 2));
    // Terraced houses share walls: a slightly negative margin lets touching footprints through.
    if (!placeBox(box(c, yaw, length / 2, depth / 2, 0.0, height, Material::kBuilding), propertyLine(style) - 0.2,
                  -0.05)) {
      return uniform(2.0, 6.0);
    }
    if (chance(0.35)) {  // bays, porches or balconies standing out of the facade
      const int bays = 1 + static_cast<int>(uniform(0.0, 3.0));
      for (int b = 0; b < bays; ++b) {
        const double width = uniform(1.5, 3.5), out = uniform(0.5, 1.2);
        // On the ground only where the front garden has room for it, else a balcony.
        const double z0 = setback > out + 0.5 && chance(0.5) ? 0.0 : uniform(2.5, 3.5);
        const Eigen::Vector2d bc = at(p, uniform(width / 2, std::max(width / 2, length - width / 2)),
                                      sign * (front - out / 2));
        placeBox(box(bc, yaw, width / 2, out / 2, z0, std::max(z0 + 2.5, height - uniform(0.0, 3.0)),
                     Material::kBuilding),
                 propertyLine(style) - 0.2, -0.05);
      }
    }
    if (chance(0.3)) {  // an annex behind one end: an L-shaped footprint
      const double annex_len = uniform(4.0, std::max(4.5, length * 0.6)), annex_depth = uniform(4.0, 10.0);
      const double along = chance(0.5) ? annex_len / 2 : length - annex_len / 2;
      const Eigen::Vector2d ac = at(p, along, sign * (front + depth + annex_depth / 2));
      placeBox(box(ac, yaw, annex_len / 2, annex_depth / 2, 0.0, uniform(3.0, std::max(3.5, height)),
                   Material::kBuilding),
               propertyLine(style), -0.05);
    }
    if (chance(style.back_row)) {  // the next row of houses, seen through the gaps
      const double back_len = uniform(style.length_min, style.length_max), back_depth = uniform(8.0, 16.0);
      const Eigen::Vector2d bc = at(p, uniform(0.0, length), sign * (front + depth + uniform(6.0, 15.0) + back_depth / 2));
      placeBox(box(bc, yaw + uniform(-0.1, 0.1), back_len / 2, back_depth / 2, 0.0,
                   uniform(style.height_min, style.height_max + 6.0), Material::kBuilding),
               propertyLine(style) + 2.0, 0.5);
    }
    if (chance(style.garden) && setback > 3.5) garden(p, sign, front - setback, setback, length);
    return length + (chance(style.adjoining) ? 0.0 : uniform(style.gap_min, style.gap_max));
  }

  /// A tree or two and some bushes between the property line and the facade.
  void garden(const PathPoint& p, double sign, double line, double setback, double length) {
    if (chance(0.5)) tree(at(p, uniform(1.0, length - 1.0), sign * (line + setback / 2)), line, 0.7);
    const int bushes = static_cast<int>(uniform(0.0, 4.0));
    for (int b = 0; b < bushes; ++b) {
      const double r = uniform(0.5, 1.3);
      const Eigen::Vector2d c = at(p, uniform(0.0, length), sign * (line + uniform(0.8, setback - 0.5)));
      place(ellipsoid(c, 0.5 * r, Eigen::Vector3d(r, r, 0.8 * r), Material::kFoliage, 0.35),
            footprintOf(c, 0.0, r, r), line - 0.3, 0.0);
    }
  }

  /// A trunk and a canopy (broad, or narrow and tall for a conifer) at c; `scale` shrinks garden trees.
  void tree(const Eigen::Vector2d& c, double clearance, double scale) {
    const double trunk_r = uniform(0.12, 0.3) * scale;
    const bool conifer = chance(0.12);
    const double trunk_h = conifer ? uniform(0.8, 1.5) : uniform(2.3, 3.5) * std::max(scale, 0.8);
    const Primitive trunk = cylinder(c, trunk_r, 0.0, trunk_h + 0.5, Material::kTrunk);
    if (!place(trunk, footprintOf(c, 0.0, trunk_r + 0.2, trunk_r + 0.2), clearance, 0.3)) return;
    const double r = conifer ? uniform(1.2, 2.0) : uniform(1.8, 3.5) * scale;
    const double rz = conifer ? uniform(3.0, 5.0) : uniform(1.5, 3.2) * scale;
    out_.push_back(ellipsoid(c, trunk_h + rz, Eigen::Vector3d(r, r, rz), Material::kFoliage, 0.8));
  }

  double streetTree(const PathPoint& p, double sign, const Style& style) {
    if (chance(style.street_tree)) tree(at(p, 0.0, sign * (kerb() + 0.9)), kerb() + 0.3, 1.0);
    return uniform(style.tree_min, style.tree_max);
  }

  /// A street light with its arm over the road, sometimes a sign post beside it.
  double streetLight(const PathPoint& p, double sign) {
    const Eigen::Vector2d c = at(p, 0.0, sign * (kerb() + 0.4));
    const double height = uniform(6.0, 9.0);
    if (place(cylinder(c, uniform(0.08, 0.14), 0.0, height, Material::kPole), footprintOf(c, 0.0, 0.15, 0.15),
              kerb() + 0.1, 0.3)) {
      const Eigen::Vector2d arm = at(p, 0.0, sign * (kerb() + 0.4 - 0.9));
      out_.push_back(box(arm, p.heading, 0.08, 0.9, height - 0.25, height - 0.05, Material::kPole));
    }
    if (chance(0.35)) {
      const Eigen::Vector2d post = at(p, uniform(4.0, 10.0), sign * (kerb() + 0.35));
      const double top = uniform(2.4, 3.2);
      if (place(cylinder(post, 0.04, 0.0, top, Material::kPole), footprintOf(post, 0.0, 0.1, 0.1), kerb() + 0.1,
                0.3)) {
        out_.push_back(box(post, p.heading, 0.02, 0.35, top - 0.7, top, Material::kSign));
      }
    }
    return uniform(25.0, 40.0);
  }

  /// Small things on the pavement: a bin, a utility cabinet, a bench, a row of bollards or a bus shelter.
  double streetFurniture(const PathPoint& p, double sign, const Style& style) {
    const double kind = uniform(0.0, 1.0);
    const double kerb_side = kerb() + 0.6, wall_side = propertyLine(style) - 0.4;
    const auto put = [&](const Eigen::Vector2d& c, double hx, double hy, double z0, double z1, Material m) {
      return placeBox(box(c, p.heading, hx, hy, z0, z1, m), kerb() + 0.1, 0.2);
    };
    if (kind < 0.3) {
      put(at(p, 0.0, sign * kerb_side), 0.3, 0.3, 0.0, uniform(0.9, 1.2), Material::kWall);  // bin
    } else if (kind < 0.5) {
      put(at(p, 0.0, sign * wall_side), 0.45, 0.2, 0.0, uniform(1.1, 1.5), Material::kWall);  // cabinet
    } else if (kind < 0.65) {
      put(at(p, 0.0, sign * wall_side), 0.9, 0.3, 0.0, uniform(0.45, 0.8), Material::kWall);  // bench
    } else if (kind < 0.85) {
      const int count = 3 + static_cast<int>(uniform(0.0, 4.0));
      for (int b = 0; b < count; ++b) {
        const Eigen::Vector2d c = at(p, 1.5 * b, sign * (kerb() + 0.3));
        place(cylinder(c, 0.08, 0.0, uniform(0.8, 1.0), Material::kPole), footprintOf(c, 0.0, 0.1, 0.1),
              kerb() + 0.1, 0.2);
      }
    } else if (kind < 0.92) {
      // Bus shelter: roof and back panel; its glass sides let the beams through.
      const Eigen::Vector2d roof = at(p, 0.0, sign * (wall_side - 0.5));
      if (put(roof, 1.8, 0.8, 2.3, 2.5, Material::kWall)) {
        out_.push_back(box(at(p, 0.0, sign * (wall_side - 0.05)), p.heading, 1.8, 0.04, 0.1, 2.3, Material::kSign));
      }
    }
    return uniform(8.0, 25.0);
  }

  /// Body and cabin of one vehicle, kerb side at the kerb, starting `along` ahead of p.
  struct Vehicle {
    Primitive body, cabin;
    double length, width;
  };

  Vehicle vehicle(const PathPoint& p, double sign, double along, bool industrial) {
    Vehicle v;
    double body_top, roof, cabin_frac;
    const double kind = uniform(0.0, 1.0);
    if (industrial && kind < 0.3) {  // box van or lorry: one tall block
      v.length = uniform(6.0, 9.0), v.width = uniform(2.2, 2.5), body_top = uniform(2.6, 3.4), roof = body_top;
      cabin_frac = 0.0;
    } else if (kind < 0.35) {  // small car
      v.length = uniform(3.5, 4.1), v.width = uniform(1.6, 1.75), body_top = uniform(0.85, 0.95);
      roof = uniform(1.4, 1.55), cabin_frac = 0.55;
    } else if (kind < 0.78) {  // saloon or estate
      v.length = uniform(4.3, 4.9), v.width = uniform(1.75, 1.9), body_top = uniform(0.9, 1.0);
      roof = uniform(1.4, 1.5), cabin_frac = 0.5;
    } else {  // SUV or van
      v.length = uniform(4.5, 5.3), v.width = uniform(1.85, 2.05), body_top = uniform(1.05, 1.2);
      roof = uniform(1.7, 2.0), cabin_frac = 0.65;
    }
    const double yaw = p.heading + uniform(-0.04, 0.04);
    const double lateral = sign * (kerb() - 0.25 - v.width / 2);
    const Eigen::Vector2d c = at(p, along + v.length / 2, lateral);
    v.body = box(c, yaw, v.length / 2, v.width / 2, 0.3, body_top, Material::kCar);
    v.cabin = v.body;
    if (cabin_frac > 0.0) {
      // The cabin sits a little behind the middle, narrower than the body.
      const Eigen::Vector2d cc = at(p, along + v.length / 2 - 0.1 * v.length, lateral);
      v.cabin = box(cc, yaw, v.length * cabin_frac / 2, v.width / 2 - 0.08, body_top, roof, Material::kCar);
    }
    return v;
  }

  /// One parking space: empty, a car parked for the whole drive, or one that leaves, arrives or moves
  /// along the kerb at a time during the drive, so later visits find the street a little different.
  double parkedCar(const PathPoint& p, double sign, const Style& style) {
    if (!chance(style.parking)) return uniform(3.0, 8.0);
    Vehicle v = vehicle(p, sign, 0.0, style.industrial);
    const double clearance = kerb() - 2.3;  // parked cars stand on the road's edge, clear of other roads
    const auto fp = [](const Primitive& b) {
      return footprintOf(Eigen::Vector2d(b.center.x(), b.center.y()), b.yaw, b.half.x(), b.half.y());
    };
    const double advance = v.length + uniform(0.6, 2.5);
    if (!roads_.clear(fp(v.body), clearance) || !occupied_.free(fp(v.body), 0.3)) return advance;
    const bool dynamic = options_.duration > 0.0 && chance(options_.dynamic_car_fraction);
    if (!dynamic) {
      occupied_.mark(fp(v.body));
      out_.push_back(v.body);
      if (v.cabin.z1 > v.body.z1) out_.push_back(v.cabin);
      return advance;
    }
    const double when = uniform(0.0, options_.duration);
    const double kind = uniform(0.0, 1.0);
    if (kind < 1.0 / 3.0) {  // leaves at `when`
      v.body.present_to = v.cabin.present_to = when;
    } else if (kind < 2.0 / 3.0) {  // arrives at `when`
      v.body.present_from = v.cabin.present_from = when;
    } else {  // moves a few metres along the kerb at `when`
      Vehicle moved = v;
      const double shift = (chance(0.5) ? 1.0 : -1.0) * uniform(2.0, 6.0);
      const Eigen::Vector2d offset = at(p, shift, 0.0) - at(p, 0.0, 0.0);
      for (Primitive* b : {&moved.body, &moved.cabin}) {
        b->center.x() += static_cast<float>(offset.x());
        b->center.y() += static_cast<float>(offset.y());
        b->present_from = when;
      }
      if (roads_.clear(fp(moved.body), clearance) && occupied_.free(fp(moved.body), 0.3)) {
        v.body.present_to = v.cabin.present_to = when;
        occupied_.mark(fp(moved.body));
        out_.push_back(moved.body);
        if (moved.cabin.z1 > moved.body.z1) out_.push_back(moved.cabin);
      }
    }
    occupied_.mark(fp(v.body));
    out_.push_back(v.body);
    if (v.cabin.z1 > v.body.z1) out_.push_back(v.cabin);
    return advance;
  }

  const std::vector<PathPoint>& dense_;
  WorldOptions options_;
  Eigen::Vector3d ground_;
  RoadMap roads_;
  Occupancy occupied_;
  std::mt19937 rng_;
  std::vector<Primitive> out_;
};

}  // namespace

World generateWorld(const std::vector<PathPoint>& path, const WorldOptions& options) {
  const std::vector<PathPoint> dense = densify(path, 1.0);
  std::vector<Primitive> primitives = StreetBuilder(dense, options).build();
  return World(std::move(primitives), groundPlane(options));
}

}  // namespace sim
}  // namespace scan_context_loop
