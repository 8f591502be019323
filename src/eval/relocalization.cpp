#include "scan_context_loop/eval/relocalization.h"

#include <cmath>

#include "scan_context_loop/eval/metrics.h"

namespace scan_context_loop {
namespace eval {

RelocalizationMetrics computeRelocalizationMetrics(const std::vector<PriorOutcome>& outcomes) {
  RelocalizationMetrics r;
  r.queries = outcomes.size();
  std::size_t recalled = 0;
  std::vector<double> translation, yaw;
  const PriorOutcome* first = nullptr;
  for (const PriorOutcome& o : outcomes) {
    r.prior_places += o.prior_place;
    if (o.prior_place && r.first_place_seconds < 0.0) {
      r.first_place_seconds = o.seconds;
      r.first_place_metres = o.metres;
    }
    if (o.match < 0) continue;
    if (!o.correct) {
      ++r.false_positives;
      continue;
    }
    ++r.true_positives;
    recalled += o.prior_place;
    translation.push_back(o.translation_error);
    yaw.push_back(o.yaw_error * 180.0 / M_PI);
    if (first == nullptr || o.reported_seconds < first->reported_seconds) first = &o;
  }
  const std::size_t detections = r.true_positives + r.false_positives;
  r.precision = detections > 0 ? double(r.true_positives) / double(detections) : 1.0;
  r.recall = r.prior_places > 0 ? double(recalled) / double(r.prior_places) : 0.0;
  r.translation_error_median = percentile(translation, 0.5);
  r.translation_error_p90 = percentile(translation, 0.9);
  r.yaw_error_median = percentile(yaw, 0.5);
  r.yaw_error_p90 = percentile(yaw, 0.9);
  if (first != nullptr) {
    r.first_seconds = first->reported_seconds;
    r.first_metres = first->reported_metres;
    r.first_query = first->query;
    for (const PriorOutcome& o : outcomes) {
      r.false_before_first += o.match >= 0 && !o.correct && o.reported_seconds < first->reported_seconds;
    }
  }
  return r;
}

}  // namespace eval
}  // namespace scan_context_loop
