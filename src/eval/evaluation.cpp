#include "scan_context_loop/eval/evaluation.h"

#include <cmath>
#include <fstream>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/eval/prior_map.h"
#include "scan_context_loop/eval/kitti_io.h"

namespace scan_context_loop {
namespace eval {

namespace {

double yawOf(const Eigen::Isometry3d& t) { return std::atan2(t(1, 0), t(0, 0)); }

constexpr double kConstraintMetres = 1.0, kConstraintDegrees = 2.0;

/// Feeds keyframes through the pipeline and scores the query sequence's. A prior map (when given) comes
/// first, as session 0: a prior sequence's keyframes fed through the pipeline, or a saved database's
/// joining it; it is not scored.
class SequenceScorer {
 public:
  SequenceScorer(const Config& config, double revisit_radius, Evaluation* e)
      : pipeline_(config), radius_(revisit_radius), e_(*e) {}

  /// The prior's keyframes, then a new session.
  void buildPriorMap(const Sequence& prior) {
    for (std::size_t k = 0; k < prior.frames.size(); ++k) {
      pcl::PointCloud<pcl::PointXYZI> cloud;
      const Detection d = feed(prior, k, &cloud);
      if (d.accepted) keyframes_.push_back({&prior, k});
    }
    priorMapBuilt();
    pipeline_.startSession();
  }

