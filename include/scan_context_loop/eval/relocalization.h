// Relocalization in a prior map: a query sequence evaluated after a prior sequence (another session of
// the same places), its verified loops into the prior's keyframes scored against the truth. Both
// sequences' true poses must be in one world frame (scripts/simulate --session 2 writes them so).
#pragma once

#include <cstddef>
#include <vector>

namespace scan_context_loop {
namespace eval {

/// One query keyframe against the prior map.
struct PriorOutcome {
  int query = -1;            ///< frame index in the query sequence
  double seconds = 0.0;      ///< stamp, from the query's first keyframe
  double metres = 0.0;       ///< true distance driven from the query's first keyframe
  int nearest = -1;          ///< frame index of the nearest prior keyframe (truth)
  double nearest_gap = 0.0;  ///< its true distance [m]
  double nearest_yaw = 0.0;  ///< its heading relative to the query's [rad]: about pi when driven the other way
  bool prior_place = false;  ///< nearest_gap is below the revisit radius
  int match = -1;            ///< prior frame index of the verified loop into the prior, -1 without one
  /// Its registered pose is within 1 m and 2 deg of the truth (as the verified metrics score loops).
  bool correct = false;
  double translation_error = 0.0, yaw_error = 0.0;  ///< of the registered pose [m], [rad]
  /// When the loop was reported (the consistency check may wait for support): from the query's start.
  double reported_seconds = 0.0, reported_metres = 0.0;
};

struct RelocalizationMetrics {
  std::size_t prior_keyframes = 0;  ///< in the prior map
  std::size_t queries = 0, prior_places = 0;
  /// Query keyframes whose loop into the prior is correct (true positives) or not (false positives).
  std::size_t true_positives = 0, false_positives = 0;
  /// precision = TP / (TP + FP) (1 without loops); recall = correct loops at prior places / prior places.
  double precision = 1.0, recall = 0.0;
  /// Over the true positives.
  double translation_error_median = 0.0, translation_error_p90 = 0.0;
  double yaw_error_median = 0.0, yaw_error_p90 = 0.0;  ///< [deg]
  /// The first correct relocalization, when it was reported (-1: never), and the wrong ones before it.
  double first_seconds = -1.0, first_metres = -1.0;
  int first_query = -1;
  std::size_t false_before_first = 0;
  /// The first query keyframe at a prior place (-1: none), where relocalization first could happen.
  double first_place_seconds = -1.0, first_place_metres = -1.0;
};

RelocalizationMetrics computeRelocalizationMetrics(const std::vector<PriorOutcome>& outcomes);

}  // namespace eval
}  // namespace scan_context_loop
