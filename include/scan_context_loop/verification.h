// Geometric verification of a loop candidate: registration of the candidate's cloud onto the query's,
// seeded with the Scan Context yaw prior, giving an accept/reject decision, the refined relative pose
// and its covariance.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/descriptor.h"

namespace scan_context_loop {

struct VerificationConfig {
  /// Voxel size both clouds are reduced to before registration [m].
  double voxel_leaf = 0.6;
  /// Points beyond this horizontal range are dropped before registration [m].
  double max_range = 40.0;
  /// Clouds with fewer points (after preparation) are rejected as unverifiable.
  int min_points = 200;
  /// Correspondence distance of the coarse stage [m]: the yaw prior carries no translation, and
  /// revisits are often a lane or two to the side.
  double coarse_correspondence = 4.0;
  /// Correspondence distance of the fine stage [m].
  double fine_correspondence = 1.0;
  /// Iterations per stage.
  int max_iterations = 40;
  /// A query point whose nearest aligned candidate point is closer than this is an inlier [m].
  double inlier_distance = 0.5;
  /// Accept only when at least this fraction of the query's points are inliers (false pairs: 0.16-0.28
  /// on the real KITTI scans, up to 0.69 in repetitive simulated streets; true ones 0.7-0.98).
  double min_inlier_ratio = 0.7;
  /// Accept only when the inliers' mean squared distance is below this [m^2]. It grows with the voxel
  /// size (0.035-0.05 for true pairs at 0.4 m voxels, 0.055-0.07 at 0.6 m), so the inlier ratio is the
  /// main test (true pairs 0.69-0.98, false ones 0.16-0.28 on the real KITTI scans).
  double max_fitness = 0.15;
  /// Floors on the reported variances of x, y, z [m^2] and of roll, pitch, yaw [rad^2]. The
  /// point-to-point Hessian alone is far too confident: it ignores correspondence errors and does not
  /// see the slide along a corridor (on the Apollo pair it gives 1e-5 m^2 along a road where the
  /// registration moves 2 m), so a backend should never be told centimetres.
  double min_translation_variance = 0.01;
  double min_rotation_variance = 7.6e-5;  // (0.5 deg)^2
  /// The registration (Config::verify_method).
  RegistrationMethod method = RegistrationMethod::kGicp;
  /// NDT voxel resolution [m] (method ndt only).
  double ndt_resolution = 2.0;

  std::vector<std::string> validate() const;
};

struct VerificationResult {
  bool accepted = false;
  std::string reason;  ///< why it was rejected; empty when accepted
  /// T_query<-match after registration.
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  /// Mean squared distance of the inlier correspondences [m^2].
  double fitness = 0.0;
  /// Fraction of query points with an aligned candidate point within inlier_distance.
  double inlier_ratio = 0.0;
  std::size_t query_points = 0, match_points = 0;
  double seconds = 0.0;
  /// Covariance of `relative` in (x, y, z, roll, pitch, yaw), row-major like ROS: the inverse of the
  /// point-to-point Gauss-Newton Hessian at the solution over the inlier correspondences, scaled by the
  /// residual variance, with the diagonal raised to the configured floors.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
};

using VerificationCloud = pcl::PointCloud<pcl::PointXYZ>;

/// The registration settings held in the core Config (verify_* keys).
VerificationConfig verificationConfig(const Config& config);

/// Keeps the prepared cloud of every keyframe for later verification, within a byte budget. When a
/// new cloud would exceed it, the store keeps only every second keyframe (then every fourth, ...),
/// old and new alike: the whole map stays verifiable at a uniform, coarser spacing instead of its
/// oldest part vanishing, which matters because loop candidates are old keyframes. A candidate whose
/// cloud is not kept is reported as unverifiable. At 0.6 m voxels and 40 m range an HDL-64E
/// keyframe keeps about 7,000 points (112 KB): the default 1 GiB holds about 9,000 keyframes at full
/// density.
class CloudStore {
 public:
  explicit CloudStore(std::size_t max_bytes) : max_bytes_(max_bytes) {}
  /// Stores the cloud of keyframe `index` (indices arrive in increasing order) if the current density
  /// keeps it.
  void add(std::size_t index, VerificationCloud cloud);
  /// The cloud of keyframe `index`, or nullptr when it was never stored or was dropped.
  const VerificationCloud* get(std::size_t index) const;
  std::size_t bytes() const { return bytes_; }
  std::size_t stored() const;
  std::size_t dropped() const { return dropped_; }

 private:
  static std::size_t bytesOf(const VerificationCloud& c) { return c.size() * sizeof(pcl::PointXYZ); }
  std::size_t max_bytes_;
  std::size_t bytes_ = 0;
  std::size_t dropped_ = 0;
  std::size_t stride_ = 1;  // clouds are kept for keyframe numbers that are multiples of this
  std::vector<std::unique_ptr<VerificationCloud>> clouds_;  // by keyframe index; null = none
};

/// Drops NaN/Inf and far points and reduces to voxel_leaf voxels.
VerificationCloud prepareCloud(const PointView& points, const VerificationConfig& config);

/// Registers `match` onto `query` starting from `initial` (T_query<-match) and judges the result.
/// Either cloud below min_points gives a rejection with a reason, never an exception.
VerificationResult verify(const VerificationCloud& query, const VerificationCloud& match,
                          const Eigen::Isometry3d& initial, const VerificationConfig& config);

/// The pose a descriptor match implies, T_query<-match: the match's sensor stands at `viewpoint` (the
/// virtual viewpoint it was found from, zero for the real one) in the query's frame, turned by `yaw`.
Eigen::Isometry3d priorPose(double yaw, const Eigen::Vector2d& viewpoint = Eigen::Vector2d::Zero());

/// The same, starting from the descriptor prior: initial = priorPose(yaw, viewpoint).
VerificationResult verifyWithYaw(const VerificationCloud& query, const VerificationCloud& match, double yaw,
                                 const VerificationConfig& config,
                                 const Eigen::Vector2d& viewpoint = Eigen::Vector2d::Zero());

}  // namespace scan_context_loop
