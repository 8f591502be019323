#include "scan_context_loop/core/registration.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "grid_cell.h"
#include "point_gather.h"
#include "principal_axes.h"
#include "simd_clones.h"

namespace scan_context_loop {

namespace {

/// Running sums of one voxel's points, relative to the voxel's corner for precision; one cache line.
struct alignas(64) Accumulator {
  int count = 0;
  float sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  Eigen::Vector3f corner = Eigen::Vector3f::Zero();
};

/// Per-thread scratch: a dense grid of accumulator indices stamped with a generation.
struct Scratch {
  /// A cell's stamp and accumulator side by side: one cache line per point, not two.
  struct Cell {
    std::uint32_t stamp = 0;
    std::int32_t slot = -1;
  };
  std::vector<Cell> cells;
  std::vector<Accumulator> acc;
  std::uint32_t generation = 0;
};

/// The grid's cells across (x and y) and up (z), as floats: makeVoxelCloud sizes its grid with them and
/// maxVoxels bounds a cloud by them, so both count alike.
float cellsAcross(const VoxelOptions& options) {
  return std::ceil(2.0f * options.max_range * (1.0f / options.resolution)) + 1.0f;
}
float cellsUp(const VoxelOptions& options) {
  return std::ceil((options.max_z - options.min_z) * (1.0f / options.resolution)) + 1.0f;
}

std::int8_t quantise(float v) { return static_cast<std::int8_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 127.0f)); }

