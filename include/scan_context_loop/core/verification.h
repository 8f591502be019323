// Geometric verification of a loop candidate: a coarse search over the descriptor's yaw hypotheses and
// a window of translations on the bird's-eye view of vertical structure, voxelised GICP from the best
// hypotheses, and an acceptance test built for a world that changed between the two visits. Gives an
// accept/reject decision with its reason, the refined relative pose and its covariance.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/block_arena.h"
#include "scan_context_loop/core/coarse_search.h"
#include "scan_context_loop/core/descriptor.h"
#include "scan_context_loop/core/free_space.h"
#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {


struct VerificationResult {
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
  /// VerificationConfig::max_tilt), and their variance is max_tilt squared.
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
};

/// The names VerificationResult::rejected_by takes, in the order the tests run: "unverifiable" (no
/// registration data), "structure" (too few structure voxels), "registration" (no correspondences,
/// diverged), "overlap", "free_space", "fitness", "degenerate", "odometry_rotation",
/// "odometry_translation", then after verification "consistency" (no agreeing loop in time).
extern const char* const kRejectionTests[10];

/// The voxel grid of the registration data (VerificationConfig::voxel_leaf, max_range).
VoxelOptions voxelOptions(const VerificationConfig& config);

/// Keeps the prepared registration data of every keyframe for later verification, within a byte
/// budget. When a new keyframe would exceed it, the store keeps only every second keyframe (then every
/// fourth, ...), old and new alike: the whole map stays verifiable at a uniform, coarser spacing instead
/// of its oldest part vanishing, which matters because loop candidates are old keyframes. A candidate
/// whose data is not kept is reported as unverifiable. At 1 m voxels and 40 m an HDL-64E keyframe keeps
/// about 8,000 voxels (130 KB): the default 1 GiB holds about 8,000 keyframes at full density.
///
/// The clouds' arrays are not on the heap: each keyframe's go into the arena of its level, the number
/// of halvings that keep it (the trailing zero bits of its index: odd keyframes are level 0, the first
/// to go). A halving drops one whole level, so its arena goes back to the system whole once its clouds
/// are freed, and the heap never holds the holes that freeing half the store in place left (they slowed
/// every later keyframe and stayed resident: doc/testing.md, the soak). An arena maps 2 MB blocks of
/// ordinary pages, so what is resident exceeds bytes() by less than a page a level (memoryBytes(), what
/// is mapped, by less than 2 MB a level).
class CloudStore {
 public:
  explicit CloudStore(std::size_t max_bytes) : max_bytes_(max_bytes) {}
  /// Stores keyframe `index` if the current density keeps it (in any order: a team's fetched clouds come
  /// as they are asked for; a keyframe stored again replaces its data).
  void add(std::size_t index, const VoxelCloud& cloud);
  /// The data of keyframe `index`, or nullptr when it was never stored or was dropped.
  const VoxelCloud* get(std::size_t index) const;
  /// A share of the data of keyframe `index` (null as get()): a stored cloud never changes, and a share
  /// keeps it (and the arena memory it holds) alive after the store dropped it, on any thread
  /// (DatabaseSnapshot writes clouds while the store goes on).
  std::shared_ptr<const VoxelCloud> share(std::size_t index) const;
  /// Shares of the data of every stored keyframe in [begin, end), by index, in order.
  std::vector<std::pair<std::size_t, std::shared_ptr<const VoxelCloud>>> share(std::size_t begin,
                                                                               std::size_t end) const;
  /// Bytes of the voxels kept (what the budget counts).
  std::size_t bytes() const { return bytes_; }
  /// Bytes of memory the kept keyframes' arenas hold (bytes() plus each level's unused block end).
  std::size_t memoryBytes() const;
  /// Keyframes whose data are kept (counted as they come and go: the node reads it every keyframe).
  std::size_t stored() const { return stored_; }
  std::size_t dropped() const { return dropped_; }
  /// Data are kept for the keyframe numbers that are multiples of this (1 until the budget is reached;
  /// doubled by each halving).
  std::size_t stride() const { return stride_; }
  std::size_t maxBytes() const { return max_bytes_; }
  /// Dropped clouds still to be freed: halving the density takes them out at once (get() no longer
  /// serves them, bytes() no longer counts them) but frees at most kReleasedPerAdd of them in each later
  /// add(), so no single keyframe pays for freeing half the store; their level's memory goes back to the
  /// system with the last of them.
  std::size_t releasing() const { return releasing_.size(); }
  static constexpr std::size_t kReleasedPerAdd = 64;
  /// The level of keyframe `index`: its data stay while the stride is at most 2^level.
  static int levelOf(std::size_t index);
  /// The block size of each level's arena.
  static constexpr std::size_t kLevelBlockBytes = std::size_t(2) << 20;

 private:
  std::size_t max_bytes_;
  std::size_t bytes_ = 0;
  std::size_t dropped_ = 0;
  std::size_t stored_ = 0;
  std::size_t stride_ = 1;  // data are kept for keyframe numbers that are multiples of this
  // By keyframe index, the stored ones only: a store holds a few thousand of a database's keyframes,
  // and a save shares them without walking a slot for each of a million keyframes.
  std::map<std::size_t, std::shared_ptr<const VoxelCloud>> clouds_;
  std::vector<BlockArena::Handle> levels_;  // by level; null before its first cloud and once dropped
  std::vector<std::shared_ptr<const VoxelCloud>> releasing_;  // dropped, memory not yet freed
};

/// The warning for a store whose stride grew past `previous_stride` (one or more halvings since), "" when
/// it did not: what was lost, what it means for verification and saving, and what to change.
/// `keyframes` is the database's size.
std::string cloudStoreHalvingWarning(std::size_t previous_stride, const CloudStore& store, std::size_t keyframes);

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
  /// GICP from one coarse pose, then the acceptance test; returns the rejection reason or "".
  std::string refineAndJudge(const VoxelCloud& match, const Eigen::Isometry3d& initial, VerificationResult* r);

  VerificationConfig config_;
  const VoxelCloud* query_ = nullptr;
  VoxelIndex query_index_, match_index_;
  StructureMap query_map_;  // bird's-eye structure of the query (coarse_search.h)
  FreeSpace query_free_, match_free_;  // what each side saw through (free_space.h)
  std::size_t query_structure_ = 0;
};

/// One-off verification from a single guess (builds the query's index itself).
VerificationResult verify(const VoxelCloud& query, const VoxelCloud& match, const Eigen::Isometry3d& initial,
                          const VerificationConfig& config);

/// The pose a descriptor match implies, T_query<-match: the match's sensor stands at `viewpoint` (the
/// virtual viewpoint it was found from, zero for the real one) in the query's frame, turned by `yaw`.
Eigen::Isometry3d priorPose(double yaw, const Eigen::Vector2d& viewpoint = Eigen::Vector2d::Zero());

}  // namespace scan_context_loop
