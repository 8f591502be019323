#include "scan_context_loop/eval/metrics.h"

#include <algorithm>
#include <cmath>

#include "scan_context_loop/core/alignment.h"

namespace scan_context_loop {
namespace eval {

bool isRevisit(const std::vector<Eigen::Vector3d>& positions, std::size_t query, std::size_t eligible, double radius) {
  return nearestRevisit(positions, query, eligible, radius) >= 0;
}

long nearestRevisit(const std::vector<Eigen::Vector3d>& positions, std::size_t query, std::size_t eligible,
                    double radius) {
  const std::size_t end = std::min(eligible, query);
  long nearest = -1;
  double best = radius;
  for (std::size_t i = 0; i < end; ++i) {
    const double gap = (positions[i] - positions[query]).norm();
    if (gap < best) {
      best = gap;
      nearest = static_cast<long>(i);
    }
  }
  return nearest;
}

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(fraction * values.size()));
  return values[std::min(values.size() - 1, rank == 0 ? 0 : rank - 1)];
}

namespace {

struct Counts {
  std::size_t tp = 0, fp = 0;
};

Counts countBelow(const std::vector<QueryOutcome>& outcomes, double threshold) {
  Counts c;
  for (const auto& o : outcomes) {
    if (o.match < 0 || !(o.distance < threshold)) continue;
    (o.correct ? c.tp : c.fp) += 1;
  }
  return c;
}

double f1(double p, double r) { return p + r > 0.0 ? 2.0 * p * r / (p + r) : 0.0; }

}  // namespace

Metrics computeMetrics(const std::vector<QueryOutcome>& outcomes, double threshold) {
  Metrics m;
  m.queries = outcomes.size();
  m.threshold = threshold;
  for (const auto& o : outcomes) m.revisits += o.revisit;
  const auto precision = [](const Counts& c) { return c.tp + c.fp > 0 ? double(c.tp) / double(c.tp + c.fp) : 1.0; };
  const auto recall = [&](const Counts& c) { return m.revisits > 0 ? double(c.tp) / double(m.revisits) : 0.0; };

  const Counts at = countBelow(outcomes, threshold);
  m.true_positives = at.tp;
  m.false_positives = at.fp;
  m.precision = precision(at);
  m.recall = recall(at);
  m.f1 = f1(m.precision, m.recall);

  // Sweep: detections in order of distance; equal distances enter together.
  std::vector<const QueryOutcome*> sorted;
  for (const auto& o : outcomes) {
    if (o.match >= 0 && std::isfinite(o.distance)) sorted.push_back(&o);
  }
  std::sort(sorted.begin(), sorted.end(),
            [](const QueryOutcome* a, const QueryOutcome* b) { return a->distance < b->distance; });
  Counts c;
  double previous_recall = 0.0;
  for (std::size_t i = 0; i < sorted.size();) {
    const double d = sorted[i]->distance;
    for (; i < sorted.size() && sorted[i]->distance == d; ++i) (sorted[i]->correct ? c.tp : c.fp) += 1;
    const double t = std::nextafter(d, 1e300);  // "below t" includes d
    const PrPoint point{t, precision(c), recall(c)};
    m.curve.push_back(point);
    m.average_precision += (point.recall - previous_recall) * point.precision;
    previous_recall = point.recall;
    const double f = f1(point.precision, point.recall);
    if (f > m.f1_max) {
      m.f1_max = f;
      m.f1_max_threshold = t;
    }
    if (c.fp == 0 && point.recall > m.recall_at_full_precision) {
      m.recall_at_full_precision = point.recall;
      m.full_precision_threshold = t;
    }
  }

  std::vector<double> yaw_errors;
  for (const auto& o : outcomes) {
    if (o.match >= 0 && o.correct && o.distance < threshold) {
      yaw_errors.push_back(std::fabs(wrapAngle(o.yaw - o.true_yaw)) * 180.0 / M_PI);
    }
  }
  m.yaw_error_median = percentile(yaw_errors, 0.5);
  m.yaw_error_p90 = percentile(yaw_errors, 0.9);
  m.yaw_error_max = percentile(yaw_errors, 1.0);
  return m;
}

VerifiedMetrics computeVerifiedMetrics(const std::vector<QueryOutcome>& outcomes) {
  VerifiedMetrics v;
  std::size_t revisits = 0, candidates = 0, recalled = 0;
  std::vector<double> translation, yaw;
  for (const auto& o : outcomes) {
    revisits += o.revisit;
    candidates += o.candidates_verified;
    v.candidates_max = std::max(v.candidates_max, o.candidates_verified);
    const bool first_right = o.revisit && o.correct;
    v.first_candidate_right += first_right;
    if (o.verified_match < 0) continue;
    v.first_candidate_right_verified += first_right && o.verified_correct;
    v.reported_late += o.reported_late;
    if (!o.verified_correct) {
      ++v.false_positives;
      continue;
    }
    ++v.true_positives;
    recalled += o.revisit;
    v.beyond_radius += o.verified_beyond_radius;
    translation.push_back(o.translation_error);
    yaw.push_back(o.yaw_error * 180.0 / M_PI);
  }
  const std::size_t detections = v.true_positives + v.false_positives;
  v.precision = detections > 0 ? double(v.true_positives) / detections : 1.0;
  // Recall counts the revisit queries a correct loop was found for.
  v.recall = revisits > 0 ? double(recalled) / revisits : 0.0;
  v.f1 = f1(v.precision, v.recall);
  v.translation_error_median = percentile(translation, 0.5);
  v.translation_error_p90 = percentile(translation, 0.9);
  v.yaw_error_median = percentile(yaw, 0.5);
  v.yaw_error_p90 = percentile(yaw, 0.9);
  v.candidates_mean = outcomes.empty() ? 0.0 : double(candidates) / outcomes.size();
  return v;
}

}  // namespace eval
}  // namespace scan_context_loop
