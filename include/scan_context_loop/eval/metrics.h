// Loop-detection metrics: the ground-truth protocol, precision-recall sweeps and summaries.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace eval {

/// One query's outcome, scored against the truth.
struct QueryOutcome {
  int query = -1;               ///< sequence frame index of the query keyframe
  int match = -1;               ///< frame index of the best candidate, -1 without one
  double distance = 1.0;        ///< the best candidate's descriptor distance (even above the threshold)
  double yaw = 0.0;             ///< estimated yaw prior [rad]
  bool revisit = false;         ///< an eligible earlier keyframe lies within the revisit radius
  long revisit_index = -1;      ///< database index of the nearest such keyframe (nearestRevisit), -1: none
  bool correct = false;         ///< the best candidate lies within the revisit radius
  double match_gap = -1.0;      ///< true distance between query and match [m], -1 without a match
  double true_yaw = 0.0;        ///< yaw of the match in the query frame from the true poses [rad]
  bool match_in_prior = false;  ///< the best candidate is a keyframe of the prior map (evaluate's prior)

  // With verification (Config::verify):
  int verified_match = -1;         ///< frame index of the accepted candidate, -1 when none was accepted
  bool verified_in_prior = false;  ///< the accepted candidate is a keyframe of the prior map
  /// The accepted loop's registered pose is within 1 m and 2 deg of the truth: a correct constraint,
  /// even between keyframes farther apart than the revisit radius (then verified_beyond_radius).
  bool verified_correct = false;
  bool verified_beyond_radius = false;
  int candidates_verified = 0;
  double fitness = 0.0, inlier_ratio = 0.0;
  double translation_error = 0.0;  ///< |t_est - t_true| of the refined T_query<-match [m]
  double yaw_error = 0.0;          ///< |yaw_est - yaw_true| of the refined pose [rad]
  bool reported_late = false;      ///< the loop was reported after its query (consistency check)
};

/// Verified loop decisions: each query is a detection when a candidate was accepted.
struct VerifiedMetrics {
  std::size_t true_positives = 0, false_positives = 0;
  double precision = 1.0, recall = 0.0, f1 = 0.0;
  /// Over the verified true positives.
  double translation_error_median = 0.0, translation_error_p90 = 0.0;
  double yaw_error_median = 0.0, yaw_error_p90 = 0.0;  ///< [deg]
  double candidates_mean = 0.0;
  int candidates_max = 0;
  std::size_t reported_late = 0;  ///< loops reported after their own keyframe (consistency check)
  std::size_t beyond_radius = 0;  ///< correct constraints between keyframes beyond the revisit radius
  /// Revisit queries whose descriptor's first candidate is the right place (within the revisit radius),
  /// and how many of them got a correct verified loop: what verification keeps of what the descriptor found.
  std::size_t first_candidate_right = 0, first_candidate_right_verified = 0;
};

VerifiedMetrics computeVerifiedMetrics(const std::vector<QueryOutcome>& outcomes);

/// Ground-truth protocol. `positions` are the true positions of the keyframes in arrival order.
/// `eligible` keyframes (a prefix, as the database reports for this query) are the ones outside the
/// exclusion windows. A query is a true revisit when one of them lies within `radius` of it.
bool isRevisit(const std::vector<Eigen::Vector3d>& positions, std::size_t query, std::size_t eligible, double radius);
/// The revisit's true partner: the eligible keyframe nearest the query within `radius`, -1 when the
/// query is no revisit (isRevisit is this >= 0). The oracle's loops (trajectory_correction.h) join the two.
long nearestRevisit(const std::vector<Eigen::Vector3d>& positions, std::size_t query, std::size_t eligible,
                    double radius);

struct PrPoint {
  double threshold, precision, recall;
};

struct Metrics {
  std::size_t queries = 0, revisits = 0;
  double threshold = 0.0;                          ///< the configured threshold
  double precision = 1.0, recall = 0.0, f1 = 0.0;  ///< at the configured threshold
  std::size_t true_positives = 0, false_positives = 0;
  double f1_max = 0.0, f1_max_threshold = 0.0;
  double recall_at_full_precision = 0.0, full_precision_threshold = 0.0;
  double average_precision = 0.0;
  std::vector<PrPoint> curve;  ///< one point per distinct distance, thresholds ascending
  /// Yaw error [deg] over the true positives at the configured threshold.
  double yaw_error_median = 0.0, yaw_error_p90 = 0.0, yaw_error_max = 0.0;
};

/// Precision and recall when every query whose distance is below `threshold` is a detection: a correct
/// one is a true positive, any other (a wrong match, or a query that is not a revisit) a false
/// positive. Recall = TP / revisits. Precision is 1 when nothing is detected.
/// The sweep puts a threshold just above each distinct distance; average precision is the step-wise
/// area under that curve; recall at 100% precision is the highest recall of a threshold with no FP.
Metrics computeMetrics(const std::vector<QueryOutcome>& outcomes, double threshold);

/// Percentile by nearest rank of an unsorted sample (0 for an empty one).
double percentile(std::vector<double> values, double fraction);

}  // namespace eval
}  // namespace scan_context_loop
