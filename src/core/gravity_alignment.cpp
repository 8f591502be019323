#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/gravity_alignment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace scan_context_loop {

namespace {

constexpr double kRadPerDeg = M_PI / 180.0;

/// Point i of the view; false when any coordinate is NaN or Inf.
inline bool readPoint(const PointView& view, std::size_t i, Eigen::Vector3f* p) {
  const std::uint8_t* base = view.data + i * view.stride;
  float xyz[3];
  std::memcpy(&xyz[0], base + view.offset_x, sizeof(float));
  std::memcpy(&xyz[1], base + view.offset_y, sizeof(float));
  std::memcpy(&xyz[2], base + view.offset_z, sizeof(float));
  *p = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
  return p->allFinite();
}

/// normal . p + offset = 0, normal of unit length pointing to the sensor's side, so `offset` is the
/// sensor's (the origin's) height above the plane.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
};

/// What a ground plane must satisfy, from the options.
struct PlaneLimits {
  double min_cos_tilt, min_height, max_height;

  /// Orients `plane` upwards (towards the sensor's +z) and says whether it is admissible.
  bool admit(Plane* plane) const {
    if (plane->normal.z() < 0.0) {
      plane->normal = -plane->normal;
      plane->offset = -plane->offset;
    }
    return plane->normal.z() >= min_cos_tilt && plane->offset >= min_height && plane->offset <= max_height;
  }
};

std::string invalidOptions(const GroundFitOptions& o) {
  if (!(o.min_range >= 0.0 && o.max_range > o.min_range)) return "need 0 <= min_range < max_range";
  if (!(o.ground_plane_max_tilt_deg > 0.0 && o.ground_plane_max_tilt_deg < 90.0)) {
    return "need ground_plane_max_tilt_deg in (0, 90)";
  }
  if (!(o.min_height >= 0.0 && o.max_height > o.min_height)) return "need 0 <= min_height < max_height";
  if (!(o.inlier_distance > 0.0)) return "need inlier_distance > 0";
  if (o.max_points < 3) return "need max_points >= 3";
  if (o.iterations < 1) return "need iterations >= 1";
  if (!(o.min_inlier_ratio >= 0.0 && o.min_inlier_ratio <= 1.0)) return "need min_inlier_ratio in [0, 1]";
  if (!(o.max_below_ratio >= 0.0)) return "need max_below_ratio >= 0";
  return "";
}

/// Up to options.max_points points, evenly spaced in the cloud's order, that could lie on an
/// admissible ground plane: in the range band, and no higher than the steepest admissible plane
/// through the band allows (a point at horizontal range r on a plane tilted by t, h below the sensor,
/// has z <= r tan t - h / cos t, plus the inlier distance for noise).
std::vector<Eigen::Vector3f> candidatePoints(const PointView& points, const GroundFitOptions& o) {
  std::vector<Eigen::Vector3f> kept;
  if (points.data == nullptr || points.count == 0) return kept;
  const std::size_t stride = (points.count + o.max_points - 1) / o.max_points;
  const float min2 = static_cast<float>(o.min_range * o.min_range);
  const float max2 = static_cast<float>(o.max_range * o.max_range);
  const double tilt = o.ground_plane_max_tilt_deg * kRadPerDeg;
  const float slope = static_cast<float>(std::tan(tilt));
  const float lift = static_cast<float>(o.inlier_distance / std::cos(tilt) - o.min_height);
  kept.reserve(o.max_points);
  Eigen::Vector3f p;
  for (std::size_t i = 0; i < points.count; i += stride) {
    if (!readPoint(points, i, &p)) continue;
    const float r2 = p.x() * p.x() + p.y() * p.y();
    if (r2 < min2 || r2 > max2) continue;
    if (p.z() > std::sqrt(r2) * slope + lift) continue;
    kept.push_back(p);
  }
  return kept;
}

