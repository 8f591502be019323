// Running the detector online over a KITTI-format sequence and writing what it found.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/consistency.h"
#include "scan_context_loop/eval/metrics.h"
#include "scan_context_loop/eval/relocalization.h"
#include "scan_context_loop/eval/sequence.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {
namespace eval {

/// One candidate that went through verification, scored against the truth (verifications.csv): what
/// the acceptance thresholds are chosen on.
struct VerificationAttempt {
  int query = -1, match = -1;                       ///< frame indices
  double distance = 1.0;                            ///< descriptor distance
  double gap = 0.0;                                 ///< true distance between the two keyframes [m]
  bool true_place = false;                          ///< within the revisit radius
  VerificationResult result;                        ///< the decision, its reason and every feature it was made on
  double translation_error = 0.0, yaw_error = 0.0;  ///< of the registered pose against the truth [m], [rad]
  double rotation_error = 0.0;                      ///< angle of the registered rotation against the true one [rad]
};

struct Evaluation {
  std::vector<VerificationAttempt> attempts;
  std::vector<QueryOutcome> outcomes;
  std::vector<double> descriptor_ms, query_ms, verify_ms;
  /// CPU time of the process (user + system, every thread) spent scoring the sequence: reading its scans,
  /// describing, querying and verifying them [s]; the pose graph after it is not included.
  double cpu_seconds = 0.0;
  Metrics metrics;
  bool verification = false;  ///< Config::verify was on: verified_* fields and metrics are filled
  VerifiedMetrics verified;
  std::size_t rejected = 0;       ///< keyframes the detector refused (see errors)
  std::size_t loops_dropped = 0;  ///< verified loops the consistency check dropped
  std::vector<std::string> errors;
  /// Every loop reported, in order, as the node publishes them (keyframe numbers in arrival order).
  std::vector<Loop> loops;
  /// For each keyframe number (database index), the sequence's keyframe it is (Sequence::truth etc.);
  /// -1 for a keyframe of the prior map.
  std::vector<long> keyframe_of;
  /// Evaluated in a prior map: each query keyframe against the prior map, and their scores.
  bool has_prior = false;
  std::string prior_source;  ///< the prior sequence's directory or the prior database's file
  std::string prior_truth;   ///< with a database prior: the sequence whose poses.txt its tags index
  std::vector<PriorOutcome> prior_outcomes;
  RelocalizationMetrics relocalization;
  /// The prior map's keyframes in database order (database index i < frames.size()): frame index (tag),
  /// true pose, stamp, and as `odometry` the pose the pipeline stored (the prior's odometry).
  Sequence prior_keyframes;
};

struct DatabasePrior;  // prior_map.h

struct EvaluationOptions {
  double revisit_radius = 5.0;  ///< the ground-truth revisit radius [m] (isRevisit)
  /// The prior map, at most one of the two: a sequence whose keyframes go through the pipeline first
  /// (session 0, not scored), or a saved database (loadDatabasePrior) whose keyframes join it as they
  /// were saved; its sessions are moved into the pipeline. Both truths must be in the query's world frame.
  const Sequence* prior = nullptr;
  DatabasePrior* prior_database = nullptr;
  /// After the run, the pipeline's database is saved here (saveDatabase; empty: not saved), with the
  /// registration data when `save_clouds`, so a mapping run can be kept and evaluated against later.
  std::string save_database;
  bool save_clouds = false;
};

/// CPU time this process has used so far, user + system, every thread [s].
double processCpuSeconds();

/// Feeds every keyframe in order through KeyframePipeline (keyframes.h), the node's own code, and
/// scores each query with the ground-truth protocol (isRevisit with the revisit radius). In a prior map,
/// the sequence's keyframes form a new session after the prior's; its queries are scored against every
/// earlier keyframe, the prior's included, and against the prior map alone (Evaluation::relocalization).
/// Returns false, `error` saying why, when the prior database does not join the pipeline or the
/// database cannot be saved.
bool evaluate(const Sequence& sequence, const Config& config, const EvaluationOptions& options, Evaluation* evaluation,
              std::string* error);

/// evaluate() without a database: with a `prior` sequence or none.
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
