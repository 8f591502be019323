// Geometric verification of a loop candidate: a coarse search over the descriptor's yaw hypotheses and
// a window of translations on the bird's-eye view of vertical structure, voxelised GICP from the best
// hypotheses, and the measurements the acceptance rule (acceptance_rule.h) judges, built for a world that
// changed between the two visits. Gives the rule's verdict with its reason, the refined relative pose and
// its covariance.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/acceptance_rule.h"
#include "scan_context_loop/core/coarse_search.h"
#include "scan_context_loop/core/descriptor.h"
#include "scan_context_loop/core/free_space.h"
#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {

struct VerificationResult {
  /// The acceptance rule's verdict (acceptance_rule.h), as record() wrote it.
  bool accepted = false;
  std::string reason;  ///< why it was rejected; empty when accepted
  /// The test that turned it down (one of kRejectionTests; empty when accepted), the value it measured
  /// and the limit that value broke (both 0 when the test has no number, e.g. "registration").
  std::string rejected_by;
  double rejection_value = 0.0, rejection_limit = 0.0;
  /// Every test passed but the odometry checks (LoopDetector::checkOdometry): the
  /// odometry may have broken down, so the consistency check may still confirm it with one support more
  /// than usual from other loops (ConsistencyFilter).
  bool odometry_contradicted = false;
  /// The odometry checks' largest disagreement over what they allow (below 1: they passed; 0: not
  /// checked). Of two loops that contradict each other, the consistency check trusts the lower one.
  double odometry_excess = 0.0;
  /// Not accepted on its own, but every test passed except the overlap or the free-space violation,
  /// which are within VerificationConfig::supported_inlier_ratio / supported_max_violation: a loop that
  /// another, fully accepted one can confirm (ConsistencyFilter). `accepted` becomes true once one does.
  bool needs_support = false;
  /// T_query<-match after registration.
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  /// Mean squared point-to-plane distance of the agreeing structure voxels [m^2].
  double fitness = 0.0;
  /// Symmetric structure overlap: min(overlap_query, overlap_match).
  double inlier_ratio = 0.0;
  /// Fractions of the query's / the candidate's structure voxels in the common region that agree.
  double overlap_query = 0.0, overlap_match = 0.0;
  /// Fractions of the candidate's / the query's structure, moved into the other's frame, that stand where
  /// the other saw through to something farther (free_space.h); `violation` is the larger.
  double violation_query = 0.0, violation_match = 0.0, violation = 0.0;
  /// Smallest over largest eigenvalue of the horizontal translation information (1: well constrained).
  double constraint_ratio = 0.0;
  /// Coarse bird's-eye score of the registered hypothesis (fraction of structure columns that land on
  /// structure), and how many hypotheses were registered.
  double coarse_score = 0.0;
  int hypotheses = 0;
  /// Tilt of the registered rotation between the two gravity-aligned frames [deg]: the angle its z axis
  /// makes with the vertical (0 when both alignments and the registration agree).
  double tilt_deg = 0.0;
  /// Roll and pitch are the gravity alignment's, not registered (tilt_deg was above
  /// VerificationConfig::registration_max_tilt_deg), and their variance is that limit squared.
  bool tilt_from_alignment = false;
  /// Column overlap: like overlap_query / overlap_match, but a structure voxel agrees with any voxel
  /// of the other on its plane within a column around it (sparse sensors sample a facade at other
  /// heights from another viewpoint). Measured only where it can decide (the voxel overlap below
  /// VerificationConfig::min_inlier_ratio), the query's side only when the candidate's reaches the
  /// support floor; 0 where not measured. Over at most 400 voxels a side; below the support floor, the
  /// most it could have been when counting stopped. column_overlap is the smaller measured one.
  double column_overlap_query = 0.0, column_overlap_match = 0.0, column_overlap = 0.0;
  std::size_t query_points = 0, match_points = 0;  ///< structure voxels of each
  double seconds = 0.0;
  /// Covariance of `relative` in (x, y, z, roll, pitch, yaw), row-major like ROS: the inverse of the
  /// point-to-plane information over the agreeing voxels scaled by their residual variance, with the
  /// diagonal raised to the configured floors. A direction the scene does not constrain (along a
  /// corridor) keeps a large variance.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();

  /// Takes the rule's verdict: accepted, reason, rejected_by, rejection_value, rejection_limit,
  /// needs_support and odometry_contradicted become the verdict's.
  void record(const Verdict& verdict);
};

/// The voxel grid of the registration data (VerificationConfig::voxel_leaf, max_range).
VoxelOptions voxelOptions(const VerificationConfig& config);

/// The registration data of a keyframe: finite points within max_range, rotated by `gravity_alignment`
/// (identity when the cloud is not gravity-aligned), in voxels.
VoxelCloud prepareCloud(const PointView& points, const VerificationConfig& config,
                        const Eigen::Matrix3f& gravity_alignment = Eigen::Matrix3f::Identity());

/// Verifies candidates against one query. Holds the query's index, built once in setQuery() and
/// reused for every candidate and hypothesis, and a scratch index for the candidate side. Not
/// thread-safe; the query must outlive its use.
class Verifier {
 public:
  explicit Verifier(const VerificationConfig& config) : config_(config) {}
  void setQuery(const VoxelCloud& query);
  /// Registers `match` onto the query from the best of `hypotheses` (T_query<-match guesses: the
  /// descriptor's yaw candidates with their viewpoints) and judges the result.
  VerificationResult verify(const VoxelCloud& match, const std::vector<Eigen::Isometry3d>& hypotheses);
  const VerificationConfig& config() const { return config_; }
  /// Takes new acceptance thresholds (the live settings); the query set by setQuery() stays.
  void setConfig(const VerificationConfig& config) { config_ = config; }

 private:
  /// GICP from one coarse pose, the measurements, then the acceptance rule's verdict on them.
  Verdict refineAndJudge(const VoxelCloud& match, const Eigen::Isometry3d& initial, VerificationResult* r);
  /// Registers `match` onto the query from `pose` (T_query<-match, refined in place), with roll and pitch
  /// held at the gravity alignment's when the rule does not trust the registered tilt (r->tilt_deg,
  /// r->tilt_from_alignment). Returns why registration failed, or "".
  std::string refine(const VoxelCloud& match, Eigen::Isometry3d* pose, VerificationResult* r);
  /// What the rule judges of `match` at r->relative: the overlaps both ways (and the column overlap where
  /// it can decide), the free-space violations and the fitness. Returns the point-to-plane information
  /// of the agreeing pairs in the query frame, (rx, ry, rz, tx, ty, tz).
  Eigen::Matrix<double, 6, 6> measure(const VoxelCloud& match, VerificationResult* r);
  /// The covariance of r->relative and its constraint ratio from that information.
  void estimateCovariance(const Eigen::Matrix<double, 6, 6>& information, VerificationResult* r) const;

  VerificationConfig config_;
  const VoxelCloud* query_ = nullptr;
  VoxelIndex query_index_, match_index_;
  StructureMap query_map_;             // bird's-eye structure of the query (coarse_search.h)
  FreeSpace query_free_, match_free_;  // what each side saw through (free_space.h)
  std::size_t query_structure_ = 0;
};

/// One-off verification from a single guess (builds the query's index itself).
VerificationResult verify(const VoxelCloud& query, const VoxelCloud& match, const Eigen::Isometry3d& initial,
                          const VerificationConfig& config);

}  // namespace scan_context_loop
