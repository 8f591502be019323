#include "scan_context_loop/eval/sequence_scorer.h"

#include <cmath>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_loop/eval/prior_map.h"

namespace scan_context_loop {
namespace eval {

double yawOf(const Eigen::Isometry3d& t) { return std::atan2(t(1, 0), t(0, 0)); }

void constraintError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth, double* translation,
                     double* rotation) {
  *translation = (estimate.translation() - truth.translation()).norm();
  *rotation = Eigen::AngleAxisd(truth.linear().transpose() * estimate.linear()).angle();
}

bool correctConstraint(double translation_error, double rotation_error) {
  return translation_error <= kConstraintMetres && rotation_error <= kConstraintDegrees * M_PI / 180.0;
}

void SequenceScorer::buildPriorMap(const Sequence& prior) {
  for (std::size_t k = 0; k < prior.frames.size(); ++k) {
    const Detection d = feed(prior, k, nullptr);
    if (d.accepted) keyframes_.push_back({&prior, k});
  }
  priorMapBuilt();
  pipeline_.startSession();
}

bool SequenceScorer::loadPriorMap(DatabasePrior* prior, std::string* error) {
  if (!pipeline_.appendSessions(std::move(prior->sessions), error)) {
    *error = prior->path + ": " + *error;
    return false;
  }
  const Sequence& s = prior->keyframes;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    keyframes_.push_back({&s, k});
    positions_.push_back(s.truth[k].translation());
  }
  priorMapBuilt();
  return true;
}

Detection SequenceScorer::feed(const Sequence& s, std::size_t k, pcl::PointCloud<pcl::PointXYZ>* described) {
  PointView cloud;
  std::string error;
  if (!kitti::readScan(kitti::scanPath(s.dir, s.frames[k]), &scan_buffer_, &cloud, &error)) {
    e_.errors.push_back(error);
    ++e_.rejected;
    return Detection();
  }
  KeyframeInfo info;
  info.stamp = s.stamps[k];
  info.pose = s.odometry[k];
  info.tag = s.frames[k];
  Detection d = pipeline_.process(cloud, info, described);
  if (d.selected && !d.accepted) {
    e_.errors.push_back("frame " + std::to_string(s.frames[k]) + ": " + d.error);
    ++e_.rejected;
  }
  if (d.accepted) positions_.push_back(s.truth[k].translation());
  return d;
}

void SequenceScorer::priorMapBuilt() {
  prior_count_ = keyframes_.size();
  has_prior_ = true;
  Sequence& stored = e_.prior_keyframes;
  for (const Keyframe& kf : keyframes_) {
    stored.dir = kf.sequence->dir;
    stored.odometry_from_file = kf.sequence->odometry_from_file;
    stored.frames.push_back(kf.frame());
    stored.truth.push_back(kf.truth());
    stored.odometry.push_back(kf.sequence->odometry[kf.k]);
    stored.stamps.push_back(kf.sequence->stamps[kf.k]);
  }
}

PriorOutcome SequenceScorer::priorOutcome(const Sequence& s, std::size_t k) const {
  PriorOutcome o;
  o.query = s.frames[k];
  o.seconds = s.stamps[k] - s.stamps.front();
  o.metres = metres_[k];
  double nearest = 1e300;
  for (std::size_t i = 0; i < prior_count_; ++i) {
    const double gap = (positions_[i] - s.truth[k].translation()).norm();
    if (gap >= nearest) continue;
    nearest = gap;
    o.nearest = keyframes_[i].frame();
    o.nearest_yaw = yawOf(s.truth[k].inverse() * keyframes_[i].truth());
  }
  o.nearest_gap = o.nearest >= 0 ? nearest : -1.0;
  o.prior_place = o.nearest >= 0 && nearest < radius_;
  return o;
}

