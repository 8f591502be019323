#include "scan_context_loop/sim/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <unordered_map>

namespace scan_context_loop {
namespace sim {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Horizontal bounding box of a primitive.
void footprint(const Primitive& p, float* x0, float* y0, float* x1, float* y1) {
  float rx = p.half.x(), ry = p.half.y();
  if (p.kind == Primitive::Kind::kBox) {
    const float c = std::fabs(std::cos(p.yaw)), s = std::fabs(std::sin(p.yaw));
    rx = c * p.half.x() + s * p.half.y();
    ry = s * p.half.x() + c * p.half.y();
  } else if (p.kind == Primitive::Kind::kCylinder) {
    ry = rx;
  }
  *x0 = p.center.x() - rx;
  *x1 = p.center.x() + rx;
  *y0 = p.center.y() - ry;
  *y1 = p.center.y() + ry;
}

}  // namespace

World::World(std::vector<Primitive> primitives, const Eigen::Vector3d& ground, float cell_size)
    : primitives_(std::move(primitives)), ground_(ground), cell_(cell_size) {
  float x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (const auto& p : primitives_) {
    float a, b, c, d;
    footprint(p, &a, &b, &c, &d);
    x0 = std::min(x0, a);
    y0 = std::min(y0, b);
    x1 = std::max(x1, c);
    y1 = std::max(y1, d);
  }
  if (primitives_.empty()) x0 = y0 = x1 = y1 = 0.0f;
  min_x_ = x0;
  min_y_ = y0;
  nx_ = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cell_)) + 1);
  ny_ = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cell_)) + 1);
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (std::uint32_t id = 0; id < primitives_.size(); ++id) {
    float a, b, c, d;
    footprint(primitives_[id], &a, &b, &c, &d);
    const int i0 = std::max(0, static_cast<int>((a - min_x_) / cell_));
    const int i1 = std::min(nx_ - 1, static_cast<int>((c - min_x_) / cell_));
    const int j0 = std::max(0, static_cast<int>((b - min_y_) / cell_));
    const int j1 = std::min(ny_ - 1, static_cast<int>((d - min_y_) / cell_));
    for (int i = i0; i <= i1; ++i) {
      for (int j = j0; j <= j1; ++j) cells_[static_cast<std::size_t>(j) * nx_ + i].push_back(id);
    }
  }
}

