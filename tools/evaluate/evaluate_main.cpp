// scan_context_evaluate: runs the detector online over a KITTI-format sequence and scores it.
#include <cstdio>
#include <string>
#include <vector>

#include "scan_context_loop/eval/config_file.h"
#include "scan_context_loop/eval/prior_map.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/graph_study.h"
#include "scan_context_loop/eval/trajectory_correction.h"
#include "cli.h"
#include "evaluate_team.h"

namespace scl = scan_context_loop;
namespace eval = scan_context_loop::eval;

int main(int argc, char** argv) {
  std::string sequence_dir, out_dir, error;
  scl::Config config;
  eval::SequenceOptions options;
  double radius = 5.0;
  std::vector<std::string> overrides;
  std::string config_file, prior_path, prior_truth, save_database, save_map, graph_study;
  bool save_clouds = false, team = false;
  scl::cli::Parser cli(
      "scan_context_evaluate",
      "Runs the Scan Context detector frame by frame over a KITTI-format sequence (velodyne/*.bin, "
      "poses.txt, calib.txt, optional times.txt and odom_poses.txt) through the node's own code "
      "(KeyframePipeline), and writes OUT_DIR/results.csv, metrics.json and trajectory.csv (scripts/evaluate adds "
      "pr.png and "
      "map.png); with verification also verifications.csv, one row per candidate registered, scored "
      "against the truth; with --prior also relocalization.csv; with --save-database the run's "
      "database. With --team, SEQUENCE_DIR is a team's (team.txt and one sequence per robot): every robot's "
      "keyframes run in the world's clock order through a pipeline of its own, exchanging keyframe "
      "records and registration data as the node's team does, and OUT_DIR gets team.json, "
      "inter_robot_loops.csv and one folder per robot. Prints a summary, and last the line "
      "`output: OUT_DIR`.");
  cli.positional("SEQUENCE_DIR", "the KITTI-format sequence", &sequence_dir)
      .positional("OUT_DIR", "where the results go (created with its parents when missing)", &out_dir)
      .option("--config", "FILE",
              "YAML with some of the node's configuration keys (config/default.yaml lists them); keys it leaves out "
              "keep their defaults, so a sensor preset (config/sensors/*.yaml) works as it is",
              &config_file)
      .option("--set", "KEY=VALUE", "override one configuration key", &overrides)
      .option("--keyframe-spacing", "M", "one keyframe every M metres along the truth (default 0: every frame)",
              &options.keyframe_spacing)
      .option("--first", "N", "first frame of the window (default 0)", &options.first)
      .option("--last", "N", "last frame of the window (default: to the end)", &options.last)
      .option("--revisit-radius", "R", "ground-truth revisit radius [m] (default 5)", &radius)
      .flag("--team",
            "SEQUENCE_DIR is a team sequence (scan_context_simulate --team): team.txt (robot id, start on the "
            "world's clock, true start pose) and one KITTI-format folder per robot. Scores each robot's own loops, "
            "the loops between robots against the truth in the world frame, the bytes exchanged, and the map of "
            "the team (one pose-graph chain per robot, the first robot anchoring it): each robot's frame and "
            "trajectory error in the anchor's frame",
            &team)
      .flag("--truth-odometry", "feed the true poses even when odom_poses.txt exists",
            [&options] { options.use_odometry_file = false; })
      .option("--prior", "DIR|FILE",
              "relocalization in a prior map: run DIR's keyframes (all its frames, the same keyframe spacing and "
              "odometry source) first as session 0, or load the database FILE (needs --prior-truth), then "
              "SEQUENCE_DIR's as a new session, and score SEQUENCE_DIR's loops into the prior's keyframes too "
              "(metrics.json \"relocalization\", relocalization.csv). Both poses.txt must be in one world frame, "
              "as scripts/simulate --session 2 writes them",
              &prior_path)
      .option("--prior-truth", "DIR",
              "with a database --prior: the sequence it was built from; each keyframe's tag (its frame index, "
              "as --save-database writes it) picks its true pose from DIR's poses.txt and calib.txt",
              &prior_truth)
      .option("--save-database", "FILE",
              "after the run, save the pipeline's database (the prior's keyframes too) to FILE, the node's "
              "format (~load_database, database_load reads it); tags are frame indices",
              &save_database)
      .flag("--save-clouds",
            "with --save-database: include the registration data, so that loaded keyframes "
            "can be verified",
            &save_clouds)
      .option("--save-map", "DIR",
              "write the corrected map into DIR (created) as the pose_graph node's ~save_map does: map.pcd (the "
              "keyframe scans at the corrected poses, voxel-filtered), corrected_tum.txt, odometry_tum.txt, "
              "corrected_kitti.txt, times.txt, pose_graph.g2o (doc/pose_graph.md); without odom_poses.txt "
              "(or with --truth-odometry) the truth is the odometry the loops correct, as in the correction",
              &save_map)
      .option("--graph-study", "FILE",
              "also solve the pose graph of the trajectory correction once per line of FILE (a name, then KEY=VALUE "
              "words: loops=reported|reported_true|oracle|none, covariance=reported|floor, covariance_scale=X, "
              "false_loop=0|1 and the pose graph's keys) and write OUT_DIR/graph_study.csv: each one's trajectory "
              "error after a rigid and a similarity alignment and without one, on the revisited keyframes and on "
              "the rest (doc/pose_graph.md#what-limits-the-corrected-trajectory)",
              &graph_study);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  if (save_clouds && save_database.empty()) return cli.fail("--save-clouds goes with --save-database FILE");
  if (team && (!prior_path.empty() || !prior_truth.empty() || !save_database.empty() || !save_map.empty())) {
    return cli.fail("--team goes without --prior, --prior-truth, --save-database and --save-map");
  }
  std::vector<std::string> warnings;
  if (!config_file.empty() && !eval::loadConfigFile(config_file, &config, &error, &warnings)) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 2;
  }
  for (const auto& o : overrides) {
    if (!eval::applyOverride(o, &config, &error, &warnings)) {
      std::fprintf(stderr, "scan_context_evaluate: --set %s\n", error.c_str());
      return 2;
    }
  }
  for (const auto& w : warnings) std::fprintf(stderr, "scan_context_evaluate: warning: %s\n", w.c_str());
  const auto problems = config.validate();
  if (!problems.empty() || !(radius > 0.0)) {
    for (const auto& p : problems)
      std::fprintf(stderr, "scan_context_evaluate: invalid configuration: %s\n", p.c_str());
    if (!(radius > 0.0)) std::fprintf(stderr, "scan_context_evaluate: --revisit-radius must be positive\n");
    return 2;
  }

  std::vector<eval::GraphVariant> graph_variants;
  if (!graph_study.empty() && (team || !eval::readGraphVariants(graph_study, &graph_variants, &error))) {
    std::fprintf(stderr, "scan_context_evaluate: --graph-study: %s\n",
                 team ? "goes without --team" : error.c_str());
    return 2;
  }

  if (team) return scl::tools::evaluateTeam(sequence_dir, out_dir, config, options, radius);

  eval::Sequence sequence;
  if (!eval::loadSequence(sequence_dir, options, &sequence, &error)) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 1;
  }
  eval::EvaluationOptions run;
  run.revisit_radius = radius;
  run.save_database = save_database;
  run.save_clouds = save_clouds;
  eval::PriorMap prior;
  if (!eval::loadPriorMap(prior_path, prior_truth, options, config, &prior, &error)) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 1;
  }
  if (prior.kind == eval::PriorMap::Kind::kSequence) run.prior = &prior.sequence;
  if (prior.kind == eval::PriorMap::Kind::kDatabase) run.prior_database = &prior.database;
  eval::Evaluation result;
  if (!eval::evaluate(sequence, config, run, &result, &error)) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 1;
  }
  for (std::size_t i = 0; i < result.errors.size() && i < 5; ++i) {
    std::fprintf(stderr, "scan_context_evaluate: skipped %s\n", result.errors[i].c_str());
  }
  if (!scl::cli::makeDirectories(out_dir, &error) || !eval::writeResultsCsv(out_dir + "/results.csv", result, &error) ||
      !eval::writeMetricsJson(out_dir + "/metrics.json", result, sequence, config, radius, &error) ||
      !eval::writeTrajectoryCsv(out_dir + "/trajectory.csv", sequence, &error) ||
      (result.verification && !eval::writeVerificationsCsv(out_dir + "/verifications.csv", result, &error)) ||
      (result.has_prior && !eval::writeRelocalizationCsv(out_dir + "/relocalization.csv", result, &error))) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 1;
  }
  // What the loops do to the map: the reference pose graph over the odometry (in a prior map, and the
  // prior's keyframes held fixed) and the loops.
  const eval::TrajectoryCorrection correction = eval::correctTrajectory(sequence, result, config);
  if (!eval::writeTrajectoryErrorJson(out_dir + "/trajectory_error.json", correction, &error) ||
      (correction.computed &&
       !eval::writeCorrectedTrajectoryCsv(out_dir + "/trajectory_corrected.csv", sequence, correction, &error))) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 1;
  }
  if (!graph_study.empty() &&
      !eval::writeGraphStudyCsv(out_dir + "/graph_study.csv",
                                eval::runGraphStudy(sequence, result, config, graph_variants), &error)) {
    std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
    return 1;
  }
  if (!save_map.empty()) {
    std::string summary;
    if (!scl::cli::makeDirectories(save_map, &error) ||
        !eval::saveCorrectedMap(save_map, sequence, correction, &summary, &error)) {
      std::fprintf(stderr, "scan_context_evaluate: --save-map: %s\n", error.c_str());
      return 1;
    }
    std::printf("map saved to %s\n", summary.c_str());
  }
  const eval::Metrics& m = result.metrics;
  std::printf("%s\n", eval::trajectoryErrorLine(correction).c_str());
  std::printf("%s: %zu keyframes (%zu missing scans), %zu queries, %zu true revisits (R = %.1f m)\n",
              sequence_dir.c_str(), sequence.frames.size(), sequence.missing_scans, m.queries, m.revisits, radius);
  std::printf("at threshold %.3f: precision %.3f, recall %.3f (%zu TP, %zu FP)\n", m.threshold, m.precision, m.recall,
              m.true_positives, m.false_positives);
  std::printf("F1-max %.3f at %.3f; recall at 100%% precision %.3f; average precision %.3f\n", m.f1_max,
              m.f1_max_threshold, m.recall_at_full_precision, m.average_precision);
  std::printf("yaw error over true positives [deg]: median %.2f, p90 %.2f, max %.2f\n", m.yaw_error_median,
              m.yaw_error_p90, m.yaw_error_max);
  std::printf("descriptor %.3f ms median, %.3f ms p99; query + insert %.3f ms median, %.3f ms p99\n",
              eval::percentile(result.descriptor_ms, 0.5), eval::percentile(result.descriptor_ms, 0.99),
              eval::percentile(result.query_ms, 0.5), eval::percentile(result.query_ms, 0.99));
  std::printf(
      "CPU: %.2f ms a keyframe reading, describing, querying and verifying (%zu keyframes); whole process "
      "%.2f s with the pose graph and files\n",
      result.descriptor_ms.empty() ? 0.0 : 1e3 * result.cpu_seconds / static_cast<double>(result.descriptor_ms.size()),
      result.descriptor_ms.size(), eval::processCpuSeconds());
  if (result.verification) {
    const eval::VerifiedMetrics& v = result.verified;
    std::printf(
        "verified loops: precision %.3f, recall %.3f (%zu TP, %zu FP); relative pose error of true ones: "
        "translation %.3f m median / %.3f p90, yaw %.2f deg median / %.2f p90\n",
        v.precision, v.recall, v.true_positives, v.false_positives, v.translation_error_median, v.translation_error_p90,
        v.yaw_error_median, v.yaw_error_p90);
    std::printf("revisits whose first candidate is the right place: %zu, of which %zu verified (%.3f)\n",
                v.first_candidate_right, v.first_candidate_right_verified,
                v.first_candidate_right > 0 ? double(v.first_candidate_right_verified) / v.first_candidate_right : 0.0);
    std::printf(
        "verification per keyframe: %.2f candidates on average, %d at most; %.1f ms median, %.1f ms p99, "
        "%.1f ms max\n",
        v.candidates_mean, v.candidates_max, eval::percentile(result.verify_ms, 0.5),
        eval::percentile(result.verify_ms, 0.99), eval::percentile(result.verify_ms, 1.0));
    if (config.consistency_min_support > 0) {
      std::printf("consistency check: %zu loops reported after their keyframe, %zu dropped without support\n",
                  v.reported_late, result.loops_dropped);
    }
  }
  if (result.has_prior) {
    const eval::RelocalizationMetrics& r = result.relocalization;
    std::printf(
        "relocalization in %s (%zu keyframes): %zu of %zu query keyframes at a prior place (R = %.1f m); "
        "loops into the prior: precision %.3f, recall %.3f (%zu TP, %zu FP)\n",
        result.prior_source.c_str(), r.prior_keyframes, r.prior_places, r.queries, radius, r.precision, r.recall,
        r.true_positives, r.false_positives);
    std::printf(
        "relocalization pose error of true ones: translation %.3f m median / %.3f p90, yaw %.3f deg median "
        "/ %.3f p90\n",
        r.translation_error_median, r.translation_error_p90, r.yaw_error_median, r.yaw_error_p90);
    if (r.first_query >= 0) {
      std::printf(
          "first correct relocalization: %.1f s, %.0f m after the start (frame %d; first prior place at "
          "%.1f s, %.0f m); %zu wrong before it\n",
          r.first_seconds, r.first_metres, r.first_query, r.first_place_seconds, r.first_place_metres,
          r.false_before_first);
    } else {
      std::printf("no correct relocalization\n");
    }
  }
  if (!save_database.empty()) {
    std::printf("database: %s (%s registration data)\n", save_database.c_str(), save_clouds ? "with" : "without");
  }
  std::printf("output: %s\n", out_dir.c_str());
  return 0;
}
