// Relocalization in a prior map: a simulated second session evaluated against the first.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/trajectory_correction.h"
#include "../common/sim_drive.h"
#include "../common/written_sequence.h"

namespace scan_context_loop {
namespace eval {
namespace {

std::string relocTemp(const std::string& name) { return testing::TempDir() + "/scl_reloc_" + name; }

Sequence written(const test::Drive& drive, const std::string& name, std::uint32_t seed, double stamp_offset) {
  return test::writtenSequence(drive, relocTemp(name), seed, stamp_offset);
}

const test::Sessions& sessions() {
  static const test::Sessions s = test::blockSessions(3);
  return s;
}

const Sequence& prior() {
  static const Sequence s = written(sessions().first, "prior", 11, 0.0);
  return s;
}

TEST(Relocalization, TheSecondSessionRelocalizesInTheFirstsMap) {
  const Sequence& query = written(sessions().second, "query", 12, 0.0);
  ASSERT_FALSE(prior().frames.empty());
  ASSERT_FALSE(query.frames.empty());
  const Config config;  // the defaults, verification on
  const Evaluation e = evaluate(query, config, 5.0, &prior());
  ASSERT_TRUE(e.has_prior);
  EXPECT_EQ(e.rejected, 0u);
  const RelocalizationMetrics& r = e.relocalization;
  EXPECT_EQ(r.prior_keyframes, prior().frames.size());
  // Every query keyframe is scored, its first too (the prior map is there to query).
  ASSERT_EQ(e.prior_outcomes.size(), query.frames.size());
  EXPECT_EQ(e.outcomes.size(), query.frames.size());
  // The lap driven back one lane over: every place is within 5 m of the prior, facing the other way.
  EXPECT_EQ(r.prior_places, r.queries);
  int facing_back = 0;
  for (const PriorOutcome& o : e.prior_outcomes) facing_back += std::fabs(o.nearest_yaw) > 150.0 * M_PI / 180.0;
  EXPECT_GT(facing_back, 0.8 * r.queries);
  // Cars and plants changed, the other lane, the other way: most places relocalize, none wrongly.
  EXPECT_EQ(r.false_positives, 0u);
  EXPECT_GE(r.recall, 0.5);
  EXPECT_LT(r.translation_error_median, 0.2);
  EXPECT_LT(r.yaw_error_median, 0.5);
  ASSERT_GE(r.first_query, 0);
  EXPECT_LT(r.first_metres, 40.0);
  EXPECT_GE(r.first_seconds, r.first_place_seconds);
  // The usual metrics count the query's loops into the prior as well, and say whose frames they name.
  std::size_t into_prior = 0;
  for (const QueryOutcome& o : e.outcomes) into_prior += o.verified_match >= 0 && o.verified_in_prior;
  EXPECT_EQ(into_prior, r.true_positives + r.false_positives);
  EXPECT_GE(e.verified.true_positives, r.true_positives);

  std::string error;
  ASSERT_TRUE(writeMetricsJson(relocTemp("metrics.json"), e, query, config, 5.0, &error)) << error;
  std::stringstream json;
  json << std::ifstream(relocTemp("metrics.json")).rdbuf();
  EXPECT_NE(json.str().find("\"relocalization\": {\"prior\": \"" + prior().dir + "\""), std::string::npos);
  ASSERT_TRUE(writeRelocalizationCsv(relocTemp("relocalization.csv"), e, &error)) << error;
  std::ifstream csv(relocTemp("relocalization.csv"));
  std::string line;
  std::size_t rows = 0;
  for (std::getline(csv, line); std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, query.frames.size());
}

TEST(Relocalization, TheQueryIsANewSessionEvenWhenItsStampsGoOn) {
  // The same drive recorded with stamps after the prior's: no jump back in time starts the session.
  // Within the prior's session the recent-keyframe window would hide the prior's last 50 keyframes,
  // where the query starts, and the odometry gate would compare unrelated odometry frames.
  const Sequence& query = written(sessions().second, "query_later", 12, 1e5);
  const Evaluation e = evaluate(query, Config(), 5.0, &prior());
  EXPECT_EQ(e.rejected, 0u);
  EXPECT_EQ(e.relocalization.false_positives, 0u);
  EXPECT_GE(e.relocalization.recall, 0.5);
  EXPECT_LT(e.relocalization.first_metres, 40.0);
}

TEST(Relocalization, LoopTrackingCarriesTheRevisitWhereTheDescriptorMisses) {
  // The map searched alone (the node's mode relocalize). Without tracking, the keyframes whose descriptor
  // the changed street spoiled go without a relocalization; with it, the confirmed loops before them
  // and the odometry lead registration to their place.
  const Sequence& query = written(sessions().second, "query", 12, 0.0);
  Config config;
  config.prior_sessions_only = true;
  config.track_distance = 0.0;
  const Evaluation plain = evaluate(query, config, 5.0, &prior());
  config.track_distance = 30.0;
  const Evaluation tracked = evaluate(query, config, 5.0, &prior());
  EXPECT_EQ(plain.relocalization.false_positives, 0u);
  EXPECT_EQ(tracked.relocalization.false_positives, 0u);
  EXPECT_GT(tracked.relocalization.true_positives, plain.relocalization.true_positives);
  EXPECT_GE(tracked.relocalization.recall, 0.9);
  EXPECT_LT(tracked.relocalization.translation_error_median, 0.2);
  EXPECT_LT(tracked.relocalization.yaw_error_median, 0.5);
  // Every query keyframe that relocalized without tracking still does.
  ASSERT_EQ(plain.prior_outcomes.size(), tracked.prior_outcomes.size());
  for (std::size_t i = 0; i < plain.prior_outcomes.size(); ++i) {
    if (plain.prior_outcomes[i].correct) EXPECT_TRUE(tracked.prior_outcomes[i].correct) << "query " << i;
  }
}

/// The prior map of `e` as the correction held it: every keyframe where it was stored, and a summary.
void expectPriorHeldFixed(const Evaluation& e, const Sequence& prior_map, const TrajectoryCorrection& c) {
  EXPECT_TRUE(c.in_prior);
  EXPECT_EQ(c.prior_keyframes, prior_map.frames.size());
  ASSERT_EQ(e.prior_keyframes.frames, prior_map.frames);
  for (std::size_t i = 0; i < prior_map.frames.size(); ++i) {
    EXPECT_TRUE(e.prior_keyframes.odometry[i].isApprox(prior_map.odometry[i], 1e-12)) << "prior keyframe " << i;
  }
  EXPECT_EQ(c.prior_moved, 0.0);
  EXPECT_GT(c.prior_loops, 10u);
  EXPECT_LE(c.prior_loops, c.loops);
  ASSERT_EQ(c.corrected_poses.size(), c.odometry.poses);
}

TEST(Relocalization, AFixedPerfectPriorMapPullsTheDriftingSessionOntoTheTruth) {
  // The prior map at its true poses (read without its odometry: as a map corrected before it was saved)
  // and the second session with its own drifting odometry from the identity: its loops into the fixed
  // prior move it into the prior's frame and onto the truth.
  const Sequence& query = written(sessions().second, "query", 12, 0.0);
  ASSERT_FALSE(prior().frames.empty());
  SequenceOptions options;
  options.use_odometry_file = false;
  Sequence perfect;
  std::string error;
  ASSERT_TRUE(loadSequence(prior().dir, options, &perfect, &error)) << error;
  const Config config;
  const Evaluation e = evaluate(query, config, 5.0, &perfect);
  const TrajectoryCorrection c = correctTrajectory(query, e, config);
  ASSERT_TRUE(c.computed) << c.note;
  std::printf(
      "session 2 in a perfect fixed prior: odometry ATE %.3f m (max %.3f), corrected %.3f m (max %.3f) with "
      "%zu loops, %zu into the prior\n",
      c.odometry.rmse, c.odometry.max, c.corrected.rmse, c.corrected.max, c.loops, c.prior_loops);
  expectPriorHeldFixed(e, perfect, c);
  EXPECT_LT(c.prior_odometry.rmse, 1e-9);
  EXPECT_TRUE(c.own_odometry);
  EXPECT_GT(c.odometry.rmse, 0.05) << "the simulated odometry should drift";
  EXPECT_LT(c.corrected.rmse, 0.3 * c.odometry.rmse);
  EXPECT_LT(c.corrected.max, c.odometry.max);

  ASSERT_TRUE(writeTrajectoryErrorJson(relocTemp("trajectory_error.json"), c, &error)) << error;
  std::stringstream json;
  json << std::ifstream(relocTemp("trajectory_error.json")).rdbuf();
  const std::vector<std::string> keys = {"\"computed\": true", "\"corrected\": {",
                                         "\"prior_loops\": " + std::to_string(c.prior_loops),
                                         "\"prior\": {\"source\": \"" + perfect.dir + "\"", "\"held_fixed\": true"};
  for (const std::string& key : keys) {
    EXPECT_NE(json.str().find(key), std::string::npos) << key << " in " << json.str();
  }
  const std::string line = trajectoryErrorLine(c);
  EXPECT_NE(line.find(std::to_string(c.prior_loops) + " into the prior's " + std::to_string(perfect.frames.size()) +
                      " keyframes, held fixed"),
            std::string::npos)
      << line;
}

TEST(Relocalization, TheDriftingPriorMapStaysWhereItWasStored) {
  // The prior at its own drifting odometry, as a mapping run stores it: the session joins that map, so
  // its corrected trajectory takes the prior's shape where they meet, and its error is bounded by the two
  // odometries' together rather than by its own.
  const Sequence& query = written(sessions().second, "query", 12, 0.0);
  const Config config;
  const Evaluation e = evaluate(query, config, 5.0, &prior());
  const TrajectoryCorrection c = correctTrajectory(query, e, config);
  ASSERT_TRUE(c.computed) << c.note;
  std::printf(
      "session 2 in the drifting prior: odometry ATE %.3f m, prior's %.3f m, corrected %.3f m (%zu loops, "
      "%zu into the prior)\n",
      c.odometry.rmse, c.prior_odometry.rmse, c.corrected.rmse, c.loops, c.prior_loops);
  expectPriorHeldFixed(e, prior(), c);
  EXPECT_GT(c.prior_odometry.rmse, 0.05);
  EXPECT_LT(c.corrected.rmse, c.odometry.rmse + c.prior_odometry.rmse);
}

TEST(Relocalization, WithoutAPriorNothingIsScoredAgainstOne) {
  const Evaluation e = evaluate(prior(), Config(), 5.0);
  EXPECT_FALSE(e.has_prior);
  EXPECT_TRUE(e.prior_outcomes.empty());
  for (const QueryOutcome& o : e.outcomes) EXPECT_FALSE(o.match_in_prior || o.verified_in_prior);
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop
