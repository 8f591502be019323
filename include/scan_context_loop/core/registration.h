// Fast registration data and voxelised GICP for verifying loop candidates.
//
// A keyframe's registration data are prepared once, when it is processed: its points are accumulated
// into `resolution`-sized voxels (one pass, a dense index grid), and each voxel keeps its mean and the
// normal of its points (the GICP plane model). That is all a stored keyframe holds (16 bytes a voxel),
// so the map stays verifiable within a small budget. Registration aligns a candidate's voxels (source)
// onto the query's (target) through a dense index grid built once per query: correspondences are O(1)
// look-ups, not tree searches, and nothing is recomputed per attempt.
#pragma once

#include <array>
#include <cstdint>
#include <memory_resource>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {

/// The prepared registration data of one keyframe, in its (gravity-aligned) sensor frame. Its arrays are on
/// the heap unless it was made with another memory resource (CloudStore keeps its clouds in arenas of
/// their own); a plain copy is always on the heap.
struct VoxelCloud {
  VoxelCloud() = default;
  /// A copy of `other` whose arrays, exactly as long as its voxels, are in `memory`.
  VoxelCloud(const VoxelCloud& other, std::pmr::memory_resource* memory)
      : resolution(other.resolution),
        max_range(other.max_range),
        means(other.means, memory),
        normals(other.normals, memory) {}

  float resolution = 1.0f;
  /// Horizontal crop radius the voxels were made with [m].
  float max_range = 40.0f;
  std::pmr::vector<Eigen::Vector3f> means;
  /// Unit normal of the voxel's points (the direction of least spread, towards the sensor), quantised
  /// to int8 (x, y, z), and in [3] the shape of the points (VoxelShape).
  std::pmr::vector<std::array<std::int8_t, 4>> normals;

  /// How a voxel's points spread, from the eigenvalues l0 <= l1 <= l2 of their covariance.
  enum Shape : std::int8_t {
    kPlanar = 1,          ///< l0 small against l1: a surface (facade, ground, car side); GICP's plane model
    kVerticalLine = 2,    ///< l1 small against l2 along z: a pole or a trunk
    kHorizontalLine = 3,  ///< l1 small against l2, not along z: one scan line, an edge; no direction
                          ///< to trust across, so it takes part in nothing
    kScatter = 4,         ///< no dominant direction: foliage; registered, but never structure
  };

  std::size_t size() const { return means.size(); }
  bool empty() const { return means.empty(); }
  std::size_t bytes() const { return means.size() * (sizeof(Eigen::Vector3f) + 4); }
  Eigen::Vector3f normal(std::size_t i) const {
    return Eigen::Vector3f(normals[i][0], normals[i][1], normals[i][2]) * (1.0f / 127.0f);
  }
  Shape shape(std::size_t i) const { return static_cast<Shape>(normals[i][3]); }
  /// Vertical structure, what a changed world keeps (facades, walls, poles, trunks; car sides too): a
  /// planar voxel whose normal is within 30 deg of horizontal, or a vertical line.
  bool vertical(std::size_t i) const {
    return (shape(i) == kPlanar && std::abs(normals[i][2]) < 64) || shape(i) == kVerticalLine;
  }
  /// Ground-like: planar, normal within about 25 deg of vertical.
  bool ground(std::size_t i) const { return shape(i) == kPlanar && std::abs(normals[i][2]) > 115; }
  /// Usable for registration (everything but horizontal lines).
  bool registrable(std::size_t i) const { return shape(i) != kHorizontalLine; }
};

struct VoxelOptions {
  float resolution = 1.0f;  ///< voxel edge [m]
  float max_range = 40.0f;  ///< horizontal crop [m]
  float min_z = -8.0f;      ///< vertical extent kept, sensor frame [m]
  float max_z = 24.0f;
  int min_points = 3;  ///< voxels with fewer points are dropped (no plane)
};

/// Points a voxel cloud is made from at most: dense scans hold far more points near the sensor than a
/// metre-sized voxel needs for its mean and normal, so larger clouds are read with a stride.
constexpr std::size_t kVoxelCloudMaxPoints = 60000;

/// The most voxels makeVoxelCloud can make with `options`: no more than the cells of its grid over the
/// crop (one voxel a cell), nor than the points it reads (a voxel holds at least one). 0 for a
/// resolution or range that is not positive.
std::size_t maxVoxels(const VoxelOptions& options);