bool World::intersect(const Primitive& p, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max,
                      Hit* hit) const {
  switch (p.kind) {
    case Primitive::Kind::kBox: {
      // Into the box frame: centred, x along the yaw.
      const float c = std::cos(p.yaw), s = std::sin(p.yaw);
      const float ox = o.x() - p.center.x(), oy = o.y() - p.center.y();
      const Eigen::Vector3f lo(c * ox + s * oy, -s * ox + c * oy, o.z() - 0.5f * (p.z0 + p.z1));
      const Eigen::Vector3f ld(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
      const Eigen::Vector3f half(p.half.x(), p.half.y(), 0.5f * (p.z1 - p.z0));
      float t0 = 0.0f, t1 = t_max;
      int axis = -1;
      for (int k = 0; k < 3; ++k) {
        if (std::fabs(ld[k]) < 1e-9f) {
          if (std::fabs(lo[k]) > half[k]) return false;
          continue;
        }
        float a = (-half[k] - lo[k]) / ld[k], b = (half[k] - lo[k]) / ld[k];
        if (a > b) std::swap(a, b);
        if (a > t0) {
          t0 = a;
          axis = k;
        }
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
      }
      if (axis < 0 || t0 <= 0.0f) return false;  // starting inside a solid: no return
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = ld[axis] > 0 ? -1.0f : 1.0f;
      hit->range = t0;
      hit->normal = Eigen::Vector3f(c * n.x() - s * n.y(), s * n.x() + c * n.y(), n.z());
      hit->material = p.material;
      return true;
    }
    case Primitive::Kind::kCylinder: {
      const float ox = o.x() - p.center.x(), oy = o.y() - p.center.y();
      const float a = d.x() * d.x() + d.y() * d.y();
      if (a < 1e-12f) return false;
      const float b = ox * d.x() + oy * d.y();
      const float cc = ox * ox + oy * oy - p.half.x() * p.half.x();
      const float disc = b * b - a * cc;
      if (disc < 0.0f) return false;
      const float t = (-b - std::sqrt(disc)) / a;
      if (t <= 0.0f || t > t_max) return false;
      const float z = o.z() + t * d.z();
      if (z < p.z0 || z > p.z1) return false;
      hit->range = t;
      hit->normal = Eigen::Vector3f(ox + t * d.x(), oy + t * d.y(), 0.0f).normalized();
      hit->material = p.material;
      return true;
    }
    case Primitive::Kind::kEllipsoid: {
      const Eigen::Vector3f so = (o - p.center).cwiseQuotient(p.half);
      const Eigen::Vector3f sd = d.cwiseQuotient(p.half);
      const float a = sd.squaredNorm(), b = so.dot(sd), cc = so.squaredNorm() - 1.0f;
      const float disc = b * b - a * cc;
      if (disc < 0.0f) return false;
      const float t = (-b - std::sqrt(disc)) / a;
      if (t <= 0.0f || t > t_max) return false;
      hit->range = t;
      hit->normal = (so + t * sd).cwiseQuotient(p.half).normalized();
      hit->material = p.material;
      return true;
    }
  }
  return false;
}

bool World::cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float max_range, double time,
                 std::uint32_t ray_id, std::vector<std::uint32_t>* visit, Hit* hit) const {
  float best = max_range;
  bool found = false;
  // Ground plane: z - gx x - gy y - g0 = 0.
  const float gx = static_cast<float>(ground_.x()), gy = static_cast<float>(ground_.y());
  const float denom = direction.z() - gx * direction.x() - gy * direction.y();
  if (denom < -1e-6f) {
    const float t = -(origin.z() - gx * origin.x() - gy * origin.y() - static_cast<float>(ground_.z())) / denom;
    if (t > 0.0f && t < best) {
      best = t;
      found = true;
      hit->range = t;
      hit->material = Material::kGround;
      hit->normal = Eigen::Vector3f(-gx, -gy, 1.0f).normalized();
    }
  }
  // 2D DDA through the grid cells the ray's horizontal projection crosses, nearest first.
  const float fx = (origin.x() - min_x_) / cell_, fy = (origin.y() - min_y_) / cell_;
  int i = static_cast<int>(std::floor(fx)), j = static_cast<int>(std::floor(fy));
  const float dx = direction.x(), dy = direction.y();
  const int step_i = dx > 0 ? 1 : -1, step_j = dy > 0 ? 1 : -1;
  const float inv_dx = std::fabs(dx) > 1e-12f ? 1.0f / std::fabs(dx) : kInf;
  const float inv_dy = std::fabs(dy) > 1e-12f ? 1.0f / std::fabs(dy) : kInf;
  float next_x = (dx > 0 ? (i + 1 - fx) : (fx - i)) * cell_ * inv_dx;
  float next_y = (dy > 0 ? (j + 1 - fy) : (fy - j)) * cell_ * inv_dy;
  const float delta_x = cell_ * inv_dx, delta_y = cell_ * inv_dy;
  float t_enter = 0.0f;
  Hit candidate;
  while (t_enter < best) {
    if (i >= 0 && j >= 0 && i < nx_ && j < ny_) {
      for (std::uint32_t id : cells_[static_cast<std::size_t>(j) * nx_ + i]) {
        if ((*visit)[id] == ray_id) continue;
        (*visit)[id] = ray_id;
        const Primitive& p = primitives_[id];
        if (time < p.present_from || time >= p.present_to) continue;
        if (intersect(p, origin, direction, best, &candidate) && candidate.range < best) {
          best = candidate.range;
          *hit = candidate;
          found = true;
        }
      }
    } else if ((i < 0 && step_i < 0) || (i >= nx_ && step_i > 0) || (j < 0 && step_j < 0) ||
               (j >= ny_ && step_j > 0)) {
      break;  // leaving the grid for good
    }
    if (next_x < next_y) {
      t_enter = next_x;
      next_x += delta_x;
      i += step_i;
    } else {
      t_enter = next_y;
      next_y += delta_y;
      j += step_j;
    }
    if (inv_dx == kInf && inv_dy == kInf) break;  // vertical ray: one cell only
  }
  return found;
}

// ---------------------------------------------------------------------------------------------
// World generation

