// The evaluator's oracle and graph study on a hand-made evaluation (no scans): a prior map (a block's
// lap at its true poses, held fixed) and a session driving the lap again one lane in with drifting
// odometry. Every session keyframe is a revisit, so the oracle's loops (true relative poses into the
// fixed prior) must bring the session onto the truth; loops with a registration error must do worse
// than the same pairs at their true poses.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/graph_study.h"
#include "scan_context_loop/eval/metrics.h"
#include "scan_context_loop/eval/trajectory_correction.h"

#include "../common/block_poses.h"

namespace scan_context_loop {
namespace eval {
namespace {

using test::kPerLap;

using test::planar;

/// The prior (lap 1, outer lane, its stored poses the truth) and the session (lap 2, 1 m in, odometry
/// with a yaw bias of 0.06 deg a step and a 1 % scale error from its true first pose), with the scoring's
/// revisits: each session keyframe's nearest prior keyframe.
struct PriorAndSession {
  Sequence session;
  Evaluation e;
  Config config;

  PriorAndSession() {
    Sequence& prior = e.prior_keyframes;
    std::vector<Eigen::Vector3d> positions;
    for (std::size_t k = 0; k < kPerLap; ++k) {
      prior.frames.push_back(static_cast<int>(k));
      prior.truth.push_back(test::blockPose(k, 0.0, kPerLap));
      prior.odometry.push_back(prior.truth.back());
      prior.stamps.push_back(0.1 * k);
      positions.push_back(prior.truth.back().translation());
      e.keyframe_of.push_back(-1);
    }
    e.has_prior = true;
    session.odometry_from_file = true;
    for (std::size_t k = 0; k < kPerLap; ++k) {
      session.frames.push_back(static_cast<int>(k));
      session.truth.push_back(test::blockPose(k, 1.0, kPerLap));
      session.stamps.push_back(100.0 + 0.1 * k);
      if (k == 0) {
        session.odometry.push_back(session.truth[0]);
      } else {
        Eigen::Isometry3d step = session.truth[k - 1].inverse() * session.truth[k];
        step.translation() *= 1.01;
        step.linear() = step.linear() * Eigen::AngleAxisd(0.001, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        session.odometry.push_back(session.odometry.back() * step);
      }
      positions.push_back(session.truth[k].translation());
      e.keyframe_of.push_back(static_cast<long>(k));
      QueryOutcome o;
      o.query = session.frames[k];
      o.revisit_index = nearestRevisit(positions, positions.size() - 1, kPerLap, 5.0);
      o.revisit = o.revisit_index >= 0;
      e.outcomes.push_back(o);
    }
    e.verification = true;
  }

  /// A verified loop from session keyframe k to its revisit, measured `off` from the truth.
  void addLoop(std::size_t k, const Eigen::Isometry3d& off) {
    Loop loop;
    loop.query = kPerLap + k;
    loop.match = static_cast<std::size_t>(e.outcomes[k].revisit_index);
    loop.verified = true;
    loop.verification.relative = session.truth[k].inverse() * e.prior_keyframes.truth[loop.match] * off;
    Eigen::Matrix<double, 6, 1> floor;
    floor << 0.01, 0.01, 0.01, 7.6e-5, 7.6e-5, 7.6e-5;
    loop.verification.covariance = floor.asDiagonal();
    e.loops.push_back(loop);
  }
};

TEST(GraphStudy, TheOracleBringsASessionOntoTheTruthThroughAFixedPrior) {
  PriorAndSession d;
  // A few loops, each registered 0.3 m and 1 deg off: the corrected trajectory carries their error.
  for (std::size_t k = 5; k < kPerLap; k += 20) d.addLoop(k, planar(0.3, -0.2, M_PI / 180.0));
  const TrajectoryCorrection c = correctTrajectory(d.session, d.e, d.config);
  ASSERT_TRUE(c.computed) << c.note;
  std::printf("ATE RMSE: odometry %.3f m, corrected %.3f m (%zu loops), same pairs at true poses %.3f m, oracle "
              "%.3f m (%zu loops)\n",
              c.odometry.rmse, c.corrected.rmse, c.loops, c.reported_true.rmse, c.oracle.rmse, c.oracle_loops);
  EXPECT_GT(c.odometry.rmse, 1.0) << "the session's odometry should drift";
  EXPECT_EQ(c.oracle_loops, kPerLap) << "every session keyframe is a revisit";
  EXPECT_LT(c.reported_true.rmse, c.corrected.rmse) << "the loops' own error should cost something";
  EXPECT_LT(c.oracle.rmse, c.reported_true.rmse) << "a loop at every keyframe should do better than a few";
  EXPECT_LT(c.oracle.rmse, 0.05 * c.odometry.rmse);
  // Every session keyframe is a revisit and none of the prior's is part of the session: all revisited.
  EXPECT_EQ(c.corrected_revisited.keyframes, kPerLap);
  EXPECT_EQ(c.corrected_rest.keyframes, 0u);

  std::string error;
  const std::string path = ::testing::TempDir() + "graph_study_trajectory_error.json";
  ASSERT_TRUE(writeTrajectoryErrorJson(path, c, &error)) << error;
  std::stringstream json;
  json << std::ifstream(path).rdbuf();
  for (const char* key : {"\"oracle\": {", "\"oracle_loops\": 180", "\"reported_loops_true_poses\": {",
                          "\"corrected_by_part\": {"}) {
    EXPECT_NE(json.str().find(key), std::string::npos) << key << " in " << json.str();
  }
}

TEST(GraphStudy, NearlyRigidOracleLoopsRecoverTheTruthExactly) {
  // The oracle's loops made a million times surer: the session lands on the truth, in the prior's
  // frame (the truth's) without any alignment, whatever its odometry did.
  PriorAndSession d;
  GraphVariant oracle;
  std::string error;
  ASSERT_TRUE(parseGraphVariant("rigid_oracle loops=oracle covariance_scale=1e-6", &oracle, &error)) << error;
  const std::vector<GraphStudyRow> rows = runGraphStudy(d.session, d.e, d.config, {oracle});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].name, "odometry");
  EXPECT_EQ(rows[0].loops, 0u);
  EXPECT_EQ(rows[1].name, "rigid_oracle");
  EXPECT_EQ(rows[1].loops, kPerLap);
  std::printf("odometry %.3f m; rigid oracle %.6f m aligned, %.6f m without alignment\n", rows[0].aligned.rmse,
              rows[1].aligned.rmse, rows[1].anchored.rmse);
  EXPECT_GT(rows[0].aligned.rmse, 1.0);
  EXPECT_LT(rows[1].aligned.rmse, 1e-3);
  EXPECT_LT(rows[1].anchored.rmse, 1e-3);
  EXPECT_NEAR(rows[1].similarity_scale, 1.0, 1e-4);
}

TEST(GraphStudy, VariantLinesAreParsedAndCheckedAgainstTheGraphsTable) {
  GraphVariant v;
  std::string error;
  ASSERT_TRUE(parseGraphVariant("stiff loops=reported_true covariance=floor covariance_scale=0.5 false_loop=1 "
                                "odometry_rotation_per_radian=0.01 loop_robust_scale=0",
                                &v, &error))
      << error;
  EXPECT_EQ(v.name, "stiff");
  EXPECT_EQ(v.loops, GraphVariant::Loops::kReportedTrue);
  EXPECT_TRUE(v.floor_covariance);
  EXPECT_DOUBLE_EQ(v.covariance_scale, 0.5);
  EXPECT_TRUE(v.false_loop);
  EXPECT_DOUBLE_EQ(v.graph.odometry_rotation_per_radian, 0.01);
  EXPECT_DOUBLE_EQ(v.graph.loop_robust_scale, 0.0);
  EXPECT_FALSE(parseGraphVariant("# a comment", &v, &error));
  EXPECT_TRUE(error.empty());
  EXPECT_FALSE(parseGraphVariant("bad odometry_rotation_per_radian=-1", &v, &error));
  EXPECT_NE(error.find("odometry_rotation_per_radian"), std::string::npos) << error;
  EXPECT_FALSE(parseGraphVariant("bad no_such_key=1", &v, &error));
  EXPECT_NE(error.find("no_such_key"), std::string::npos) << error;
  EXPECT_FALSE(parseGraphVariant("bad covariance_scale=0", &v, &error));
  EXPECT_FALSE(parseGraphVariant("bad loops=some", &v, &error));
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop
