#include "scan_context_loop/eval/evaluation.h"

#include <sys/resource.h>

#include <cmath>
#include <fstream>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/eval/prior_map.h"
#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_loop/eval/sequence_scorer.h"

namespace scan_context_loop {
namespace eval {

double processCpuSeconds() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * t.tv_usec; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

bool evaluate(const Sequence& s, const Config& config, const EvaluationOptions& options, Evaluation* out,
              std::string* error) {
  if (options.prior != nullptr && options.prior_database != nullptr) {
    *error = "a prior sequence and a prior database at once";
    return false;
  }
  Evaluation e;
  KeyframePipeline pipeline(config);
  SequenceScorer run(&pipeline, options.revisit_radius, &e);
  if (options.prior != nullptr) {
    run.buildPriorMap(*options.prior);
    e.prior_source = options.prior->dir;
  } else if (options.prior_database != nullptr) {
    if (!run.loadPriorMap(options.prior_database, error)) return false;
    e.prior_source = options.prior_database->path;
    e.prior_truth = options.prior_database->truth_dir;
  }
  const double cpu_before = processCpuSeconds();
  run.score(s);
  e.cpu_seconds = processCpuSeconds() - cpu_before;
  if (!options.save_database.empty()) {
    SaveOptions save;
    save.include_clouds = options.save_clouds;
    if (!saveDatabase(run.pipeline().detector(), options.save_database, save, error)) return false;
  }
  e.has_prior = options.prior != nullptr || options.prior_database != nullptr;
  finishEvaluation(config, &e);
  if (e.has_prior) e.relocalization.prior_keyframes = run.priorKeyframes();
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
      << "  \"cpu_ms_per_keyframe\": "
      << (e.descriptor_ms.empty() ? 0.0 : 1e3 * e.cpu_seconds / static_cast<double>(e.descriptor_ms.size())) << ",\n"
      << "  \"descriptor_ms\": {\"median\": " << percentile(e.descriptor_ms, 0.5)
      << ", \"p99\": " << percentile(e.descriptor_ms, 0.99) << "},\n"
      << "  \"query_ms\": {\"median\": " << percentile(e.query_ms, 0.5) << ", \"p99\": " << percentile(e.query_ms, 0.99)
      << "}";
  if (e.verification) {
    const VerifiedMetrics& v = e.verified;
    out << ",\n  \"verified\": {\"true_positives\": " << v.true_positives
        << ", \"false_positives\": " << v.false_positives << ", \"precision\": " << v.precision
        << ", \"recall\": " << v.recall << ", \"f1\": " << v.f1
        << ", \"translation_error_m\": {\"median\": " << v.translation_error_median
        << ", \"p90\": " << v.translation_error_p90 << "}, \"yaw_error_deg\": {\"median\": " << v.yaw_error_median
        << ", \"p90\": " << v.yaw_error_p90 << "}, \"candidates_mean\": " << v.candidates_mean
        << ", \"candidates_max\": " << v.candidates_max << ", \"reported_late\": " << v.reported_late
        << ", \"correct_beyond_radius\": " << v.beyond_radius
        << ", \"first_candidate_right\": " << v.first_candidate_right
        << ", \"first_candidate_right_verified\": " << v.first_candidate_right_verified
        << ", \"dropped_by_consistency\": " << e.loops_dropped
        << ", \"verify_ms\": {\"median\": " << percentile(e.verify_ms, 0.5)
        << ", \"p99\": " << percentile(e.verify_ms, 0.99) << ", \"max\": " << percentile(e.verify_ms, 1.0)
        << "}, \"rejected_by\": {";
    // Registrations each test turned down, at the true place and elsewhere (verifications.csv has them
    // one by one); a loop the odometry contradicted may still be confirmed later.
    bool first = true;
    for (const char* test : kRejectionTests) {
      std::size_t at_place = 0, elsewhere = 0;
      for (const VerificationAttempt& a : e.attempts) {
        if (a.result.rejected_by != test) continue;
        ++(a.true_place ? at_place : elsewhere);
      }
      out << (first ? "" : ", ") << "\"" << test << "\": {\"true_place\": " << at_place
          << ", \"elsewhere\": " << elsewhere << "}";
      first = false;
    }
    out << "}}";
  }
  if (e.has_prior) {
    const RelocalizationMetrics& r = e.relocalization;
    out << ",\n  \"relocalization\": {\"prior\": \"" << e.prior_source << "\", ";
    if (!e.prior_truth.empty()) out << "\"prior_truth\": \"" << e.prior_truth << "\", ";
    out << "\"prior_keyframes\": " << r.prior_keyframes << ", \"queries\": " << r.queries
        << ", \"prior_places\": " << r.prior_places << ", \"true_positives\": " << r.true_positives
        << ", \"false_positives\": " << r.false_positives << ", \"precision\": " << r.precision
        << ", \"recall\": " << r.recall << ", \"translation_error_m\": {\"median\": " << r.translation_error_median
        << ", \"p90\": " << r.translation_error_p90 << "}, \"yaw_error_deg\": {\"median\": " << r.yaw_error_median
        << ", \"p90\": " << r.yaw_error_p90 << "}, \"first_correct\": {\"query\": " << r.first_query
        << ", \"seconds\": " << r.first_seconds << ", \"metres\": " << r.first_metres
        << ", \"false_before\": " << r.false_before_first
        << "}, \"first_prior_place\": {\"seconds\": " << r.first_place_seconds
        << ", \"metres\": " << r.first_place_metres << "}}";
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
  out << "query,match,distance,gap_m,accepted,overlap_query,overlap_match,violation,fitness,constraint_ratio,coarse_"
         "score,"
         "hypotheses,trans_err_m,yaw_err_deg,rot_err_deg,tilt_deg,column_overlap_query,column_overlap_match,ms,"
         "rejected_by,rejection_value,rejection_limit,reason\n";
  out.precision(6);
  for (const auto& a : e.attempts) {
    const VerificationResult& r = a.result;
    std::string reason = r.reason;
    for (char& c : reason)
      if (c == ',' || c == '"') c = ';';
    out << a.query << ',' << a.match << ',' << a.distance << ',' << a.gap << ',' << int(r.accepted) << ','
        << r.overlap_query << ',' << r.overlap_match << ',' << r.violation << ',' << r.fitness << ','
        << r.constraint_ratio << ',' << r.coarse_score << ',' << r.hypotheses << ',' << a.translation_error << ','
        << a.yaw_error * 180.0 / M_PI << ',' << a.rotation_error * 180.0 / M_PI << ',' << r.tilt_deg << ','
        << r.column_overlap_query << ',' << r.column_overlap_match << ',' << r.seconds * 1e3 << ',' << r.rejected_by
        << ',' << r.rejection_value << ',' << r.rejection_limit << ',' << reason << '\n';
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
