#include "scan_context_sim/world.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

/// A repeatable number in [0, 1) for one ray and one solid (where in a canopy that ray returns).
float scatterOf(std::uint32_t ray_id, std::uint32_t solid) {
  std::uint64_t z = (static_cast<std::uint64_t>(ray_id) << 32 | solid) + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<float>(z >> 40) * (1.0f / 16777216.0f);
}

/// A porous solid entered at t_in and left at t_out returns the ray from somewhere in between, or not
/// at all. Returns the range of the return, or a negative number when the ray passes through.
float scatterDepth(const Primitive& p, float t_in, float t_out, float scatter) {
  if (p.free_path <= 0.0f) return t_in;
  const float t = t_in - p.free_path * std::log1p(-scatter);
  return t <= t_out ? t : -1.0f;
}

/// The ray/box test with the box's yaw already as cosine c and sine s.
bool intersectBox(const Primitive& p, float c, float s, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max,
                  float scatter, Hit* hit) {
  // Into the box frame: centred, x along the yaw.
  const float ox = o.x() - p.center.x(), oy = o.y() - p.center.y();
  const Eigen::Vector3f lo(c * ox + s * oy, -s * ox + c * oy, o.z() - 0.5f * (p.z0 + p.z1));
  const Eigen::Vector3f ld(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
  const Eigen::Vector3f half(p.half.x(), p.half.y(), 0.5f * (p.z1 - p.z0));
  float t0 = 0.0f, t1 = kInf;
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
    if (t0 > t1 || t0 > t_max) return false;
  }
  if (axis < 0 || t0 <= 0.0f) return false;  // starting inside a solid: no return
  const float t = scatterDepth(p, t0, t1, scatter);
  if (t <= 0.0f || t > t_max) return false;
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  n[axis] = ld[axis] > 0 ? -1.0f : 1.0f;
  hit->range = t;
  hit->width = 0.0f;
  hit->normal = Eigen::Vector3f(c * n.x() - s * n.y(), s * n.x() + c * n.y(), n.z());
  hit->material = p.material;
  return true;
}

bool intersectCylinder(const Primitive& p, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, Hit* hit) {
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
  hit->width = 2.0f * p.half.x();
  hit->normal = Eigen::Vector3f(ox + t * d.x(), oy + t * d.y(), 0.0f).normalized();
  hit->material = p.material;
  return true;
}

bool intersectEllipsoid(const Primitive& p, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max,
                        float scatter, Hit* hit) {
  const Eigen::Vector3f so = (o - p.center).cwiseQuotient(p.half);
  const Eigen::Vector3f sd = d.cwiseQuotient(p.half);
  const float a = sd.squaredNorm(), b = so.dot(sd), cc = so.squaredNorm() - 1.0f;
  const float disc = b * b - a * cc;
  if (disc < 0.0f) return false;
  const float root = std::sqrt(disc);
  const float t_in = (-b - root) / a;
  if (t_in <= 0.0f || t_in > t_max) return false;
  const float t = scatterDepth(p, t_in, (-b + root) / a, scatter);
  if (t <= 0.0f || t > t_max) return false;
  hit->range = t;
  hit->width = 0.0f;
  hit->normal = (so + t_in * sd).cwiseQuotient(p.half).normalized();
  hit->material = p.material;
  return true;
}

}  // namespace

bool intersect(const Primitive& p, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_max,
               float scatter, Hit* hit) {
  switch (p.kind) {
    case Primitive::Kind::kBox:
      return intersectBox(p, std::cos(p.yaw), std::sin(p.yaw), origin, direction, t_max, scatter, hit);
    case Primitive::Kind::kCylinder:
      return intersectCylinder(p, origin, direction, t_max, hit);
    case Primitive::Kind::kEllipsoid:
      return intersectEllipsoid(p, origin, direction, t_max, scatter, hit);
  }
  return false;
}

World::World(std::vector<Primitive> primitives, const Eigen::Vector3d& ground, float cell_size)
    : primitives_(std::move(primitives)), ground_(ground), cell_(cell_size) {
  float x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  yaw_axes_.reserve(primitives_.size());
  for (const auto& p : primitives_) {
    float a, b, c, d;
    footprint(p, &a, &b, &c, &d);
    x0 = std::min(x0, a);
    y0 = std::min(y0, b);
    x1 = std::max(x1, c);
    y1 = std::max(y1, d);
    yaw_axes_.emplace_back(std::cos(p.yaw), std::sin(p.yaw));
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
      hit->width = 0.0f;
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
        const float scatter = p.free_path > 0.0f ? scatterOf(ray_id, id) : 0.0f;
        const bool hit_it =
            p.kind == Primitive::Kind::kBox
                ? intersectBox(p, yaw_axes_[id].x(), yaw_axes_[id].y(), origin, direction, best, scatter, &candidate)
                : intersect(p, origin, direction, best, scatter, &candidate);
        if (hit_it && candidate.range < best) {
          best = candidate.range;
          *hit = candidate;
          found = true;
        }
      }
    } else if ((i < 0 && step_i < 0) || (i >= nx_ && step_i > 0) || (j < 0 && step_j < 0) || (j >= ny_ && step_j > 0)) {
      break;  // leaving the grid for good
    }
    if (inv_dx == kInf && inv_dy == kInf) break;  // vertical ray: one cell only
    if (next_x < next_y) {
      t_enter = next_x;
      next_x += delta_x;
      i += step_i;
    } else {
      t_enter = next_y;
      next_y += delta_y;
      j += step_j;
    }
  }
  return found;
}

}  // namespace sim
}  // namespace scan_context_loop
