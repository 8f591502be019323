// Online loop detection: describe a keyframe, query the database, then add the keyframe; optionally
// verify the candidates geometrically and check verified loops against each other.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/cloud_store.h"
#include "scan_context_loop/core/consistency.h"
#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/descriptor.h"
#include "scan_context_loop/core/loop_tracking.h"
#include "scan_context_loop/core/prior_sessions.h"
#include "scan_context_loop/core/verification.h"
#include "scan_context_loop/core/world_tilt.h"

namespace scan_context_loop {

/// A candidate that went through geometric verification.
struct VerifiedCandidate {
  std::size_t index = 0;                                ///< candidate keyframe number
  Alignment alignment;                                  ///< its descriptor alignment (distance, yaw prior)
  Eigen::Vector2d viewpoint = Eigen::Vector2d::Zero();  ///< the viewpoint it was found from
  bool tracked = false;  ///< proposed by loop tracking (Loop::tracked), not by the descriptor
  VerificationResult result;

  /// The loop it makes with query keyframe `query` (verified when the registration accepted it).
  Loop toLoop(std::size_t query) const;
};

struct Detection {
  /// false: keyframe selection (KeyframePipeline) passed over the cloud; nothing else is set.
  bool selected = true;
  bool accepted = false;  ///< false: the keyframe was rejected (see error) and nothing changed
  std::string error;
  std::size_t index = 0;  ///< keyframe number given to the new keyframe
  /// The keyframe began a new session (its stamp jumped back, Config::new_session_jump).
  bool new_session = false;
  /// Candidates among the earlier keyframes, from every viewpoint (Config::lateral_offset_step), best
  /// first, at most Config::num_candidates.
  QueryResult query;
  /// Gravity alignment of this keyframe: "pose", "ground" or "none", and the tilt it removed [deg] (tilts
  /// below 0.5 deg are left alone).
  const char* aligned_by = "none";
  double tilt_deg = 0.0;
  /// With a pose (gravity alignment auto or pose), the ground is fitted too, on every keyframe until the world's
  /// tilt is known (world_tilt.h) and every LoopDetector::kGravityCheckInterval keyframes after:
  /// the angle between the up the pose gives and the ground's [deg] (negative: not checked). `world_tilt_deg`: how far
  /// the odometry's world frame is from gravity, once known (negative before).
  double gravity_disagreement_deg = -1.0;
  double world_tilt_deg = -1.0;
  std::size_t points_used = 0;
  std::size_t points_skipped = 0;
  double descriptor_seconds = 0.0;  ///< making the descriptors (one per viewpoint)
  double query_seconds = 0.0;       ///< querying the database and adding the keyframe

  /// With Config::verify: the candidates verified, in order; the last one is accepted when `verified`.
  std::vector<VerifiedCandidate> verifications;
  bool verified = false;
  double verify_seconds = 0.0;
  /// The ground fit that checks the pose's up (gravity_disagreement_deg), and choosing the loops to report
  /// (consistency, odometry checks): the rest of the keyframe's time in LoopDetector::process.
  double ground_check_seconds = 0.0;
  double choose_seconds = 0.0;
  bool verifications_enabled = false;

  /// The loops to report now. Without verification: this keyframe's descriptor match. With it: this
  /// keyframe's verified loop, or with the consistency check (Config::consistency_min_support) the
  /// loops it confirmed now, which may belong to earlier keyframes (Loop::query says which).
  std::vector<Loop> loops;
  /// Verified loops that the consistency check gave up on at this keyframe (no support in time).
  std::vector<Loop> dropped;
};

/// Not thread-safe (one owner thread), like Database.
class LoopDetector {
 public:
  explicit LoopDetector(const Config& config)
      : database_(config),
        store_(static_cast<std::size_t>(config.verification.max_bytes)),
        verification_(config.verification),
        verifier_(verification_),
        consistency_(config) {}

