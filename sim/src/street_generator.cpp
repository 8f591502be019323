// Builds the street world along a driven path: every side of every street is furnished as the path is
// walked, in the character of the district it runs through.
#include <algorithm>
#include <cmath>
#include <random>

#include "placement.h"
#include "scan_context_sim/world.h"
#include "street_kit.h"
#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

namespace {

/// Places things along both sides of the path as it walks it, and records what may change later.
class StreetBuilder : public StreetKit {
 public:
  StreetBuilder(const std::vector<PathPoint>& dense, const WorldOptions& options) : StreetKit(dense, options) {}

  StreetRecord build() {
    // Each side of the road keeps, per kind of thing, the arc length up to which it is furnished.
    enum { kPavement, kFrontage, kBuilding, kTree, kLight, kFurniture, kCar, kKinds };
    double next[kKinds][2] = {};
    double s = 0.0;
    for (std::size_t k = 0; k < dense.size(); ++k) {
      if (k > 0) s += std::hypot(dense[k].x - dense[k - 1].x, dense[k].y - dense[k - 1].y);
      const PathPoint& p = dense[k];
      for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0;  // left, right of the direction of travel
        const District district = districtAt(at(p, 0.0, sign * 15.0));
        const Style& style = styleOf(district);
        if (s >= next[kPavement][side]) next[kPavement][side] = s + pavement(p, sign, style);
        if (s >= next[kFrontage][side]) next[kFrontage][side] = s + frontage(p, sign, district);
        if (s >= next[kBuilding][side]) next[kBuilding][side] = s + building(p, sign, district);
        if (s >= next[kTree][side]) next[kTree][side] = s + streetTree(p, sign, style);
        if (s >= next[kLight][side]) next[kLight][side] = s + streetLight(p, sign);
        if (s >= next[kFurniture][side]) next[kFurniture][side] = s + streetFurniture(p, sign, style);
        if (options.vehicles && s >= next[kCar][side]) next[kCar][side] = s + parkedCar(p, sign, style);
      }
    }
    return std::move(record_);
  }

 private:
  /// With repeat_templates, a building (with its bays, annex, back row and garden) or a stretch of
  /// frontage is one of a few designs per district character, the same all over one district square,
  /// as in estates and terraces of identical houses: fn draws from a generator seeded by the design, so
  /// each design looks the same in every street that gets it, and squares of one character that get
  /// the same design look alike. Off, fn draws from the world's generator as ever.
  template <typename Fn>
  double fromDesign(const PathPoint& p, double sign, District district, std::uint64_t what, Fn fn) {
    if (!options.repeat_templates) return fn();
    constexpr std::uint64_t kDesigns = 5;
    const std::uint64_t design = mix(squareDraw(at(p, 0.0, sign * 15.0)) ^ 0x5D3A1E7Bull) % kDesigns;
    std::mt19937 draws(static_cast<std::uint32_t>(
        mix(mix(options.seed ^ 0x7E3A9D1Bull) ^ (what << 16 | static_cast<std::uint64_t>(district) << 8 | design))));
    const DrawFrom scoped(*this, &draws);
    return fn();
  }

  /// A 2 m strip of raised pavement from the kerb to the property line. Other things stand on it, so it
  /// takes no room; it only has to keep off every road.
  double pavement(const PathPoint& p, double sign, const Style& style) {
    const double step = 2.0;
    const Eigen::Vector2d c = at(p, step / 2, sign * (kerb() + style.pavement / 2));
    const Primitive strip = box(c, p.heading, step / 2 + 0.05, style.pavement / 2, -0.3, 0.13, Material::kPavement);
    if (roads.clear(footprintOf(c, p.heading, strip.half.x(), strip.half.y()), kerb() - 0.15)) out.push_back(strip);
    return step;
  }

  /// A hedge, a wall or a fence along the property line, up to a driveway.
  double frontage(const PathPoint& p, double sign, District district) {
    const Style& style = styleOf(district);
    if (!chance(style.frontage)) return uniform(5.0, 15.0);
    return fromDesign(p, sign, district, 1, [&] { return frontageDesign(p, sign, style); });
  }

  double frontageDesign(const PathPoint& p, double sign, const Style& style) {
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
    Primitive wall = alongPropertyLine(p, sign, style, length, thickness, height, material);
    wall.free_path = static_cast<float>(free_path);
    if (placeBox(wall, propertyLine(style) - 0.3, 0.05) && material == Material::kFoliage) {
      record_.hedges.push_back(out.size() - 1);
    }
    return length + uniform(2.5, 5.0);
  }

  /// A building set back from the property line, sometimes with an annex, bays and a second row behind;
  /// returns how far along the street the next one starts.
  double building(const PathPoint& p, double sign, District district) {
    const Style& style = styleOf(district);
    if (chance(style.open_lot)) return uniform(8.0, 20.0);
    return fromDesign(p, sign, district, 2, [&] { return buildingDesign(p, sign, style); });
  }