/// Accumulates the finite points within the crop, after rotating them by `rotation` (a gravity alignment
/// rotation; identity for none), into voxels. Reuses an internal scratch grid per thread.
VoxelCloud makeVoxelCloud(const PointView& points, const VoxelOptions& options,
                          const Eigen::Matrix3f& rotation = Eigen::Matrix3f::Identity());

/// A dense index over a VoxelCloud's voxels for O(1) look-ups by position: a grid of cells of the
/// cloud's resolution over its crop, each holding the index of the voxel whose mean falls in it.
/// Cells are stamped with a generation, so rebuilding it for the next cloud costs only that cloud's
/// voxels, not a clear of the whole grid.
class VoxelIndex {
 public:
  void build(const VoxelCloud& cloud);
  /// Index of the voxel in the cell holding p, or -1.
  int at(const Eigen::Vector3f& p) const;
  /// The voxel among p's cell and its 6 face neighbours whose mean is nearest to p, within
  /// `max_distance`, or -1.
  int nearest(const Eigen::Vector3f& p, float max_distance) const;
  /// Whether a voxel other than scatter lies on the vertical plane through p with horizontal normal n:
  /// within `plane` [m] of it, `along` [m] of p horizontally and `up` [m] vertically. With a zero n,
  /// within `plane` of p horizontally (a pole). A sparse sensor samples a facade at heights that depend
  /// on the viewpoint; this asks only whether the other keyframe saw the same surface there.
  bool onPlane(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float plane, float along, float up) const;
  const VoxelCloud* cloud() const { return cloud_; }

 private:
  int cell(int ix, int iy, int iz) const {
    if (ix < 0 || iy < 0 || iz < 0 || ix >= nx_ || iy >= nx_ || iz >= nz_) return -1;
    return (iz * nx_ + iy) * nx_ + ix;
  }
  /// The voxel in cell c (from cell()), or -1.
  int voxelIn(int c) const { return c >= 0 ? slots_[c] : -1; }
  const VoxelCloud* cloud_ = nullptr;
  float inv_res_ = 1.0f, min_xy_ = 0.0f, min_z_ = 0.0f;
  int nx_ = 0, nz_ = 0;
  /// The voxel in each cell, -1 for none: 4 bytes a cell, as the grid is megabytes and registration
  /// looks up seven cells per correspondence (a generation stamp beside each index doubled the misses).
  std::vector<std::int32_t> slots_;
  /// The cells the last build filled, emptied by the next one (a few thousand of the grid's 280,000).
  std::vector<std::int32_t> filled_;
};

struct GicpOptions {
  int max_iterations = 20;
  float max_correspondence = 1.0f;  ///< [m], between a moved source mean and a target mean
  /// Source voxels used (vertical structure first, then an even share of the rest): the cost bound.
  int max_source_voxels = 1500;
  /// GICP plane model: the variance along the normal relative to the in-plane one.
  float plane_epsilon = 1e-2f;
  /// Stop when the update is below these [m], [rad].
  double translation_epsilon = 1e-3, rotation_epsilon = 1e-4;
  /// Estimate yaw and translation only (4 DoF): roll and pitch stay as in `initial`.
  bool fix_tilt = false;
};

struct GicpResult {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  ///< target <- source
  int iterations = 0;
  int correspondences = 0;
  bool converged = false;
  /// Gauss-Newton Hessian of the point-to-plane cost at the solution in (rx, ry, rz, tx, ty, tz),
  /// weighted by the plane model's information.
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  double cost = 0.0;  ///< mean Mahalanobis cost over the correspondences
};

/// Voxelised GICP: aligns `source` onto the cloud indexed by `target`, starting from `initial`
/// (target <- source). 6-DoF Gauss-Newton with the plane model on both sides.
GicpResult alignVoxels(const VoxelCloud& source, const VoxelIndex& target, const Eigen::Isometry3d& initial,
                       const GicpOptions& options);

/// Picks up to `max_count` source voxels: every vertical one first (structure), then an even stride
/// over the others.
std::vector<int> sampleVoxels(const VoxelCloud& cloud, int max_count);

}  // namespace scan_context_loop