namespace {

/// Nearest-path-point queries on a hashed grid of the (densified) path.
class PathIndex {
 public:
  PathIndex(const std::vector<PathPoint>& path, double cell) : cell_(cell) {
    for (std::size_t k = 0; k < path.size(); ++k) cells_[key(path[k].x, path[k].y)].push_back(k);
    path_ = &path;
  }
  /// Distance to the nearest path point, searched up to `radius` (returns radius when none is closer).
  double distance(double x, double y, double radius) const {
    double best = radius;
    const int r = static_cast<int>(std::ceil(radius / cell_));
    const int ci = static_cast<int>(std::floor(x / cell_)), cj = static_cast<int>(std::floor(y / cell_));
    for (int i = ci - r; i <= ci + r; ++i) {
      for (int j = cj - r; j <= cj + r; ++j) {
        const auto it = cells_.find(pack(i, j));
        if (it == cells_.end()) continue;
        for (std::size_t k : it->second) {
          best = std::min(best, std::hypot((*path_)[k].x - x, (*path_)[k].y - y));
        }
      }
    }
    return best;
  }

 private:
  static std::int64_t pack(int i, int j) { return (static_cast<std::int64_t>(i) << 32) ^ static_cast<std::uint32_t>(j); }
  std::int64_t key(double x, double y) const {
    return pack(static_cast<int>(std::floor(x / cell_)), static_cast<int>(std::floor(y / cell_)));
  }
  double cell_;
  const std::vector<PathPoint>* path_ = nullptr;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

/// Coarse occupancy of what has been placed, so overlapping objects (from revisits) are skipped.
class Occupancy {
 public:
  explicit Occupancy(double cell) : cell_(cell) {}
  /// Rectangle given by centre, yaw and half extents; `margin` grows it.
  bool free(double cx, double cy, double yaw, double hx, double hy, double margin) const {
    bool ok = true;
    visit(cx, cy, yaw, hx + margin, hy + margin, [&](std::int64_t k) { ok = ok && cells_.count(k) == 0; });
    return ok;
  }
  void mark(double cx, double cy, double yaw, double hx, double hy) {
    visit(cx, cy, yaw, hx, hy, [&](std::int64_t k) { cells_[k] = 1; });
  }

 private:
  template <typename Fn>
  void visit(double cx, double cy, double yaw, double hx, double hy, Fn fn) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (double u = -hx; u <= hx + 1e-9; u += cell_ * 0.5) {
      for (double v = -hy; v <= hy + 1e-9; v += cell_ * 0.5) {
        const double x = cx + c * u - s * v, y = cy + s * u + c * v;
        fn((static_cast<std::int64_t>(std::floor(x / cell_)) << 32) ^
           static_cast<std::uint32_t>(static_cast<int>(std::floor(y / cell_))));
      }
    }
  }
  double cell_;
  std::unordered_map<std::int64_t, char> cells_;
};

std::vector<PathPoint> densify(const std::vector<PathPoint>& path, double spacing) {
  std::vector<PathPoint> out;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const double len = std::hypot(path[k + 1].x - path[k].x, path[k + 1].y - path[k].y);
    const int n = std::max(1, static_cast<int>(len / spacing));
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / n;
      out.push_back({path[k].x + t * (path[k + 1].x - path[k].x), path[k].y + t * (path[k + 1].y - path[k].y),
                     std::atan2(path[k + 1].y - path[k].y, path[k + 1].x - path[k].x)});
    }
  }
  if (!path.empty()) out.push_back(path.back());
  return out;
}

class StreetBuilder {
 public:
  StreetBuilder(const std::vector<PathPoint>& dense, const WorldOptions& options)
      : dense_(dense), options_(options), index_(dense, 4.0), occupied_(1.0), rng_(options.seed) {}