Eigen::Matrix3f skew(const Eigen::Vector3f& v) {
  Eigen::Matrix3f m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// The crop and cells of makeVoxelCloud's grid, for locateBlock.
struct VoxelGrid {
  float r2, max_range, min_z, max_z, inv_resolution;
  int nxy, nz;
  std::optional<Eigen::Matrix<float, 3, 3, Eigen::RowMajor>> rotation;  ///< applied to every point first
};

constexpr std::size_t kVoxelBlock = 256;

/// A block of points, turned, with the grid cell each falls into (-1: outside the crop, or not finite).
struct VoxelBlock {
  float x[kVoxelBlock], y[kVoxelBlock], z[kVoxelBlock];
  std::int32_t cell[kVoxelBlock];
};

/// Reads n points (every stride-th from `first`), turns them and finds their cells, without branches so
/// that the compiler vectorises it: the accumulation that follows is left with the scattered sums only.
SCL_CLONES void locateBlock(const PointView& points, std::size_t first, std::size_t stride, std::size_t n,
                            const VoxelGrid& g, VoxelBlock* b) {
  gatherXyz(points, points.data + first * points.stride, stride * points.stride, n, b->x, b->y, b->z);
  if (g.rotation) {
    const float* R = g.rotation->data();
    for (std::size_t i = 0; i < n; ++i) {
      const float x = b->x[i], y = b->y[i], z = b->z[i];
      b->x[i] = R[0] * x + R[1] * y + R[2] * z;
      b->y[i] = R[3] * x + R[4] * y + R[5] * z;
      b->z[i] = R[6] * x + R[7] * y + R[8] * z;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const float x = b->x[i], y = b->y[i], z = b->z[i];
    // NaN fails every comparison; Inf fails the range or the height bounds.
    const bool inside = (x * x + y * y <= g.r2) & (z >= g.min_z) & (z < g.max_z);
    const int ix = static_cast<int>(((inside ? x : 0.0f) + g.max_range) * g.inv_resolution);
    const int iy = static_cast<int>(((inside ? y : 0.0f) + g.max_range) * g.inv_resolution);
    const int iz = static_cast<int>(((inside ? z : g.min_z) - g.min_z) * g.inv_resolution);
    const bool in_grid = inside & (ix >= 0) & (iy >= 0) & (iz >= 0) & (ix < g.nxy) & (iy < g.nxy) & (iz < g.nz);
    b->cell[i] = in_grid ? (iz * g.nxy + iy) * g.nxy + ix : -1;
  }
}

}  // namespace

VoxelCloud makeVoxelCloud(const PointView& points, const VoxelOptions& options, const Eigen::Matrix3f& rotation) {
  VoxelCloud out;
  out.resolution = options.resolution;
  out.max_range = options.max_range;
  if (points.data == nullptr || points.count == 0 || !(options.resolution > 0.0f)) return out;
  const float inv = 1.0f / options.resolution;
  const int nxy = static_cast<int>(cellsAcross(options));
  const int nz = static_cast<int>(cellsUp(options));
  const std::size_t cells = static_cast<std::size_t>(nxy) * nxy * nz;
  thread_local Scratch s;
  if (s.cells.size() != cells) {
    s.cells.assign(cells, Scratch::Cell());
    s.generation = 0;
  }
  if (++s.generation == 0) {  // wrapped: clear once every 4 billion clouds
    std::fill(s.cells.begin(), s.cells.end(), Scratch::Cell());
    s.generation = 1;
  }
  s.acc.clear();
  VoxelGrid grid{
      options.max_range * options.max_range, options.max_range, options.min_z, options.max_z, inv, nxy, nz, {}};
  if (!rotation.isIdentity()) grid.rotation = rotation;
  const std::size_t stride = std::max<std::size_t>(1, (points.count + kVoxelCloudMaxPoints - 1) / kVoxelCloudMaxPoints);
  VoxelBlock block;
  for (std::size_t first = 0; first < points.count; first += kVoxelBlock * stride) {
    const std::size_t n = std::min(kVoxelBlock, (points.count - first + stride - 1) / stride);
    locateBlock(points, first, stride, n, grid, &block);
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t c = block.cell[i];
      if (c < 0) continue;
      Scratch::Cell& cell = s.cells[static_cast<std::size_t>(c)];
      if (cell.stamp != s.generation) {
        cell = {s.generation, static_cast<std::int32_t>(s.acc.size())};
        const int iz = c / (nxy * nxy), iy = (c / nxy) % nxy, ix = c % nxy;
        Accumulator a;
        a.corner =
            Eigen::Vector3f(ix * options.resolution - options.max_range, iy * options.resolution - options.max_range,
                            iz * options.resolution + options.min_z);
        s.acc.push_back(a);
      }
      Accumulator& a = s.acc[cell.slot];
      // Relative to the voxel's corner (under a metre), so float sums keep their precision.
      const float x = block.x[i] - a.corner.x(), y = block.y[i] - a.corner.y(), z = block.z[i] - a.corner.z();
      ++a.count;
      a.sx += x;
      a.sy += y;
      a.sz += z;
      a.sxx += x * x;
      a.sxy += x * y;
      a.sxz += x * z;
      a.syy += y * y;
      a.syz += y * z;
      a.szz += z * z;
    }
  }
  // Exactly the voxels that have enough points: the cloud store keeps these arrays for the keyframe's
  // life and budgets them by their size, so no capacity may sit unused behind them (reserving one slot
  // per accumulated voxel left about half again as much allocated on 0.4 m-voxel keyframes).
  std::size_t kept = 0;
  for (const Accumulator& a : s.acc) kept += a.count >= options.min_points;
  out.means.reserve(kept);
  out.normals.reserve(kept);
  // The voxels' shapes a block at a time: their covariances (in double from the float sums, as the
  // sums are relative to the corner), then their principal axes, vectorised.
  thread_local SymmetricBlock cov;
  thread_local AxesBlock axes;
  std::size_t next = 0;
  while (next < s.acc.size()) {
    const Accumulator* block[kAxesBlock];
    std::size_t n = 0;
    for (; next < s.acc.size() && n < kAxesBlock; ++next) {
      const Accumulator& a = s.acc[next];
      if (a.count < options.min_points) continue;
      const double inv_n = 1.0 / a.count;
      const double mx = a.sx * inv_n, my = a.sy * inv_n, mz = a.sz * inv_n;
      cov.xx[n] = static_cast<float>(a.sxx * inv_n - mx * mx);
      cov.xy[n] = static_cast<float>(a.sxy * inv_n - mx * my);
      cov.xz[n] = static_cast<float>(a.sxz * inv_n - mx * mz);
      cov.yy[n] = static_cast<float>(a.syy * inv_n - my * my);
      cov.yz[n] = static_cast<float>(a.syz * inv_n - my * mz);
      cov.zz[n] = static_cast<float>(a.szz * inv_n - mz * mz);
      block[n++] = &a;
    }
    principalAxes(cov, n, &axes);
    for (std::size_t i = 0; i < n; ++i) {
      const Accumulator& a = *block[i];
      Eigen::Vector3f normal(axes.nx[i], axes.ny[i], axes.nz[i]);
      if (!normal.allFinite()) continue;
      const double inv_n = 1.0 / a.count;
      const Eigen::Vector3f mean = a.corner + Eigen::Vector3d(a.sx * inv_n, a.sy * inv_n, a.sz * inv_n).cast<float>();
      if (normal.dot(-mean) < 0.0f) normal = -normal;  // towards the sensor
      const float l0 = std::max(axes.l0[i], 0.0f), l1 = std::max(axes.l1[i], 0.0f), l2 = std::max(axes.l2[i], 0.0f);
      VoxelCloud::Shape shape = VoxelCloud::kScatter;
      if (l1 < 0.1f * l2) {
        shape = std::fabs(axes.major_z[i]) > 0.85f ? VoxelCloud::kVerticalLine : VoxelCloud::kHorizontalLine;
      } else if (l0 < 0.25f * l1) {
        shape = VoxelCloud::kPlanar;
      }
      out.means.push_back(mean);
      out.normals.push_back(
          {quantise(normal.x()), quantise(normal.y()), quantise(normal.z()), static_cast<std::int8_t>(shape)});
    }
  }
  return out;
}