  double buildingDesign(const PathPoint& p, double sign, const Style& style) {
    const double length = uniform(style.length_min, style.length_max);
    const double depth = uniform(style.depth_min, style.depth_max);
    const double height = chance(style.tower) ? uniform(20.0, 30.0) : uniform(style.height_min, style.height_max);
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
        const Eigen::Vector2d bc =
            at(p, uniform(width / 2, std::max(width / 2, length - width / 2)), sign * (front - out / 2));
        placeBox(
            box(bc, yaw, width / 2, out / 2, z0, std::max(z0 + 2.5, height - uniform(0.0, 3.0)), Material::kBuilding),
            propertyLine(style) - 0.2, -0.05);
      }
    }
    if (chance(0.3)) {  // an annex behind one end: an L-shaped footprint
      const double annex_len = uniform(4.0, std::max(4.5, length * 0.6)), annex_depth = uniform(4.0, 10.0);
      const double along = chance(0.5) ? annex_len / 2 : length - annex_len / 2;
      const Eigen::Vector2d ac = at(p, along, sign * (front + depth + annex_depth / 2));
      placeBox(
          box(ac, yaw, annex_len / 2, annex_depth / 2, 0.0, uniform(3.0, std::max(3.5, height)), Material::kBuilding),
          propertyLine(style), -0.05);
    }
    if (chance(style.back_row)) {  // the next row of houses, seen through the gaps
      const double back_len = uniform(style.length_min, style.length_max), back_depth = uniform(8.0, 16.0);
      const Eigen::Vector2d bc =
          at(p, uniform(0.0, length), sign * (front + depth + uniform(6.0, 15.0) + back_depth / 2));
      placeBox(box(bc, yaw + uniform(-0.1, 0.1), back_len / 2, back_depth / 2, 0.0,
                   uniform(style.height_min, style.height_max + 6.0), Material::kBuilding),
               propertyLine(style) + 2.0, 0.5);
    }
    if (chance(style.garden) && setback > 3.5) garden(p, sign, front - setback, setback, length);
    return length + (chance(style.adjoining) ? 0.0 : uniform(style.gap_min, style.gap_max));
  }

  /// A tree or two and some bushes between the property line and the facade.
  void garden(const PathPoint& p, double sign, double line, double setback, double length) {
    if (chance(0.5)) tree(at(p, uniform(1.0, length - 1.0), sign * (line + setback / 2)), line, 0.7, &record_);
    const int bushes = static_cast<int>(uniform(0.0, 4.0));
    for (int b = 0; b < bushes; ++b) {
      const double r = uniform(0.5, 1.3);
      const Eigen::Vector2d c = at(p, uniform(0.0, length), sign * (line + uniform(0.8, setback - 0.5)));
      if (place(ellipsoid(c, 0.5 * r, Eigen::Vector3d(r, r, 0.8 * r), Material::kFoliage, 0.35),
                footprintOf(c, 0.0, r, r), line - 0.3, 0.0)) {
        record_.bushes.push_back(out.size() - 1);
      }
    }
  }

  double streetTree(const PathPoint& p, double sign, const Style& style) {
    if (chance(style.street_tree)) tree(at(p, 0.0, sign * (kerb() + 0.9)), kerb() + 0.3, 1.0, &record_);
    return uniform(style.tree_min, style.tree_max);
  }

  /// A street light with its arm over the road, sometimes a sign post beside it.
  double streetLight(const PathPoint& p, double sign) {
    const Eigen::Vector2d c = at(p, 0.0, sign * (kerb() + 0.4));
    const double height = uniform(6.0, 9.0);
    if (place(cylinder(c, uniform(0.08, 0.14), 0.0, height, Material::kPole), footprintOf(c, 0.0, 0.15, 0.15),
              kerb() + 0.1, 0.3)) {
      // The arm reaches 1.8 m over the road, less over a narrow path, which it keeps clear.
      const double reach = std::min(1.8, kerb() + 0.4 - kPathClearance);
      const Eigen::Vector2d arm = at(p, 0.0, sign * (kerb() + 0.4 - reach / 2));
      out.push_back(box(arm, p.heading, 0.08, reach / 2, height - 0.25, height - 0.05, Material::kPole));
    }
    if (chance(0.35)) {
      const Eigen::Vector2d post = at(p, uniform(4.0, 10.0), sign * (kerb() + 0.35));
      const double top = uniform(2.4, 3.2);
      if (place(cylinder(post, 0.04, 0.0, top, Material::kPole), footprintOf(post, 0.0, 0.1, 0.1), kerb() + 0.1, 0.3)) {
        out.push_back(box(post, p.heading, 0.02, 0.35, top - 0.7, top, Material::kSign));
        record_.furniture.push_back({{out.size() - 2, out.size() - 1}, p.heading});
      }
    }
    return uniform(25.0, 40.0);
  }

  /// Small things on the pavement: a bin, a utility cabinet, a bench, a row of bollards or a bus shelter.
  double streetFurniture(const PathPoint& p, double sign, const Style& style) {
    const double kind = uniform(0.0, 1.0);
    const double kerb_side = kerb() + 0.6, wall_side = propertyLine(style) - 0.4;
    // What is placed from here on is one piece of furniture (WorldOptions::furniture moves it).
    const std::size_t first = out.size();
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
        place(cylinder(c, 0.08, 0.0, uniform(0.8, 1.0), Material::kPole), footprintOf(c, 0.0, 0.1, 0.1), kerb() + 0.1,
              0.2);
      }
    } else if (kind < 0.92) {
      // Bus shelter: roof and back panel; its glass sides let the beams through.
      const Eigen::Vector2d roof = at(p, 0.0, sign * (wall_side - 0.5));
      if (put(roof, 1.8, 0.8, 2.3, 2.5, Material::kWall)) {
        out.push_back(box(at(p, 0.0, sign * (wall_side - 0.05)), p.heading, 1.8, 0.04, 0.1, 2.3, Material::kSign));
      }
    }
    if (out.size() > first) {
      record_.furniture.push_back({{}, p.heading});
      for (std::size_t i = first; i < out.size(); ++i) record_.furniture.back().solids.push_back(i);
    }
    return uniform(8.0, 25.0);
  }

  /// One parking space: empty, a car parked for the whole drive, or one that leaves, arrives or moves
  /// along the kerb at a time during the drive, so later visits find the street a little different.
  double parkedCar(const PathPoint& p, double sign, const Style& style) {
    if (!chance(style.parking)) {
      record_.empty_spaces.push_back({p, sign, style.industrial});
      return uniform(3.0, 8.0);
    }
    Vehicle v = parkedVehicle(p, sign, 0.0, style.industrial);
    const double advance = v.length + uniform(0.6, 2.5);
    if (!roads.clear(footprintOf(v.body), parkingClearance()) || !occupied.free(footprintOf(v.body), 0.3)) {
      return advance;
    }
    const bool dynamic = options.duration > 0.0 && chance(options.dynamic_car_fraction);
    if (!dynamic) {
      occupied.mark(footprintOf(v.body));
      record_.parked.push_back(add(v));
      return advance;
    }
    const double when = uniform(0.0, options.duration);
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
      if (roads.clear(footprintOf(moved.body), parkingClearance()) && occupied.free(footprintOf(moved.body), 0.3)) {
        v.body.present_to = v.cabin.present_to = when;
        occupied.mark(footprintOf(moved.body));
        add(moved);
      }
    }
    occupied.mark(footprintOf(v.body));
    add(v);
    return advance;
  }

  StreetRecord record_;
};

}  // namespace

