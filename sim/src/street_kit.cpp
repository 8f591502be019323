#include "street_kit.h"

#include <cmath>

namespace scan_context_loop {
namespace sim {

const Style& styleOf(District d) {
  // clang-format off
  //                                pave  front setback     length      depth       height      tower adjoin gap        open  back  tree  pits        park  garden industrial
  static const Style kTerrace    = {4.0, 0.1,  0.5, 1.5,  10.0, 24.0, 10.0, 16.0,  9.0, 20.0, 0.12, 0.75, 1.0,  4.0, 0.05, 0.5,  0.45, 8.0, 14.0, 0.8,  0.0, false};
  static const Style kHouses     = {2.5, 0.85, 2.5, 6.0,   8.0, 15.0,  8.0, 12.0,  5.0, 11.0, 0.0,  0.3,  2.0,  6.0, 0.05, 0.6,  0.6,  8.0, 14.0, 0.7,  0.7, false};
  static const Style kAvenue     = {4.5, 0.4,  2.0, 8.0,  14.0, 30.0, 10.0, 18.0,  8.0, 22.0, 0.2,  0.3,  3.0, 10.0, 0.06, 0.5,  0.95, 7.0, 10.0, 0.55, 0.5, false};
  static const Style kIndustrial = {2.0, 0.8,  3.0, 10.0, 20.0, 45.0, 12.0, 30.0,  6.0, 12.0, 0.05, 0.1,  4.0, 12.0, 0.1,  0.3,  0.25, 10.0, 20.0, 0.35, 0.0, true};
  // clang-format on
  switch (d) {
    case District::kTerrace:
      return kTerrace;
    case District::kHouses:
      return kHouses;
    case District::kAvenue:
      return kAvenue;
    case District::kIndustrial:
      return kIndustrial;
  }
  return kTerrace;
}

std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

Eigen::Vector3d groundPlane(const WorldOptions& options) {
  const double direction = 2.0 * M_PI * static_cast<double>(mix(options.seed) >> 11) / 9007199254740992.0;
  return {options.ground_slope * std::cos(direction), options.ground_slope * std::sin(direction), 0.0};
}

StreetKit::StreetKit(const std::vector<PathPoint>& dense_path, const WorldOptions& world_options)
    : dense(dense_path),
      options(world_options),
      ground(groundPlane(world_options)),
      roads(dense_path),
      base_rng(world_options.seed) {}

std::uint64_t StreetKit::squareDraw(const Eigen::Vector2d& q) const {
  const auto i = static_cast<std::int64_t>(std::floor(q.x() / options.district_size));
  const auto j = static_cast<std::int64_t>(std::floor(q.y() / options.district_size));
  return mix(mix(options.seed ^ static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^ static_cast<std::uint64_t>(j));
}

District StreetKit::districtAt(const Eigen::Vector2d& q) const {
  // A suburb is houses all over: the changes then draw their pavements and parking from its style.
  if (options.style == WorldOptions::Style::kSuburb) return District::kHouses;
  const double u = static_cast<double>(squareDraw(q) >> 11) / 9007199254740992.0;
  if (u < 0.3) return District::kTerrace;
  if (u < 0.65) return District::kHouses;
  if (u < 0.85) return District::kAvenue;
  return District::kIndustrial;
}

Eigen::Vector2d StreetKit::at(const PathPoint& p, double along, double lateral) {
  const double c = std::cos(p.heading), s = std::sin(p.heading);
  return {p.x + c * along - s * lateral, p.y + s * along + c * lateral};
}

Footprint StreetKit::footprintOf(const Eigen::Vector2d& c, double yaw, double hx, double hy) {
  Footprint f;
  f.center = c;
  f.yaw = yaw;
  f.half = Eigen::Vector2d(hx, hy);
  return f;
}

Footprint StreetKit::footprintOf(const Primitive& b) {
  return footprintOf(Eigen::Vector2d(b.center.x(), b.center.y()), b.yaw, b.half.x(), b.half.y());
}

Primitive StreetKit::box(const Eigen::Vector2d& c, double yaw, double hx, double hy, double z0, double z1,
                         Material m) const {
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

Primitive StreetKit::cylinder(const Eigen::Vector2d& c, double radius, double z0, double z1, Material m) const {
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

Primitive StreetKit::ellipsoid(const Eigen::Vector2d& c, double z, const Eigen::Vector3d& radii, Material m,
                               double free_path) const {
  Primitive e;
  e.kind = Primitive::Kind::kEllipsoid;
  e.material = m;
  e.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(groundAt(c) + z));
  e.half = radii.cast<float>();
  e.free_path = static_cast<float>(free_path);
  return e;
}

bool StreetKit::place(const Primitive& prim, const Footprint& f, double clearance, double margin) {
  if (!roads.clear(f, clearance) || !occupied.free(f, margin)) return false;
  occupied.mark(f);
  out.push_back(prim);
  return true;
}

VehicleShape StreetKit::vehicleShape(bool industrial) {
  VehicleShape v;
  const double kind = uniform(0.0, 1.0);
  if (industrial && kind < 0.3) {  // box van or lorry: one tall block
    v.length = uniform(6.0, 9.0), v.width = uniform(2.2, 2.5), v.body_top = uniform(2.6, 3.4), v.roof = v.body_top;
    v.cabin_frac = 0.0;
  } else if (kind < 0.35) {  // small car
    v.length = uniform(3.5, 4.1), v.width = uniform(1.6, 1.75), v.body_top = uniform(0.85, 0.95);
    v.roof = uniform(1.4, 1.55), v.cabin_frac = 0.55;
  } else if (kind < 0.78) {  // saloon or estate
    v.length = uniform(4.3, 4.9), v.width = uniform(1.75, 1.9), v.body_top = uniform(0.9, 1.0);
    v.roof = uniform(1.4, 1.5), v.cabin_frac = 0.5;
  } else {  // SUV or van
    v.length = uniform(4.5, 5.3), v.width = uniform(1.85, 2.05), v.body_top = uniform(1.05, 1.2);
    v.roof = uniform(1.7, 2.0), v.cabin_frac = 0.65;
  }
  return v;
}

Vehicle StreetKit::vehicleAt(const VehicleShape& shape, const PathPoint& p, double along, double lateral,
                             double yaw) const {
  Vehicle v;
  v.length = shape.length;
  v.width = shape.width;
  const Eigen::Vector2d c = at(p, along + v.length / 2, lateral);
  v.body = box(c, yaw, v.length / 2, v.width / 2, 0.3, shape.body_top, Material::kCar);
  v.cabin = v.body;
  if (shape.cabin_frac > 0.0) {
    // The cabin sits a little behind the middle, narrower than the body.
    const Eigen::Vector2d cc = at(p, along + v.length / 2 - 0.1 * v.length, lateral);
    v.cabin =
        box(cc, yaw, v.length * shape.cabin_frac / 2, v.width / 2 - 0.08, shape.body_top, shape.roof, Material::kCar);
  }
  return v;
}

Vehicle StreetKit::parkedVehicle(const PathPoint& p, double sign, double along, bool industrial) {
  const VehicleShape shape = vehicleShape(industrial);
  const double yaw = p.heading + uniform(-0.04, 0.04);
  return vehicleAt(shape, p, along, sign * (kerb() - 0.25 - shape.width / 2), yaw);
}

void StreetKit::tree(const Eigen::Vector2d& c, double clearance, double scale, StreetRecord* record) {
  const double trunk_r = uniform(0.12, 0.3) * scale;
  const bool conifer = chance(0.12);
  const double trunk_h = conifer ? uniform(0.8, 1.5) : uniform(2.3, 3.5) * std::max(scale, 0.8);
  const Primitive trunk = cylinder(c, trunk_r, 0.0, trunk_h + 0.5, Material::kTrunk);
  if (!place(trunk, footprintOf(c, 0.0, trunk_r + 0.2, trunk_r + 0.2), clearance, 0.3)) return;
  double r = conifer ? uniform(1.2, 2.0) : uniform(1.8, 3.5) * scale;
  // Beside a narrow path the canopy is smaller, so it does not hang over the path.
  while (r > 0.6 && !roads.clear(footprintOf(c, 0.0, r, r), kPathClearance)) r *= 0.9;
  const double rz = conifer ? uniform(3.0, 5.0) : uniform(1.5, 3.2) * scale;
  record->trees.push_back({out.size() - 1, out.size(), conifer});
  out.push_back(ellipsoid(c, trunk_h + rz, Eigen::Vector3d(r, r, rz), Material::kFoliage, 0.8));
}

StreetRecord::Car StreetKit::add(const Vehicle& v) {
  StreetRecord::Car car;
  car.body = car.cabin = out.size();
  out.push_back(v.body);
  if (v.cabin.z1 > v.body.z1) {
    car.cabin = out.size();
    out.push_back(v.cabin);
  }
  return car;
}

}  // namespace sim
}  // namespace scan_context_loop