std::size_t maxVoxels(const VoxelOptions& options) {
  if (!(options.resolution > 0.0f) || !(options.max_range > 0.0f)) return 0;
  const double across = cellsAcross(options), up = cellsUp(options);
  // In double: a tiny resolution makes the product overflow what an integer holds.
  return static_cast<std::size_t>(std::min(across * across * up, static_cast<double>(kVoxelCloudMaxPoints)));
}

void VoxelIndex::build(const VoxelCloud& cloud) {
  cloud_ = &cloud;
  inv_res_ = 1.0f / cloud.resolution;
  min_xy_ = -cloud.max_range - cloud.resolution;
  min_z_ = -12.0f;
  nx_ = static_cast<int>(std::ceil(2.0f * (cloud.max_range + cloud.resolution) * inv_res_)) + 1;
  nz_ = static_cast<int>(std::ceil(40.0f * inv_res_)) + 1;
  const std::size_t cells = static_cast<std::size_t>(nx_) * nx_ * nz_;
  if (slots_.size() != cells) {
    slots_.assign(cells, -1);
  } else {
    for (const std::int32_t c : filled_) slots_[c] = -1;
  }
  filled_.clear();
  filled_.reserve(cloud.size());  // before any cell is set: a throw here leaves the grid empty
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& m = cloud.means[i];
    const int ix = gridCell((m.x() - min_xy_) * inv_res_);
    const int iy = gridCell((m.y() - min_xy_) * inv_res_);
    const int iz = gridCell((m.z() - min_z_) * inv_res_);
    const int c = cell(ix, iy, iz);
    if (c < 0) continue;
    if (slots_[c] < 0) filled_.push_back(c);
    slots_[c] = static_cast<std::int32_t>(i);
  }
}

int VoxelIndex::at(const Eigen::Vector3f& p) const {
  if (cloud_ == nullptr) return -1;
  const int c = cell(gridCell((p.x() - min_xy_) * inv_res_), gridCell((p.y() - min_xy_) * inv_res_),
                     gridCell((p.z() - min_z_) * inv_res_));
  return voxelIn(c);
}