std::size_t countInliers(const std::vector<Eigen::Vector3f>& pts, const Plane& plane, float threshold) {
  const Eigen::Vector3f n = plane.normal.cast<float>();
  const float d = static_cast<float>(plane.offset);
  std::size_t count = 0;
  for (const auto& p : pts) count += std::fabs(n.dot(p) + d) <= threshold;
  return count;
}

/// Fills fit->inliers, fit->rms and fit->below for `plane`.
void describeSupport(const std::vector<Eigen::Vector3f>& pts, const Plane& plane, float threshold, GroundFit* fit) {
  const Eigen::Vector3f n = plane.normal.cast<float>();
  const float d = static_cast<float>(plane.offset);
  std::size_t inliers = 0, below = 0;
  double sum2 = 0.0;
  for (const auto& p : pts) {
    const float r = n.dot(p) + d;
    if (std::fabs(r) <= threshold) {
      ++inliers;
      sum2 += static_cast<double>(r) * r;
    } else if (r < -2.0f * threshold) {
      ++below;
    }
  }
  fit->inliers = inliers;
  fit->below = below;
  fit->rms = inliers > 0 ? std::sqrt(sum2 / static_cast<double>(inliers)) : 0.0;
}

/// Plane through three points; false when they are (nearly) collinear.
bool planeThrough(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c, Plane* plane) {
  const Eigen::Vector3d n = (b - a).cross(c - a).cast<double>();
  const double norm = n.norm();
  if (norm < 1e-6) return false;
  plane->normal = n / norm;
  plane->offset = -plane->normal.dot(a.cast<double>());
  return true;
}

/// Least-squares plane (smallest principal axis through the centroid) of the points within
/// `threshold` of `plane`; false when fewer than three are.
bool refit(const std::vector<Eigen::Vector3f>& pts, float threshold, Plane* plane) {
  const Eigen::Vector3f n = plane->normal.cast<float>();
  const float d = static_cast<float>(plane->offset);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  std::size_t count = 0;
  for (const auto& p : pts) {
    if (std::fabs(n.dot(p) + d) > threshold) continue;
    const Eigen::Vector3d q = p.cast<double>();
    sum += q;
    outer += q * q.transpose();
    ++count;
  }
  if (count < 3) return false;
  const Eigen::Vector3d centroid = sum / static_cast<double>(count);
  const Eigen::Matrix3d covariance = outer / static_cast<double>(count) - centroid * centroid.transpose();
  // Eigenvalues come in increasing order: column 0 is the normal.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
  plane->normal = eig.eigenvectors().col(0).normalized();
  plane->offset = -plane->normal.dot(centroid);
  return true;
}

/// printf into a std::string, for the failure reasons.
template <typename... Args>
std::string formatted(const char* format, Args... args) {
  char text[200];
  std::snprintf(text, sizeof text, format, args...);
  return text;
}

std::string describeLimits(const GroundFitOptions& o) {
  return formatted("%.3g-%.3g m below the sensor and within %.3g degrees of level", o.min_height, o.max_height,
                   o.ground_plane_max_tilt_deg);
}

}  // namespace

Eigen::Matrix3d gravityAlignmentFromUp(const Eigen::Vector3d& up) {
  const double length = up.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d z = up / length;
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  Eigen::Vector3d y;
  if (x.norm() > 1e-9) {
    x.normalize();
    y = z.cross(x);
  } else {
    y = (Eigen::Vector3d::UnitY() - z.y() * z).normalized();
    x = y.cross(z);
  }
  Eigen::Matrix3d L_R_sensor;
  L_R_sensor.row(0) = x.transpose();
  L_R_sensor.row(1) = y.transpose();
  L_R_sensor.row(2) = z.transpose();
  return L_R_sensor;
}

Eigen::Matrix3d gravityAlignmentFromOrientation(const Eigen::Matrix3d& world_R_sensor) {
  // World up seen from the sensor is the world's z row of world_R_sensor. Built from it, the result
  // equals Rz(-psi) * world_R_sensor and stays a rotation even when world_R_sensor has drifted a little
  // from orthonormal.
  return gravityAlignmentFromUp(world_R_sensor.row(2).transpose());
}

