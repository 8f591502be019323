#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/metrics.h"
#include "scan_context_loop/eval/relocalization.h"

namespace scan_context_loop {
namespace eval {
namespace {

QueryOutcome outcome(double distance, bool revisit, bool correct, int match = 1) {
  QueryOutcome o;
  o.query = 10;
  o.match = match;
  o.distance = distance;
  o.revisit = revisit;
  o.correct = correct;
  return o;
}

TEST(Metrics, HandComputedSweep) {
  // Sorted by distance: TP, TP, FP (not a revisit), TP, FP (wrong match on a revisit), TP; plus a
  // revisit with no candidate and a non-revisit far away. Revisits: 5 TP-able + wrong-match + none = 7.
  const std::vector<QueryOutcome> o = {
      outcome(0.05, true, true),     outcome(0.10, true, true),  outcome(0.15, false, false),
      outcome(0.20, true, true),     outcome(0.25, true, false), outcome(0.30, true, true),
      outcome(1.0, true, false, -1), outcome(0.9, false, false), outcome(0.35, true, true)};
  const Metrics m = computeMetrics(o, 0.22);
  EXPECT_EQ(m.queries, 9u);
  EXPECT_EQ(m.revisits, 7u);
  // Below 0.22: 0.05 TP, 0.10 TP, 0.15 FP, 0.20 TP.
  EXPECT_EQ(m.true_positives, 3u);
  EXPECT_EQ(m.false_positives, 1u);
  EXPECT_DOUBLE_EQ(m.precision, 0.75);
  EXPECT_DOUBLE_EQ(m.recall, 3.0 / 7.0);
  // Recall at 100% precision: the first two detections.
  EXPECT_DOUBLE_EQ(m.recall_at_full_precision, 2.0 / 7.0);
  EXPECT_GT(m.full_precision_threshold, 0.10);
  EXPECT_LE(m.full_precision_threshold, 0.15);
  // Curve points (P, R): (1, 1/7) (1, 2/7) (2/3, 2/7) (3/4, 3/7) (3/5, 3/7) (2/3, 4/7) (5/7, 5/7) (5/8, 5/7)
  ASSERT_EQ(m.curve.size(), 8u);
  EXPECT_DOUBLE_EQ(m.curve[6].precision, 5.0 / 7.0);
  const double ap = (1.0 / 7) * 1 + (1.0 / 7) * 1 + (1.0 / 7) * 0.75 + (1.0 / 7) * (2.0 / 3) + (1.0 / 7) * (5.0 / 7);
  EXPECT_NEAR(m.average_precision, ap, 1e-12);
  // F1: best at (5/7, 5/7) = 5/7, reached when 0.35 enters.
  EXPECT_NEAR(m.f1_max, 5.0 / 7.0, 1e-12);
  EXPECT_GT(m.f1_max_threshold, 0.35);
  EXPECT_LT(m.f1_max_threshold, 0.36);
}

TEST(Metrics, TiesEnterTogetherAndEmptyCasesAreDefined) {
  const std::vector<QueryOutcome> tied = {outcome(0.1, true, true), outcome(0.1, false, false)};
  const Metrics m = computeMetrics(tied, 0.5);
  ASSERT_EQ(m.curve.size(), 1u);
  EXPECT_DOUBLE_EQ(m.curve[0].precision, 0.5);
  EXPECT_DOUBLE_EQ(m.recall_at_full_precision, 0.0);

  const Metrics none = computeMetrics({}, 0.2);
  EXPECT_EQ(none.queries, 0u);
  EXPECT_DOUBLE_EQ(none.precision, 1.0);
  EXPECT_DOUBLE_EQ(none.recall, 0.0);
  EXPECT_DOUBLE_EQ(none.average_precision, 0.0);

  // No revisits at all: every detection is a false positive, recall stays 0.
  const Metrics no_revisits = computeMetrics({outcome(0.1, false, false)}, 0.2);
  EXPECT_EQ(no_revisits.false_positives, 1u);
  EXPECT_DOUBLE_EQ(no_revisits.precision, 0.0);
  EXPECT_DOUBLE_EQ(no_revisits.recall, 0.0);
  EXPECT_DOUBLE_EQ(no_revisits.f1_max, 0.0);
}

TEST(Metrics, YawErrorOverTruePositivesOnly) {
  std::vector<QueryOutcome> o;
  for (double err_deg : {1.0, -2.0, 3.0, 170.0}) {
    QueryOutcome q = outcome(0.1, true, true);
    q.true_yaw = 3.0;  // near +pi: errors wrap
    q.yaw = 3.0 + err_deg * M_PI / 180.0;
    o.push_back(q);
  }
  o.back().correct = false;  // the 170-degree one is a wrong match and does not count
  const Metrics m = computeMetrics(o, 0.2);
  EXPECT_NEAR(m.yaw_error_median, 2.0, 1e-9);
  EXPECT_NEAR(m.yaw_error_max, 3.0, 1e-9);
}

TEST(GroundTruth, RevisitNeedsAnEligibleKeyframeWithinTheRadius) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {10, 0, 0}, {20, 0, 0}, {10, 3, 0}, {10, 4.5, 0}};
  EXPECT_TRUE(isRevisit(p, 3, 3, 5.0));   // keyframe 1 is 3 m away and eligible
  EXPECT_FALSE(isRevisit(p, 3, 1, 5.0));  // only keyframe 0 is eligible: 10.4 m away
  EXPECT_FALSE(isRevisit(p, 3, 3, 2.0));  // radius too small
  EXPECT_TRUE(isRevisit(p, 4, 4, 5.0));
  EXPECT_FALSE(isRevisit(p, 0, 0, 5.0));
  // The partner is the nearest eligible keyframe: keyframe 3 (1.5 m), not keyframe 1 (4.5 m).
  EXPECT_EQ(nearestRevisit(p, 4, 4, 5.0), 3);
  EXPECT_EQ(nearestRevisit(p, 4, 3, 5.0), 1);
  EXPECT_EQ(nearestRevisit(p, 3, 1, 5.0), -1);
  EXPECT_DOUBLE_EQ(percentile({5, 1, 3, 2, 4}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(percentile({5, 1, 3, 2, 4}, 1.0), 5.0);
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop

namespace scan_context_loop {
namespace eval {
namespace {

TEST(VerifiedMetrics, HandComputed) {
  std::vector<QueryOutcome> o(6);
  for (auto& q : o) q.revisit = true;
  o[0].verified_match = 3;  // true positive
  o[0].verified_correct = true;
  o[0].translation_error = 0.1;
  o[0].yaw_error = 1.0 * M_PI / 180.0;
  o[0].candidates_verified = 1;
  o[1].verified_match = 4;  // true positive
  o[1].verified_correct = true;
  o[1].translation_error = 0.3;
  o[1].yaw_error = 3.0 * M_PI / 180.0;
  o[1].candidates_verified = 2;
  o[2].verified_match = 9;  // wrong place
  o[2].candidates_verified = 2;
  o[3].candidates_verified = 1;  // verified, none accepted
  o[4].revisit = false;          // nothing verified
  // A correct constraint between keyframes beyond the revisit radius, on a query that is no revisit:
  // a true positive for precision, nothing for recall.
  o[5].revisit = false;
  o[5].verified_match = 7;
  o[5].verified_correct = true;
  o[5].verified_beyond_radius = true;
  o[5].translation_error = 0.2;
  const VerifiedMetrics v = computeVerifiedMetrics(o);
  EXPECT_EQ(v.true_positives, 3u);
  EXPECT_EQ(v.false_positives, 1u);
  EXPECT_EQ(v.beyond_radius, 1u);
  EXPECT_DOUBLE_EQ(v.precision, 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(v.recall, 2.0 / 4.0);
  EXPECT_DOUBLE_EQ(v.translation_error_median, 0.2);
  EXPECT_DOUBLE_EQ(v.translation_error_p90, 0.3);
  EXPECT_NEAR(v.yaw_error_p90, 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(v.candidates_mean, 6.0 / 6.0);
  EXPECT_EQ(v.candidates_max, 2);
  EXPECT_EQ(v.first_candidate_right, 0u);
}

TEST(VerifiedMetrics, WhatVerificationKeepsOfTheRightFirstCandidates) {
  std::vector<QueryOutcome> o(5);
  for (auto& q : o) q.revisit = q.correct = true;  // the descriptor put the right place first
  o[0].verified_match = o[1].verified_match = 2;
  o[0].verified_correct = true;
  o[1].verified_correct = false;  // registered wrong: not kept
  o[3].correct = false;           // the first candidate was elsewhere; verified through another one
  o[3].verified_match = 1;
  o[3].verified_correct = true;
  o[4].revisit = false;  // no revisit: the best candidate cannot be the right place
  const VerifiedMetrics v = computeVerifiedMetrics(o);
  EXPECT_EQ(v.first_candidate_right, 3u);
  EXPECT_EQ(v.first_candidate_right_verified, 1u);
}

TEST(RelocalizationMetrics, HandComputed) {
  std::vector<PriorOutcome> o(6);
  for (std::size_t i = 0; i < o.size(); ++i) {
    o[i].query = static_cast<int>(i);
    o[i].seconds = o[i].reported_seconds = static_cast<double>(i);
    o[i].metres = o[i].reported_metres = 10.0 * i;
    o[i].prior_place = i >= 1;
  }
  o[1].match = 40;  // wrong, before the first true one
  o[2].match = 41;  // true, reported late: after query 3's
  o[2].correct = true;
  o[2].translation_error = 0.05;
  o[2].yaw_error = 0.1 * M_PI / 180.0;
  o[2].reported_seconds = 3.5;
  o[2].reported_metres = 35.0;
  o[3].match = 42;  // the first true one reported
  o[3].correct = true;
  o[3].translation_error = 0.01;
  o[3].yaw_error = 0.3 * M_PI / 180.0;
  o[0].match = 43;  // true, but no prior place within the radius: precision only
  o[0].correct = true;
  o[0].translation_error = 0.02;
  o[0].reported_seconds = 5.0;
  const RelocalizationMetrics r = computeRelocalizationMetrics(o);
  EXPECT_EQ(r.queries, 6u);
  EXPECT_EQ(r.prior_places, 5u);
  EXPECT_EQ(r.true_positives, 3u);
  EXPECT_EQ(r.false_positives, 1u);
  EXPECT_DOUBLE_EQ(r.precision, 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(r.recall, 2.0 / 5.0);
  EXPECT_DOUBLE_EQ(r.translation_error_median, 0.02);
  EXPECT_DOUBLE_EQ(r.translation_error_p90, 0.05);
  EXPECT_NEAR(r.yaw_error_p90, 0.3, 1e-9);
  EXPECT_EQ(r.first_query, 3);
  EXPECT_DOUBLE_EQ(r.first_seconds, 3.0);
  EXPECT_DOUBLE_EQ(r.first_metres, 30.0);
  EXPECT_EQ(r.false_before_first, 1u);
  EXPECT_DOUBLE_EQ(r.first_place_seconds, 1.0);
  EXPECT_DOUBLE_EQ(r.first_place_metres, 10.0);

  const RelocalizationMetrics none = computeRelocalizationMetrics({PriorOutcome()});
  EXPECT_DOUBLE_EQ(none.precision, 1.0);
  EXPECT_DOUBLE_EQ(none.recall, 0.0);
  EXPECT_EQ(none.first_query, -1);
  EXPECT_DOUBLE_EQ(none.first_seconds, -1.0);
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop
