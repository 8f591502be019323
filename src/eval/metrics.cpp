#include "scan_context_loop/eval/metrics.h"

#include <algorithm>
#include <cmath>

#include "scan_context_loop/alignment.h"

namespace scan_context_loop {
namespace eval {

bool isRevisit(const std::vector<Eigen::Vector3d>& positions, std::size_t query, std::size_t eligible, double radius) {
  const std::size_t end = std::min(eligible, query);
  for (std::size_t i = 0; i < end; ++i) {
    if ((positions[i] - positions[query]).norm() < radius) return true;
  }
  return false;
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
  std::sort(sorted.begin(), sorted.end(), [](const QueryOutcome* a, const QueryOutcome* b) { return a->distance < b->distance; });
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

}  // namespace eval
}  // namespace scan_context_loop