  /// The database's keyframes, as saved (the next keyframe begins a new session).
  bool loadPriorMap(DatabasePrior* prior, std::string* error) {
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

  void score(const Sequence& s);
  std::size_t priorKeyframes() const { return prior_count_; }
  const KeyframePipeline& pipeline() const { return pipeline_; }

 private:
  struct Keyframe {
    const Sequence* sequence;
    std::size_t k;
    const Eigen::Isometry3d& truth() const { return sequence->truth[k]; }
    int frame() const { return sequence->frames[k]; }
  };

  /// Reads and processes keyframe k; a cloud that cannot be read, or that the detector refuses, counts
  /// as rejected (Detection::accepted false).
  Detection feed(const Sequence& s, std::size_t k, pcl::PointCloud<pcl::PointXYZI>* cloud) {
    std::string error;
    if (!kitti::readScan(kitti::scanPath(s.dir, s.frames[k]), cloud, &error)) {
      e_.errors.push_back(error);
      ++e_.rejected;
      return Detection();
    }
    KeyframeInfo info;
    info.stamp = s.stamps[k];
    info.pose = s.odometry[k];
    info.tag = s.frames[k];
    Detection d = pipeline_.process(viewOf(*cloud), info);
    if (d.selected && !d.accepted) {
      e_.errors.push_back("frame " + std::to_string(s.frames[k]) + ": " + d.error);
      ++e_.rejected;
    }
    if (d.accepted) positions_.push_back(s.truth[k].translation());
    return d;
  }

  void priorMapBuilt() {
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
  bool inPrior(std::size_t index) const { return index < prior_count_; }
  PriorOutcome priorOutcome(const Sequence& s, std::size_t k) const;
  void scoreLoops(const Sequence& s, std::size_t k, const Detection& d);

  KeyframePipeline pipeline_;
  double radius_;
  bool has_prior_ = false;
  Evaluation& e_;
  std::vector<Eigen::Vector3d> positions_;  // true positions of the accepted keyframes
  std::vector<Keyframe> keyframes_;         // detector index -> sequence and keyframe
  std::size_t prior_count_ = 0;             // keyframes of the prior map
  std::vector<long> outcome_of_, prior_outcome_of_;  // detector index -> outcome, -1 for none
  std::vector<double> metres_;  // true distance along the query sequence to each keyframe
};

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
    const double pose_error = (loop.verification.relative.translation() - truth.translation()).norm();
    const double rotation_error =
        Eigen::AngleAxisd(truth.linear().transpose() * loop.verification.relative.linear()).angle();
    q.verified_correct = pose_error <= kConstraintMetres && rotation_error <= kConstraintDegrees * M_PI / 180.0;
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

void SequenceScorer::score(const Sequence& s) {
  metres_.assign(s.frames.size(), 0.0);
  for (std::size_t k = 1; k < s.frames.size(); ++k) {
    metres_[k] = metres_[k - 1] + (s.truth[k].translation() - s.truth[k - 1].translation()).norm();
  }
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    pcl::PointCloud<pcl::PointXYZI> cloud;
    const Detection d = feed(s, k, &cloud);
    if (!d.accepted) continue;  // refused, or passed over by keyframe selection
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
    if (d.index == 0) continue;  // the first keyframe has nothing to query

    QueryOutcome o;
    o.query = s.frames[k];
    o.revisit = isRevisit(positions_, d.index, d.query.eligible, radius_);
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
        a.translation_error = (v.result.relative.translation() - truth.translation()).norm();
        a.yaw_error = std::fabs(wrapAngle(yawOf(v.result.relative) - yawOf(truth)));
        a.rotation_error = Eigen::AngleAxisd(truth.linear().transpose() * v.result.relative.linear()).angle();
        e_.attempts.push_back(a);
      }
    }
    outcome_of_[d.index] = static_cast<long>(e_.outcomes.size());
    e_.outcomes.push_back(o);
    scoreLoops(s, k, d);
  }
}

}  // namespace

bool evaluate(const Sequence& s, const Config& config, const EvaluationOptions& options, Evaluation* out,
              std::string* error) {
  if (options.prior != nullptr && options.prior_database != nullptr) {
    *error = "a prior sequence and a prior database at once";
    return false;
  }
  Evaluation e;
  SequenceScorer run(config, options.revisit_radius, &e);
  if (options.prior != nullptr) {
    run.buildPriorMap(*options.prior);
    e.prior_source = options.prior->dir;
  } else if (options.prior_database != nullptr) {
    if (!run.loadPriorMap(options.prior_database, error)) return false;
    e.prior_source = options.prior_database->path;
    e.prior_truth = options.prior_database->truth_dir;
  }
  run.score(s);
  if (!options.save_database.empty()) {
    SaveOptions save;
    save.include_clouds = options.save_clouds;
    if (!saveDatabase(run.pipeline().detector(), options.save_database, save, error)) return false;
  }
  e.metrics = computeMetrics(e.outcomes, config.distance_threshold);
  e.verification = config.verification.enabled;
  if (e.verification) e.verified = computeVerifiedMetrics(e.outcomes);
  e.has_prior = options.prior != nullptr || options.prior_database != nullptr;
  if (e.has_prior) {
    e.relocalization = computeRelocalizationMetrics(e.prior_outcomes);
    e.relocalization.prior_keyframes = run.priorKeyframes();
  }
  *out = std::move(e);
  return true;
}

Evaluation evaluate(const Sequence& s, const Config& config, double revisit_radius, const Sequence* prior) {
  EvaluationOptions options;
  options.revisit_radius = revisit_radius;
  options.prior = prior;
  Evaluation e;
  std::string error;
  evaluate(s, config, options, &e, &error);  // cannot fail without a database to load or save
  return e;
}

bool writeResultsCsv(const std::string& path, const Evaluation& e, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "query,match,distance,yaw_rad,true_revisit,correct,match_gap_m,true_yaw_rad";
  if (e.verification) {
    out << ",verified,verified_match,verified_correct,candidates_verified,fitness,inlier_ratio,trans_err_m,"
           "yaw_err_rad";
  }
  // With a prior map, match frame numbers may be the prior's: these say whose.
  if (e.has_prior) out << ",match_in_prior" << (e.verification ? ",verified_in_prior" : "");
  out << '\n';
  out.precision(6);
  for (const auto& o : e.outcomes) {
    out << o.query << ',' << o.match << ',' << o.distance << ',' << o.yaw << ',' << int(o.revisit) << ','
        << int(o.correct) << ',' << o.match_gap << ',' << o.true_yaw;
    if (e.verification) {
      out << ',' << int(o.verified_match >= 0) << ',' << o.verified_match << ',' << int(o.verified_correct) << ','
          << o.candidates_verified << ',' << o.fitness << ',' << o.inlier_ratio << ',' << o.translation_error << ','
          << o.yaw_error;
    }
    if (e.has_prior) {
      out << ',' << int(o.match_in_prior);
      if (e.verification) out << ',' << int(o.verified_in_prior);
    }
    out << '\n';
  }
  return out.good();
}

bool writeMetricsJson(const std::string& path, const Evaluation& e, const Sequence& s, const Config& config,
                      double revisit_radius, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  const Metrics& m = e.metrics;
  out.precision(6);
  out << "{\n"
      << "  \"sequence\": \"" << s.dir << "\",\n"
      << "  \"keyframes\": " << s.frames.size() << ",\n"
      << "  \"missing_scans\": " << s.missing_scans << ",\n"
      << "  \"rejected_keyframes\": " << e.rejected << ",\n"
      << "  \"odometry\": \"" << (s.odometry_from_file ? "odom_poses.txt" : "poses.txt (truth)") << "\",\n"
      << "  \"revisit_radius_m\": " << revisit_radius << ",\n"
      << "  \"queries\": " << m.queries << ",\n"
      << "  \"true_revisits\": " << m.revisits << ",\n"
      << "  \"threshold\": " << m.threshold << ",\n"
      << "  \"ring_key\": \"" << ringKeyTypeName(config.ring_key) << "\",\n"
      << "  \"true_positives\": " << m.true_positives << ",\n"
      << "  \"false_positives\": " << m.false_positives << ",\n"
      << "  \"precision\": " << m.precision << ",\n"
      << "  \"recall\": " << m.recall << ",\n"
      << "  \"f1\": " << m.f1 << ",\n"
      << "  \"f1_max\": " << m.f1_max << ",\n"
      << "  \"f1_max_threshold\": " << m.f1_max_threshold << ",\n"
      << "  \"recall_at_100_precision\": " << m.recall_at_full_precision << ",\n"
      << "  \"recall_at_100_precision_threshold\": " << m.full_precision_threshold << ",\n"
      << "  \"average_precision\": " << m.average_precision << ",\n"
      << "  \"yaw_error_deg\": {\"median\": " << m.yaw_error_median << ", \"p90\": " << m.yaw_error_p90
      << ", \"max\": " << m.yaw_error_max << "},\n"
      << "  \"descriptor_ms\": {\"median\": " << percentile(e.descriptor_ms, 0.5)
      << ", \"p99\": " << percentile(e.descriptor_ms, 0.99) << "},\n"
      << "  \"query_ms\": {\"median\": " << percentile(e.query_ms, 0.5) << ", \"p99\": " << percentile(e.query_ms, 0.99)
      << "}";
  if (e.verification) {
    const VerifiedMetrics& v = e.verified;
    out << ",\n  \"verified\": {\"true_positives\": " << v.true_positives << ", \"false_positives\": "
        << v.false_positives << ", \"precision\": " << v.precision << ", \"recall\": " << v.recall
        << ", \"f1\": " << v.f1 << ", \"translation_error_m\": {\"median\": " << v.translation_error_median
        << ", \"p90\": " << v.translation_error_p90 << "}, \"yaw_error_deg\": {\"median\": " << v.yaw_error_median
        << ", \"p90\": " << v.yaw_error_p90 << "}, \"candidates_mean\": " << v.candidates_mean
        << ", \"candidates_max\": " << v.candidates_max << ", \"reported_late\": " << v.reported_late
        << ", \"correct_beyond_radius\": " << v.beyond_radius << ", \"first_candidate_right\": "
        << v.first_candidate_right << ", \"first_candidate_right_verified\": " << v.first_candidate_right_verified
        << ", \"dropped_by_consistency\": " << e.loops_dropped << ", \"verify_ms\": {\"median\": "
        << percentile(e.verify_ms, 0.5) << ", \"p99\": " << percentile(e.verify_ms, 0.99)
        << ", \"max\": " << percentile(e.verify_ms, 1.0) << "}, \"rejected_by\": {";
    // Registrations each test turned down, at the true place and elsewhere (verifications.csv has them
    // one by one); a loop the odometry contradicted may still be confirmed later.
    bool first = true;
    for (const char* test : kRejectionTests) {
      std::size_t at_place = 0, elsewhere = 0;
      for (const VerificationAttempt& a : e.attempts) {
        if (a.result.rejected_by != test) continue;
        ++(a.true_place ? at_place : elsewhere);
      }
      out << (first ? "" : ", ") << "\"" << test << "\": {\"true_place\": " << at_place << ", \"elsewhere\": " << elsewhere << "}";
      first = false;
    }
    out << "}}";
  }
  if (e.has_prior) {
    const RelocalizationMetrics& r = e.relocalization;
    out << ",\n  \"relocalization\": {\"prior\": \"" << e.prior_source << "\", ";
    if (!e.prior_truth.empty()) out << "\"prior_truth\": \"" << e.prior_truth << "\", ";
    out << "\"prior_keyframes\": " << r.prior_keyframes
        << ", \"queries\": " << r.queries << ", \"prior_places\": " << r.prior_places
        << ", \"true_positives\": " << r.true_positives << ", \"false_positives\": " << r.false_positives
        << ", \"precision\": " << r.precision << ", \"recall\": " << r.recall
        << ", \"translation_error_m\": {\"median\": " << r.translation_error_median
        << ", \"p90\": " << r.translation_error_p90 << "}, \"yaw_error_deg\": {\"median\": " << r.yaw_error_median
        << ", \"p90\": " << r.yaw_error_p90 << "}, \"first_correct\": {\"query\": " << r.first_query
        << ", \"seconds\": " << r.first_seconds << ", \"metres\": " << r.first_metres
        << ", \"false_before\": " << r.false_before_first << "}, \"first_prior_place\": {\"seconds\": "
        << r.first_place_seconds << ", \"metres\": " << r.first_place_metres << "}}";
  }
  out << "\n}\n";
  return out.good();
}

bool writeVerificationsCsv(const std::string& path, const Evaluation& e, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "query,match,distance,gap_m,accepted,overlap_query,overlap_match,violation,fitness,constraint_ratio,coarse_score,"
         "hypotheses,trans_err_m,yaw_err_deg,rot_err_deg,tilt_deg,column_overlap_query,column_overlap_match,ms,"
         "rejected_by,rejection_value,rejection_limit,reason\n";
  out.precision(6);
  for (const auto& a : e.attempts) {
    const VerificationResult& r = a.result;
    std::string reason = r.reason;
    for (char& c : reason) if (c == ',' || c == '"') c = ';';
    out << a.query << ',' << a.match << ',' << a.distance << ',' << a.gap << ',' << int(r.accepted) << ','
        << r.overlap_query << ',' << r.overlap_match << ',' << r.violation << ',' << r.fitness << ','
        << r.constraint_ratio << ',' << r.coarse_score << ',' << r.hypotheses << ',' << a.translation_error << ','
        << a.yaw_error * 180.0 / M_PI << ',' << a.rotation_error * 180.0 / M_PI << ',' << r.tilt_deg << ','
        << r.column_overlap_query << ',' << r.column_overlap_match << ',' << r.seconds * 1e3 << ',' << r.rejected_by << ',' << r.rejection_value
        << ',' << r.rejection_limit << ',' << reason << '\n';
  }
  return out.good();
}

bool writeRelocalizationCsv(const std::string& path, const Evaluation& e, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "query,seconds,metres,nearest_prior,nearest_gap_m,nearest_yaw_deg,prior_place,match,correct,trans_err_m,"
         "yaw_err_deg,reported_seconds\n";
  out.precision(6);
  for (const PriorOutcome& o : e.prior_outcomes) {
    out << o.query << ',' << o.seconds << ',' << o.metres << ',' << o.nearest << ',' << o.nearest_gap << ','
        << o.nearest_yaw * 180.0 / M_PI << ',' << int(o.prior_place) << ',' << o.match << ',' << int(o.correct) << ','
        << o.translation_error << ',' << o.yaw_error * 180.0 / M_PI << ',' << o.reported_seconds << '\n';
  }
  return out.good();
}

bool writeTrajectoryCsv(const std::string& path, const Sequence& s, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "frame,x,y,z\n";
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const auto t = s.truth[k].translation();
    out << s.frames[k] << ',' << t.x() << ',' << t.y() << ',' << t.z() << '\n';
  }
  return out.good();
}

}  // namespace eval
}  // namespace scan_context_loop