namespace {

/// The world along `paths`; the changes during the drive (changed_world) follow the drive `path`,
/// nullptr for none.
World build(const std::vector<std::vector<PathPoint>>& paths, const std::vector<PathPoint>* path,
            const WorldOptions& options, const LaterDrive* later) {
  std::vector<PathPoint> dense;
  for (const std::vector<PathPoint>& p : paths) {
    const std::vector<PathPoint> d = densify(p, 1.0);
    dense.insert(dense.end(), d.begin(), d.end());
  }
  StreetBuilder builder(dense, options);
  const StreetRecord record =
      options.style == WorldOptions::Style::kSuburb ? buildSuburb(&builder) : builder.build();
  if (path != nullptr && options.changed_world > 0.0 && options.duration > 0.0) {
    changeWorld(*path, options.times, record, duringDrive(options), &builder);
  }
  if (path != nullptr) harderChanges(*path, options.times, record, &builder);
  if (later != nullptr && !later->times.empty()) {
    Changes since;
    since.strength = later->changed;
    since.from = since.to = later->times.front();
    since.seen_before = true;
    since.salt = 0x2D7F93A1B6C5E8ull;
    changeWorld(later->path, later->times, record, since, &builder);
  }
  return World(std::move(builder.out), groundPlane(options));
}

}  // namespace

World generateWorld(const std::vector<PathPoint>& path, const WorldOptions& options) {
  return build({path}, &path, options, nullptr);
}

World generateWorld(const std::vector<PathPoint>& path, const WorldOptions& options, const LaterDrive& later) {
  return build({path}, &path, options, &later);
}

World generateWorld(const std::vector<std::vector<PathPoint>>& paths, const WorldOptions& options) {
  return build(paths, nullptr, options, nullptr);
}

}  // namespace sim
}  // namespace scan_context_loop