  std::vector<Primitive> build() {
    const double w = options_.road_half_width;
    // Walk the path; each side keeps the arc length up to which it is already furnished.
    double s = 0.0;
    double next_building[2] = {0.0, 0.0}, next_tree[2] = {0.0, 0.0}, next_pole[2] = {0.0, 0.0},
           next_car[2] = {0.0, 0.0}, next_wall[2] = {0.0, 0.0};
    for (std::size_t k = 0; k < dense_.size(); ++k) {
      if (k > 0) s += std::hypot(dense_[k].x - dense_[k - 1].x, dense_[k].y - dense_[k - 1].y);
      const PathPoint& p = dense_[k];
      for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0;  // left, right
        if (s >= next_building[side]) next_building[side] = s + building(p, sign, w);
        if (s >= next_tree[side]) next_tree[side] = s + tree(p, sign, w);
        if (s >= next_pole[side]) next_pole[side] = s + pole(p, sign, w);
        if (s >= next_car[side]) next_car[side] = s + car(p, sign, w);
        if (s >= next_wall[side]) next_wall[side] = s + wall(p, sign, w);
      }
    }
    return std::move(out_);
  }

 private:
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }

  /// Point at lateral offset `lateral` (positive = left) and along-track offset `along` from p.
  Eigen::Vector2d at(const PathPoint& p, double along, double lateral) const {
    const double c = std::cos(p.heading), s = std::sin(p.heading);
    return {p.x + c * along - s * lateral, p.y + s * along + c * lateral};
  }

  /// True when the rectangle keeps `clearance` from every part of the path (no object on any road).
  bool offRoad(const Eigen::Vector2d& c, double yaw, double hx, double hy, double clearance) const {
    const double cs = std::cos(yaw), sn = std::sin(yaw);
    const double radius = clearance + 1.0;
    for (double u : {-hx, 0.0, hx}) {
      for (double v : {-hy, 0.0, hy}) {
        const double x = c.x() + cs * u - sn * v, y = c.y() + sn * u + cs * v;
        if (index_.distance(x, y, radius) < clearance) return false;
      }
    }
    // Long facades: also check along the edges.
    for (double u = -hx; u <= hx; u += 2.0) {
      for (double v : {-hy, hy}) {
        const double x = c.x() + cs * u - sn * v, y = c.y() + sn * u + cs * v;
        if (index_.distance(x, y, radius) < clearance) return false;
      }
    }
    return true;
  }

  bool place(Primitive prim, double hx, double hy, double clearance, double margin) {
    const Eigen::Vector2d c(prim.center.x(), prim.center.y());
    if (!offRoad(c, prim.yaw, hx, hy, clearance)) return false;
    if (!occupied_.free(c.x(), c.y(), prim.yaw, hx, hy, margin)) return false;
    occupied_.mark(c.x(), c.y(), prim.yaw, hx, hy);
    out_.push_back(prim);
    return true;
  }

  double groundAt(const Eigen::Vector2d& c) const {
    return options_.ground_slope * (0.6 * c.x() + 0.8 * c.y());
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

  /// A building (sometimes an L of two blocks); returns the along-track advance.
  double building(const PathPoint& p, double sign, double w) {
    const double length = uniform(8.0, 26.0);
    if (chance(0.18)) return uniform(4.0, 14.0);  // a gap: a yard, a side street, a car park
    const double depth = uniform(8.0, 20.0);
    const double setback = w + uniform(2.5, 5.0);
    // Mostly 2-4 storeys, a few towers.
    const double height = chance(0.15) ? uniform(15.0, 30.0) : uniform(4.0, 14.0);
    const Eigen::Vector2d c = at(p, length / 2, sign * (setback + depth / 2));
    place(box(c, p.heading, length / 2, depth / 2, 0.0, height, Material::kBuilding), length / 2, depth / 2,
          w + 2.0, 0.5);
    if (chance(0.3)) {  // a lower annex behind
      const Eigen::Vector2d a = at(p, uniform(0.0, length), sign * (setback + depth + 4.0));
      place(box(a, p.heading, uniform(3.0, 6.0), 4.0, 0.0, uniform(3.0, 8.0), Material::kBuilding), 6.0, 4.0,
            w + 2.0, 0.2);
    }
    return length + uniform(0.0, 3.0);
  }

  double tree(const PathPoint& p, double sign, double w) {
    if (chance(0.5)) return uniform(6.0, 20.0);
    const Eigen::Vector2d c = at(p, 0.0, sign * (w + uniform(1.2, 2.0)));
    const double g = groundAt(c);
    const double trunk_h = uniform(1.8, 3.5);
    Primitive trunk;
    trunk.kind = Primitive::Kind::kCylinder;
    trunk.material = Material::kTrunk;
    trunk.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()), 0.0f);
    trunk.half = Eigen::Vector3f::Constant(static_cast<float>(uniform(0.12, 0.3)));
    trunk.z0 = static_cast<float>(g);
    trunk.z1 = static_cast<float>(g + trunk_h + 0.5);
    if (!place(trunk, 0.4, 0.4, w + 0.8, 0.5)) return 3.0;
    Primitive canopy;
    canopy.kind = Primitive::Kind::kEllipsoid;
    canopy.material = Material::kFoliage;
    const double r = uniform(1.5, 3.2), rz = uniform(1.5, 3.0);
    canopy.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()),
                                    static_cast<float>(g + trunk_h + rz));
    canopy.half = Eigen::Vector3f(static_cast<float>(r), static_cast<float>(r), static_cast<float>(rz));
    out_.push_back(canopy);
    if (chance(0.3)) {  // a bush by the facade
      Primitive bush;
      bush.kind = Primitive::Kind::kEllipsoid;
      bush.material = Material::kFoliage;
      const Eigen::Vector2d b = at(p, uniform(-3.0, 3.0), sign * (w + uniform(2.5, 3.5)));
      const double br = uniform(0.5, 1.2);
      bush.center = Eigen::Vector3f(static_cast<float>(b.x()), static_cast<float>(b.y()),
                                    static_cast<float>(groundAt(b) + 0.4 * br));
      bush.half = Eigen::Vector3f(static_cast<float>(br), static_cast<float>(br), static_cast<float>(0.8 * br));
      if (offRoad(b, 0.0, br, br, w + 0.5)) out_.push_back(bush);
    }
    return uniform(7.0, 15.0);
  }

  double pole(const PathPoint& p, double sign, double w) {
    const Eigen::Vector2d c = at(p, 0.0, sign * (w + 0.7));
    const double g = groundAt(c);
    Primitive pole;
    pole.kind = Primitive::Kind::kCylinder;
    pole.material = Material::kPole;
    pole.center = Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y()), 0.0f);
    pole.half = Eigen::Vector3f::Constant(static_cast<float>(uniform(0.08, 0.15)));
    pole.z0 = static_cast<float>(g);
    pole.z1 = static_cast<float>(g + uniform(4.5, 9.0));
    place(pole, 0.2, 0.2, w + 0.4, 0.3);
    return uniform(18.0, 40.0);
  }

  double car(const PathPoint& p, double sign, double w) {
    if (chance(0.35)) return uniform(3.0, 12.0);
    const double length = uniform(3.8, 5.0), width = uniform(1.7, 1.95);
    const Eigen::Vector2d c = at(p, length / 2, sign * (w - 1.2));
    const double yaw = p.heading + uniform(-0.05, 0.05);
    Primitive body = box(c, yaw, length / 2, width / 2, 0.25, 1.0, Material::kCar);
    Primitive cabin = box(at(p, length / 2 - 0.2, sign * (w - 1.2)), yaw, length * 0.3, width / 2 - 0.1, 1.0,
                          uniform(1.4, 1.7), Material::kCar);
    if (chance(options_.dynamic_car_fraction) && options_.duration > 0.0) {
      // Parked for a while: revisits find it there or gone.
      const double start = uniform(-0.3, 1.0) * options_.duration;
      const double stay = uniform(0.1, 0.5) * options_.duration;
      body.present_from = cabin.present_from = start;
      body.present_to = cabin.present_to = start + stay;
    }
    // Parked cars stand on the road's edge: only the other roads must stay clear.
    if (place(body, length / 2, width / 2, w - 2.3, 0.3)) out_.push_back(cabin);
    return length + uniform(0.8, 6.0);
  }

  double wall(const PathPoint& p, double sign, double w) {
    if (chance(0.8)) return uniform(10.0, 30.0);
    const double length = uniform(6.0, 20.0);
    const double height = chance(0.5) ? uniform(0.9, 1.5) : uniform(1.8, 2.8);  // fence or wall
    const Eigen::Vector2d c = at(p, length / 2, sign * (w + uniform(2.2, 2.8)));
    place(box(c, p.heading, length / 2, 0.15, 0.0, height, Material::kWall), length / 2, 0.15, w + 1.5, 0.1);
    return length + uniform(5.0, 20.0);
  }

  const std::vector<PathPoint>& dense_;
  WorldOptions options_;
  PathIndex index_;
  Occupancy occupied_;
  std::mt19937 rng_;
  std::vector<Primitive> out_;
};

}  // namespace

World generateWorld(const std::vector<PathPoint>& path, const WorldOptions& options) {
  const std::vector<PathPoint> dense = densify(path, 1.0);
  StreetBuilder builder(dense, options);
  std::vector<Primitive> primitives = builder.build();
  const Eigen::Vector3d ground(options.ground_slope * 0.6, options.ground_slope * 0.8, 0.0);
  return World(std::move(primitives), ground);
}

}  // namespace sim
}  // namespace scan_context_loop
