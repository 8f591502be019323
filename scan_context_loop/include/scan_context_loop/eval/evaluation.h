// Running the detector online over a KITTI-format sequence and writing what it found.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/consistency.h"
#include "scan_context_loop/eval/metrics.h"
#include "scan_context_loop/eval/relocalization.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {
namespace eval {

struct SequenceOptions {
  double keyframe_spacing = 0.0;  ///< metres of true travel between keyframes; 0 = every frame
  int first = 0, last = -1;       ///< frame window (last < 0: to the end)
  bool use_odometry_file = true;  ///< feed odom_poses.txt to the detector when the sequence has one
};

/// The keyframes of a sequence: frame numbers, true and odometry LiDAR poses, stamps.
struct Sequence {
  std::string dir;
  std::vector<int> frames;
  std::vector<Eigen::Isometry3d> truth, odometry;
  std::vector<double> stamps;
  std::size_t missing_scans = 0;  ///< frames of the window skipped because their .bin is absent
  bool odometry_from_file = false;
};

/// Reads poses.txt, calib.txt, times.txt (optional) and odom_poses.txt (optional), then selects the
/// keyframes among the frames whose scan exists.
bool loadSequence(const std::string& dir, const SequenceOptions& options, Sequence* sequence, std::string* error);

/// One candidate that went through verification, scored against the truth (verifications.csv): what
/// the acceptance thresholds are chosen on.
struct VerificationAttempt {
  int query = -1, match = -1;   ///< frame indices
  double distance = 1.0;        ///< descriptor distance
  double gap = 0.0;             ///< true distance between the two keyframes [m]
  VerificationResult result;    ///< the decision, its reason and every feature it was made on
  double translation_error = 0.0, yaw_error = 0.0;  ///< of the registered pose against the truth [m], [rad]
};

struct Evaluation {
  std::vector<VerificationAttempt> attempts;
  std::vector<QueryOutcome> outcomes;
  std::vector<double> descriptor_ms, query_ms, verify_ms;
  Metrics metrics;
  bool verification = false;  ///< Config::verify was on: verified_* fields and metrics are filled
  VerifiedMetrics verified;
  std::size_t rejected = 0;  ///< keyframes the detector refused (see errors)
  std::size_t loops_dropped = 0;  ///< verified loops the consistency check dropped
  std::vector<std::string> errors;
  /// Every loop reported, in order, as the node publishes them (keyframe numbers in arrival order).
  std::vector<Loop> loops;
  /// Evaluated after a prior sequence: each query keyframe against the prior map, and their scores.
  bool has_prior = false;
  std::string prior_dir;
  std::vector<PriorOutcome> prior_outcomes;
  RelocalizationMetrics relocalization;
};

/// Feeds every keyframe in order through KeyframePipeline (keyframes.h), the node's own code, and
/// scores each query with the ground-truth protocol (isRevisit with `revisit_radius`). With a `prior`
/// sequence, its keyframes go through the pipeline first (session 0, the prior map, not scored), then the
/// sequence's as a new session; its queries are scored against every earlier keyframe, the prior's
/// included, and against the prior map alone (Evaluation::relocalization). Both sequences' true poses
/// must be in one world frame.
Evaluation evaluate(const Sequence& sequence, const Config& config, double revisit_radius,
                    const Sequence* prior = nullptr);

bool writeResultsCsv(const std::string& path, const Evaluation& evaluation, std::string* error);
bool writeMetricsJson(const std::string& path, const Evaluation& evaluation, const Sequence& sequence,
                      const Config& config, double revisit_radius, std::string* error);
bool writeVerificationsCsv(const std::string& path, const Evaluation& evaluation, std::string* error);
/// One row per query keyframe against the prior map (Evaluation::prior_outcomes).
bool writeRelocalizationCsv(const std::string& path, const Evaluation& evaluation, std::string* error);
bool writeTrajectoryCsv(const std::string& path, const Sequence& sequence, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