void SequenceScorer::scoreLoops(const Sequence& s, std::size_t k, const Detection& d) {
  // Loops may be reported a few keyframes after their query (consistency check): score each one on
  // its own query's outcome.
  e_.loops_dropped += d.dropped.size();
  e_.loops.insert(e_.loops.end(), d.loops.begin(), d.loops.end());
  if (!d.verifications_enabled) return;
  for (const Loop& loop : d.loops) {
    if (loop.query >= outcome_of_.size() || outcome_of_[loop.query] < 0) continue;
    QueryOutcome& q = e_.outcomes[outcome_of_[loop.query]];
    const Keyframe& query = keyframes_[loop.query];
    const Keyframe& match = keyframes_[loop.match];
    const Eigen::Isometry3d truth = query.truth().inverse() * match.truth();
    q.verified_match = match.frame();
    q.verified_in_prior = inPrior(loop.match);
    // A verified loop is a constraint: it is correct when its pose is (within 1 m and 2 deg of the
    // truth), however far apart the keyframes are; one between places within the revisit radius with
    // a wrong pose is a false constraint all the same.
    double pose_error = 0.0, rotation_error = 0.0;
    constraintError(loop.verification.relative, truth, &pose_error, &rotation_error);
    q.verified_correct = correctConstraint(pose_error, rotation_error);
    q.verified_beyond_radius = truth.translation().norm() >= radius_;
    q.fitness = loop.verification.fitness;
    q.inlier_ratio = loop.verification.inlier_ratio;
    q.translation_error = pose_error;
    q.yaw_error = std::fabs(wrapAngle(yawOf(loop.verification.relative) - yawOf(truth)));
    q.reported_late = loop.query != d.index;
    if (!q.verified_in_prior) continue;
    PriorOutcome& r = e_.prior_outcomes[prior_outcome_of_[loop.query]];
    r.match = q.verified_match;
    r.correct = q.verified_correct;
    r.translation_error = q.translation_error;
    r.yaw_error = q.yaw_error;
    r.reported_seconds = s.stamps[k] - s.stamps.front();
    r.reported_metres = metres_[k];
  }
}

void SequenceScorer::begin(const Sequence& s) {
  metres_.assign(s.frames.size(), 0.0);
  for (std::size_t k = 1; k < s.frames.size(); ++k) {
    metres_[k] = metres_[k - 1] + (s.truth[k].translation() - s.truth[k - 1].translation()).norm();
  }
}

void SequenceScorer::score(const Sequence& s) {
  begin(s);
  for (std::size_t k = 0; k < s.frames.size(); ++k) step(s, k);
}

Detection SequenceScorer::step(const Sequence& s, std::size_t k, pcl::PointCloud<pcl::PointXYZ>* described) {
  const Detection d = feed(s, k, described);
  if (!d.accepted) return d;  // refused, or passed over by keyframe selection
  e_.descriptor_ms.push_back(d.descriptor_seconds * 1e3);
  e_.query_ms.push_back(d.query_seconds * 1e3);
  keyframes_.push_back({&s, k});
  e_.keyframe_of.resize(d.index + 1, -1);
  e_.keyframe_of[d.index] = static_cast<long>(k);
  outcome_of_.resize(d.index + 1, -1);
  prior_outcome_of_.resize(d.index + 1, -1);
  if (has_prior_) {
    prior_outcome_of_[d.index] = static_cast<long>(e_.prior_outcomes.size());
    e_.prior_outcomes.push_back(priorOutcome(s, k));
  }
  if (d.index == 0) return d;  // the first keyframe has nothing to query

  QueryOutcome o;
  o.query = s.frames[k];
  o.revisit_index = nearestRevisit(positions_, d.index, d.query.eligible, radius_);
  o.revisit = o.revisit_index >= 0;
  if (const Candidate* best = d.query.best()) {
    const Keyframe& m = keyframes_[best->index];
    o.match = m.frame();
    o.match_in_prior = inPrior(best->index);
    o.distance = best->alignment.distance;
    o.yaw = best->alignment.yaw;
    o.match_gap = (m.truth().translation() - s.truth[k].translation()).norm();
    o.correct = o.match_gap < radius_;
    o.true_yaw = yawOf(s.truth[k].inverse() * m.truth());
  }
  if (d.verifications_enabled) {
    e_.verify_ms.push_back(d.verify_seconds * 1e3);
    o.candidates_verified = static_cast<int>(d.verifications.size());
    for (const VerifiedCandidate& v : d.verifications) {
      const Keyframe& m = keyframes_[v.index];
      const Eigen::Isometry3d truth = s.truth[k].inverse() * m.truth();
      VerificationAttempt a;
      a.query = s.frames[k];
      a.match = m.frame();
      a.distance = v.alignment.distance;
      a.gap = truth.translation().norm();
      a.true_place = a.gap < radius_;
      a.result = v.result;
      constraintError(v.result.relative, truth, &a.translation_error, &a.rotation_error);
      a.yaw_error = std::fabs(wrapAngle(yawOf(v.result.relative) - yawOf(truth)));
      e_.attempts.push_back(a);
    }
  }
  outcome_of_[d.index] = static_cast<long>(e_.outcomes.size());
  e_.outcomes.push_back(o);
  scoreLoops(s, k, d);
  return d;
}

void finishEvaluation(const Config& config, Evaluation* e) {
  e->metrics = computeMetrics(e->outcomes, config.distance_threshold);
  e->verification = config.verification.enabled;
  if (e->verification) e->verified = computeVerifiedMetrics(e->outcomes);
  if (e->has_prior) e->relocalization = computeRelocalizationMetrics(e->prior_outcomes);
}

}  // namespace eval
}  // namespace scan_context_loop