int VoxelIndex::nearest(const Eigen::Vector3f& p, float max_distance) const {
  if (cloud_ == nullptr) return -1;
  static const int kOffsets[7][3] = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int ix = gridCell((p.x() - min_xy_) * inv_res_);
  const int iy = gridCell((p.y() - min_xy_) * inv_res_);
  const int iz = gridCell((p.z() - min_z_) * inv_res_);
  int best = -1;
  float best2 = max_distance * max_distance;
  for (const auto& o : kOffsets) {
    const int i = voxelIn(cell(ix + o[0], iy + o[1], iz + o[2]));
    if (i < 0) continue;
    const float d2 = (cloud_->means[i] - p).squaredNorm();
    if (d2 < best2) {
      best2 = d2;
      best = i;
    }
  }
  return best;
}

bool VoxelIndex::onPlane(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float plane, float along, float up) const {
  if (cloud_ == nullptr) return false;
  const int ix = gridCell((p.x() - min_xy_) * inv_res_);
  const int iy = gridCell((p.y() - min_xy_) * inv_res_);
  const int iz = gridCell((p.z() - min_z_) * inv_res_);
  const int reach_xy = static_cast<int>(std::ceil(along * inv_res_));
  const int reach_z = static_cast<int>(std::ceil(up * inv_res_));
  const bool pole = n.squaredNorm() < 0.25f;
  const float along2 = along * along, plane2 = plane * plane;
  // Nearest layers and cells first: the same facade is most often found at the voxel's own height.
  for (int step_z = 0; step_z <= 2 * reach_z; ++step_z) {
    const int dz = (step_z + 1) / 2 * (step_z % 2 == 0 ? 1 : -1);
    for (int step_y = 0; step_y <= 2 * reach_xy; ++step_y) {
      const int dy = (step_y + 1) / 2 * (step_y % 2 == 0 ? 1 : -1);
      for (int step_x = 0; step_x <= 2 * reach_xy; ++step_x) {
        const int dx = (step_x + 1) / 2 * (step_x % 2 == 0 ? 1 : -1);
        const int i = voxelIn(cell(ix + dx, iy + dy, iz + dz));
        if (i < 0) continue;
        if (cloud_->shape(i) == VoxelCloud::kScatter) continue;
        const Eigen::Vector3f d = cloud_->means[i] - p;
        if (std::fabs(d.z()) > up) continue;
        const float h2 = d.x() * d.x() + d.y() * d.y();
        if (pole) {
          if (h2 <= plane2) return true;
          continue;
        }
        const float across = n.x() * d.x() + n.y() * d.y();
        if (std::fabs(across) <= plane && h2 - across * across <= along2) return true;
      }
    }
  }
  return false;
}

std::vector<int> sampleVoxels(const VoxelCloud& cloud, int max_count) {
  std::vector<int> picked, rest;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.registrable(i)) (cloud.vertical(i) ? picked : rest).push_back(static_cast<int>(i));
  }
  if (static_cast<int>(picked.size()) > max_count) {
    // Even stride over the vertical ones alone.
    std::vector<int> thinned;
    const double step = static_cast<double>(picked.size()) / max_count;
    for (int k = 0; k < max_count; ++k) thinned.push_back(picked[static_cast<std::size_t>(k * step)]);
    return thinned;
  }
  const int room = max_count - static_cast<int>(picked.size());
  if (!rest.empty() && room > 0) {
    const double step = std::max(1.0, static_cast<double>(rest.size()) / room);
    for (double k = 0; k < rest.size() && static_cast<int>(picked.size()) < max_count; k += step) {
      picked.push_back(rest[static_cast<std::size_t>(k)]);
    }
  }
  return picked;
}

/// Correspondences whose Hessian and gradient terms are summed in float before joining the double sums.
constexpr int kGicpBlock = 32;