bool gravityAlignmentFromGround(const PointView& points, const GroundFitOptions& options, Eigen::Matrix3d* L_R_sensor,
                                GroundFit* fit) {
  GroundFit result;
  const auto fail = [&](std::string reason) {
    result.reason = std::move(reason);
    if (fit != nullptr) *fit = result;
    return false;
  };
  const std::string invalid = invalidOptions(options);
  if (!invalid.empty()) return fail("invalid ground fit options: " + invalid);

  const std::vector<Eigen::Vector3f> pts = candidatePoints(points, options);
  result.considered = pts.size();
  const auto ratio_needed = static_cast<std::size_t>(std::ceil(options.min_inlier_ratio * pts.size()));
  const std::size_t needed = std::max<std::size_t>({options.min_inliers, ratio_needed, 3});
  const PlaneLimits limits{std::cos(options.ground_plane_max_tilt_deg * kRadPerDeg), options.min_height,
                           options.max_height};
  const float threshold = static_cast<float>(options.inlier_distance);
  if (pts.size() < needed) {
    return fail(formatted("too few points could be ground: %zu sampled in the %.3g-%.3g m range band, need %zu",
                          pts.size(), options.min_range, options.max_range, needed));
  }

  // RANSAC. Indices come from a fixed-seed engine reduced with %, not a distribution, so that the
  // sample (and the fit) is the same with every standard library.
  std::mt19937 rng(options.seed);
  const auto pick = [&] { return static_cast<std::size_t>(rng() % pts.size()); };
  Plane best;
  std::size_t best_count = 0;
  for (int it = 0; it < options.iterations; ++it) {
    const std::size_t i = pick(), j = pick(), k = pick();
    Plane plane;
    if (i == j || j == k || i == k || !planeThrough(pts[i], pts[j], pts[k], &plane) || !limits.admit(&plane)) continue;
    const std::size_t count = countInliers(pts, plane, threshold);
    if (count > best_count) {
      best_count = count;
      best = plane;
    }
  }
  if (best_count == 0) return fail("no plane " + describeLimits(options));

  // Two least-squares rounds: the first moves the plane from three points to all of its inliers,
  // the second re-selects the inliers around that better plane.
  for (int round = 0; round < 2; ++round) {
    if (!refit(pts, threshold, &best)) break;
    if (!limits.admit(&best)) return fail("the refined plane is not " + describeLimits(options));
  }
  result.normal = best.normal;
  result.height = best.offset;
  result.tilt_deg = std::acos(std::min(1.0, best.normal.z())) / kRadPerDeg;
  describeSupport(pts, best, threshold, &result);
  if (result.inliers < needed) {
    return fail(formatted("too few ground points: %zu of %zu sampled lie on the best plane, need %zu", result.inliers,
                          pts.size(), needed));
  }
  if (static_cast<double>(result.below) > options.max_below_ratio * static_cast<double>(result.inliers)) {
    return fail(
        formatted("not the ground: %zu sampled points lie below the plane, %zu on it", result.below, result.inliers));
  }
  if (L_R_sensor != nullptr) *L_R_sensor = gravityAlignmentFromUp(result.normal);
  if (fit != nullptr) *fit = result;
  return true;
}

pcl::PointCloud<pcl::PointXYZ> rotatedCloud(const PointView& points, const Eigen::Matrix3f& R) {
  return transformedCloud(points, Eigen::Affine3f(R));
}

pcl::PointCloud<pcl::PointXYZ> transformedCloud(const PointView& points, const Eigen::Affine3f& transform) {
  pcl::PointCloud<pcl::PointXYZ> out;
  if (points.data == nullptr) return out;
  out.reserve(points.count);
  Eigen::Vector3f p;
  for (std::size_t i = 0; i < points.count; ++i) {
    if (!readPoint(points, i, &p)) continue;
    const Eigen::Vector3f q = transform * p;
    out.push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  return out;
}

}  // namespace scan_context_loop