  Detection process(const PointView& points, const KeyframeInfo& info);

  /// The ground fits behind the world's tilt (Detection::world_tilt_deg), once it is known.
  static constexpr std::size_t kGravityCheckInterval = 10;
  /// A world tilted more than this from gravity deserves a warning [deg].
  static constexpr double kGravitySuspectDeg = 4.0;
  /// The odometry's world frame as far as gravity alignment knows it (world_tilt.h).
  const WorldTilt& worldTilt() const { return world_tilt_; }

  /// Where a cloud is among the stored keyframes, without storing it (relocalization on request):
  /// gravity-aligned by its ground, described from every viewpoint, queried (the candidates the windows allow:
  /// with Config::prior_sessions_only, every keyframe of the earlier sessions) and verified. The result
  /// has `accepted` false (nothing was added) and `index` the database size; `verified` and the last of
  /// `verifications` say where it is. Needs verification on (else nothing is verified).
  Detection locate(const PointView& points);

  /// Keyframes from now on form a new session (Database::startSession).
  void startSession() { database_.startSession(); }

  /// Adds keyframes of earlier runs (a saved database, database_file.h) after the current ones as
  /// earlier sessions (Database::appendSessions), with their gravity alignment and registration data (which
  /// the cloud store keeps within its budget, CloudStore::add); keyframes from now on form a new
  /// session. Returns false and changes nothing when they do not fit this detector: a descriptor or
  /// session problem (Database::appendSessions), gravity alignment or cloud lists of another length than the
  /// keyframes', or registration data made with other voxel settings. `error` then says which.
  bool appendSessions(PriorSessions sessions, std::string* error = nullptr);

  /// Gives keyframe `index`, appended without them (appendSessions), its gravity alignment L_R_sensor and its
  /// registration data, as they arrive later (a team's keyframes: team_matcher.h). False, changing nothing,
  /// for an index past the database or data made with other voxel settings than verification's (`error`
  /// says which).
  bool attachCloud(std::size_t index, const Eigen::Matrix3f& gravity_alignment, const VoxelCloud& cloud,
                   std::string* error = nullptr);

  /// Takes new values of the live settings for the next keyframe; the caller checks that only live
  /// ones changed (KeyframePipeline::reconfigure).
  void reconfigure(const Config& config);

  const Database& database() const { return database_; }
  const Config& config() const { return database_.config(); }
  const CloudStore& cloudStore() const { return store_; }
  /// L_R_sensor of keyframe `index`: the gravity alignment its descriptor and registration data were made in.
  const Eigen::Matrix3f& gravityAlignment(std::size_t index) const;
  /// The gravity alignments of keyframes [begin, end) (clamped) as they are now, readable on any thread
  /// while this detector goes on (attachCloud copies a shared chunk before changing it).
  ChunkedLog<Eigen::Matrix3f>::View gravityAlignments(std::size_t begin, std::size_t end) const {
    return gravity_alignment_.view(begin, end);
  }
  const ConsistencyFilter& consistency() const { return consistency_; }