GicpResult alignVoxels(const VoxelCloud& source, const VoxelIndex& target, const Eigen::Isometry3d& initial,
                       const GicpOptions& options) {
  GicpResult result;
  result.transform = initial;
  const VoxelCloud* tc = target.cloud();
  if (tc == nullptr || source.empty() || tc->empty()) return result;
  const std::vector<int> sample = sampleVoxels(source, options.max_source_voxels);
  // The GICP covariance of a pair is the sum of two plane models, I - a n n^T each (a = 1 - epsilon):
  // 2 I - a (n_t n_t^T + (R n_s)(R n_s)^T), formed from the turned source normal instead of turning a
  // matrix per correspondence.
  const float a = 1.0f - options.plane_epsilon;
  std::vector<Eigen::Vector3f> source_normal(sample.size());
  for (std::size_t k = 0; k < sample.size(); ++k) source_normal[k] = source.normal(sample[k]);
  const float robust2 = 4.0f;  // Cauchy scale on the Mahalanobis cost
  Eigen::Isometry3d T = initial;
  for (int it = 0; it < options.max_iterations; ++it) {
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    // Summed in float over a block of correspondences, then into the double totals: each term is a
    // float product anyway, and converting a 6 x 6 matrix per correspondence cost as much as forming it.
    Eigen::Matrix<float, 6, 6> Hf = Eigen::Matrix<float, 6, 6>::Zero();
    Eigen::Matrix<float, 6, 1> gf = Eigen::Matrix<float, 6, 1>::Zero();
    int in_block = 0;
    const auto flush = [&] {
      H += Hf.cast<double>();
      g += gf.cast<double>();
      Hf.setZero();
      gf.setZero();
      in_block = 0;
    };
    double cost = 0.0;
    int n = 0;
    for (std::size_t k = 0; k < sample.size(); ++k) {
      const Eigen::Vector3f p = R * source.means[sample[k]] + t;
      const int j = target.nearest(p, options.max_correspondence);
      if (j < 0 || !tc->registrable(j)) continue;
      const Eigen::Vector3f u = tc->normal(j);
      const Eigen::Vector3f v = R * source_normal[k];
      const Eigen::Matrix3f C = 2.0f * Eigen::Matrix3f::Identity() - a * (u * u.transpose() + v * v.transpose());
      const Eigen::Matrix3f M = C.inverse();
      const Eigen::Vector3f r = tc->means[j] - p;
      const Eigen::Vector3f Mr = M * r;
      const float e = r.dot(Mr);
      const float w = robust2 / (robust2 + e);
      // J = [skew(p), -I], so J^T M J = [S^T M S, -S^T M; -M S, M] and J^T M r = [S^T M r; -M r] with
      // S = skew(p), S^T = -S and M symmetric: two 3 x 3 products instead of a 6 x 3 by 3 x 6 one.
      const Eigen::Matrix3f S = skew(p);
      const Eigen::Matrix3f MS = w * (M * S);
      Hf.topLeftCorner<3, 3>().noalias() -= S * MS;
      Hf.topRightCorner<3, 3>() -= MS.transpose();
      Hf.bottomLeftCorner<3, 3>() -= MS;
      Hf.bottomRightCorner<3, 3>() += w * M;
      gf.head<3>() -= w * p.cross(Mr);
      gf.tail<3>() -= w * Mr;
      cost += e;
      ++n;
      if (++in_block == kGicpBlock) flush();
    }
    flush();
    result.iterations = it + 1;
    result.correspondences = n;
    result.hessian = H;
    result.cost = n > 0 ? cost / n : 0.0;
    if (n < 6) break;
    Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
    if (options.fix_tilt) {
      // Yaw and translation only: the rotation update stays about the target's z axis.
      const Eigen::Matrix4d H4 = H.bottomRightCorner<4, 4>();
      delta.tail<4>() = H4.ldlt().solve(-g.tail<4>());
    } else {
      delta = H.ldlt().solve(-g);
    }
    if (!delta.allFinite()) break;
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d w = delta.head<3>();
    if (w.norm() > 1e-12) step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    step.translation() = delta.tail<3>();
    T = step * T;
    if (delta.tail<3>().norm() < options.translation_epsilon && w.norm() < options.rotation_epsilon) {
      result.converged = true;
      break;
    }
  }
  if (result.correspondences >= 6 && !result.converged) result.converged = result.iterations >= 1;
  result.transform = T;
  return result;
}

}  // namespace scan_context_loop