 private:
  /// A cloud gravity-aligned (`aligned` holds the rotated points `points` views, when it was turned) and
  /// described.
  struct GravityAlignedScan {
    /// L_R_sensor: turns `points` into the gravity-aligned frame (identity when not gravity-aligned).
    Eigen::Matrix3f to_gravity = Eigen::Matrix3f::Identity();
    PointView points;  ///< the cloud as given (not turned: binning and voxels turn each point as they read it)
    Descriptor descriptor;
  };
  /// Gravity-aligns and describes `raw`, then queries the database from every viewpoint into detection->query.
  void describeAndQuery(const PointView& raw, const KeyframeInfo& info, GravityAlignedScan* out, Detection* detection);
  /// Searches from the virtual viewpoints too (`grids`: their height grids) and merges their candidates
  /// into detection->query.
  void queryViewpoints(const std::vector<Eigen::Vector2f>& views, const std::vector<HeightGrid>& grids,
                       const KeyframeInfo& info, Detection* detection);
  /// Registers the `tracked` candidate (loop tracking; may be null), then detection->query's candidates
  /// onto `cloud` (gravity-aligned by `to_gravity`; `query` its descriptor) until one is accepted. detection->index is
  /// the query's keyframe number; `query_stored` says whether the query is in the database (then the
  /// odometry rotation check runs).
  void verifyCandidates(const VoxelCloud& cloud, const Descriptor& query, const Eigen::Matrix3f& to_gravity,
                        bool query_stored, const TrackedCandidate* tracked, Detection* detection);
  /// Registers candidate `c` from `guesses` (T_query<-match in the gravity-aligned frames) and appends the
  /// outcome to detection->verifications; returns whether it was accepted.
  bool verifyOne(const Candidate& c, bool tracked, const std::vector<Eigen::Isometry3d>& guesses,
                 const Eigen::Matrix3f& to_gravity, bool query_stored, Detection* detection);
  /// Registration guesses for a candidate (T_query<-match): its alignment, then other yaw hypotheses.
  std::vector<Eigen::Isometry3d> hypotheses(const Candidate& candidate, const Descriptor& query) const;
  static constexpr int kYawHypotheses = 3;
  /// What keeps registration data from joining this detector (voxel settings other than verification's,
  /// inconsistent arrays), or "".
  std::string cloudMismatch(const VoxelCloud& cloud) const;
  /// L_R_sensor of a new keyframe (Config::gravity alignment), identity when it is not gravity-aligned.
  Eigen::Matrix3f gravityAlignmentOf(const PointView& points, const KeyframeInfo& info, Detection* detection) const;
  /// For a keyframe with a pose (gravity alignment auto or pose): fits the ground of `points` (every keyframe until
  /// the world's tilt is known, every kGravityCheckInterval after), adds it to the world's tilt and
  /// records how far pose and ground disagree in `detection`.
  void updateWorldTilt(const PointView& points, const KeyframeInfo& info, Detection* detection);
  /// The candidate's data with its Config::verify_submap neighbours on each side (older than `query`).
  VoxelCloud submapOf(std::size_t index, std::size_t query) const;
  /// Registration results are in the gravity-aligned frames; loops are reported in the sensor frames.
  void toSensorFrames(const Eigen::Matrix3f& query_alignment, std::size_t match, VerificationResult* result) const;
  /// The odometry checks of an accepted result or one that needs support: measures how far its rotation,
  /// and its translation, are from what the odometry predicts (odometry_trust.h) and records the
  /// acceptance rule's verdict on that (judgeOdometry, acceptance_rule.h) when they contradict it.
  void checkOdometry(std::size_t query, std::size_t match, VerificationResult* result) const;
  /// Fills detection->loops: without verification, the descriptor's best candidate; with it, the
  /// accepted candidate (or, with the consistency check, one waiting for support), published at once or
  /// once the consistency filter confirms it.
  void chooseLoops(Detection* detection);

  Database database_;
  CloudStore store_;
  VerificationConfig verification_;
  Verifier verifier_;
  ChunkedLog<Eigen::Matrix3f> gravity_alignment_;  // L_R_sensor per keyframe; a snapshot shares its chunks
  WorldTilt world_tilt_;                           // of the current session's odometry frame
  std::uint32_t world_tilt_session_ = 0;           // the session it is of
  std::size_t posed_keyframes_ = 0;                // keyframes with a pose since the world's tilt is known
  ConsistencyFilter consistency_;
  LoopTracker tracker_;
};

/// The virtual viewpoints of Config::lateral_offset_step / lateral_offset_count along the sensor's y
/// axis, nearest first (+step, -step, +2 step, ...), without the real one; empty when disabled.
std::vector<Eigen::Vector2f> lateralViewpoints(const Config& config);

}  // namespace scan_context_loop
