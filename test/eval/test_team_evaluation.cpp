// The evaluator's team mode: a tiny team of two robots on overlapping laps of one simulated block, each
// with its own origin and odometry, scored with the node's code (TeamSession) and merged into one map.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/team_evaluation.h"
#include "scan_context_loop/eval/team_map.h"
#include "scan_context_loop/eval/team_sequence.h"
#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/team_file.h"
#include "scan_context_sim/trajectory.h"
#include "../common/sim_drive.h"

namespace scan_context_loop {
namespace eval {
namespace {

std::string teamEvalTemp(const std::string& name) { return testing::TempDir() + "/scl_team_eval_" + name; }

/// robot1 drives lap 1 of the block; robot2 lap 2 (one lane further out, the same way), starting 2 s
/// after robot1, so it passes 40 m behind it. Each robot's sequence is relative to its own first keyframe,
/// with an odometry of its own that drifts from the identity.
const std::string& tinyTeam() {
  static const std::string dir = [] {
    const std::string out = teamEvalTemp("team");
    const test::Drive drive = test::blockDrive(false, 21);
    const std::size_t half = drive.truth.size() / 2;
    const double starts[2] = {0.0, 2.0};
    std::vector<sim::TeamMember> members;
    std::string error;
    for (std::size_t r = 0; r < 2; ++r) {
      const std::size_t begin = r * half, end = r == 0 ? half : drive.truth.size();
      sim::SequenceData data;
      data.origin = drive.truth[begin];
      for (std::size_t k = begin; k < end; ++k) {
        data.truth.push_back(data.origin.inverse() * drive.truth[k]);
        data.times.push_back(drive.times[k] - drive.times[begin]);
      }
      data.world_clock = starts[r];
      sim::DriftOptions drift;
      drift.seed = 40 + r;
      data.odometry = sim::driftedOdometry(data.truth, drift);
      const Eigen::Isometry3d origin = data.odometry.front().inverse();
      for (Eigen::Isometry3d& pose : data.odometry) pose = origin * pose;
      const std::string id = "robot" + std::to_string(r + 1);
      std::filesystem::create_directories(out + "/" + id);
      EXPECT_GT(sim::writeSequence(out + "/" + id, drive.world, drive.sensor, data, 0.0, 30 + r, 2, &error), 1000.0)
          << error;
      members.push_back({id, starts[r], data.origin});
    }
    EXPECT_TRUE(sim::writeTeamFile(out + "/team.txt", members, &error)) << error;
    return out;
  }();
  return dir;
}

struct Run {
  TeamSequence team;
  TeamEvaluation evaluation;
  TeamMap map;
};

const Run& run() {
  static const Run r = [] {
    Run x;
    std::string error;
    EXPECT_TRUE(loadTeam(tinyTeam(), SequenceOptions(), &x.team, &error)) << error;
    const Config config;  // the defaults, verification on
    x.evaluation = evaluateTeam(x.team, config, 5.0);
    x.map = mergeTeamMap(x.team, x.evaluation, config);
    return x;
  }();
  return r;
}

TEST(TeamEvaluation, LoopsBetweenRobotsAreFoundAndTrue) {
  const TeamEvaluation& e = run().evaluation;
  ASSERT_EQ(run().team.robots.size(), 2u);
  ASSERT_EQ(e.robots.size(), 2u);
  // robot2 drives where robot1 drove 2 s before, one lane over: nearly every keyframe is a revisit.
  EXPECT_GT(e.revisits, run().team.robots[1].sequence.frames.size() / 2);
  EXPECT_GE(e.loops.size(), 10u);
  EXPECT_GT(e.robots[1].true_positives, 0u);
  EXPECT_GE(e.recall, 0.5);
  // Between robots no odometry relates the two keyframes, so no odometry check stands against a
  // registration that slides along a straight street: a few such loops pass (2 of 98 here, 2-4 m off,
  // between keyframes 8-11 m apart); the rest are true.
  EXPECT_GE(e.true_positives, 10u);
  EXPECT_LE(e.false_positives, e.loops.size() / 20);
  EXPECT_EQ(e.true_positives + e.false_positives, e.loops.size());
  EXPECT_LT(e.translation_error_median, 0.1);
  EXPECT_LT(e.rotation_error_median, 0.2);
  for (const InterRobotLoop& loop : e.loops) {
    EXPECT_NE(loop.query_robot, loop.match_robot);
    EXPECT_EQ(loop.correct, loop.translation_error <= 1.0 && loop.rotation_error <= 2.0 * M_PI / 180.0);
    // Within the revisit radius, the place is right.
    if (loop.gap < 5.0) {
      EXPECT_TRUE(loop.correct) << "gap " << loop.gap << " m, off by " << loop.translation_error << " m, "
                                << loop.rotation_error * 180.0 / M_PI << " deg";
    }
  }
}

TEST(TeamEvaluation, NoPairIsReportedTwice) {
  const TeamEvaluation& e = run().evaluation;
  std::set<std::pair<std::pair<std::size_t, std::size_t>, std::pair<std::size_t, std::size_t>>> pairs;
  for (const InterRobotLoop& loop : e.loops) {
    const auto a = std::make_pair(loop.query_robot, loop.query), b = std::make_pair(loop.match_robot, loop.match);
    EXPECT_TRUE(pairs.insert(std::minmax(a, b)).second);
  }
  EXPECT_EQ(e.repeated_pairs, 0u);
  // The later keyframe's robot finds a pair: the match was stored before the query.
  for (const InterRobotLoop& loop : e.loops) {
    EXPECT_LE(run().team.robots[loop.match_robot].clock(loop.match), loop.clock);
  }
}

TEST(TeamEvaluation, BytesPerKeyframeAreCounted) {
  const TeamEvaluation& e = run().evaluation;
  std::size_t keyframes = 0, record_bytes = 0;
  for (std::size_t r = 0; r < e.robots.size(); ++r) {
    const TeamRobotEvaluation& x = e.robots[r];
    EXPECT_GT(x.keyframes, 50u);
    EXPECT_GT(x.record_bytes, 0u);
    // Each robot receives every record of the other.
    EXPECT_EQ(x.received_bytes, e.robots[1 - r].record_bytes);
    EXPECT_EQ(x.records_refused, 0u);
    EXPECT_EQ(x.fetch_failures, 0u);
    keyframes += x.keyframes;
    record_bytes += x.record_bytes;
  }
  EXPECT_EQ(e.keyframes, keyframes);
  EXPECT_EQ(e.records, keyframes);
  EXPECT_EQ(e.record_bytes, record_bytes);
  EXPECT_NEAR(e.record_bytes_mean, double(record_bytes) / keyframes, 1e-9);
  // A record is a descriptor and a pose, far smaller than a scan; the registration data of a candidate
  // are larger, and travel only for candidates: at least once for each loop's match, never for every record.
  EXPECT_LT(e.record_bytes_mean, 20000.0);
  EXPECT_GT(e.fetched_bytes_mean, e.record_bytes_mean);
  EXPECT_GE(e.fetched, 1u);
  EXPECT_LT(e.fetched, e.keyframes);
  EXPECT_NEAR(e.sent_bytes_per_keyframe, double(e.record_bytes + e.fetched_bytes) / e.keyframes, 1e-6);

  std::string error;
  ASSERT_TRUE(writeTeamJson(teamEvalTemp("team.json"), run().team, e, run().map, &error)) << error;
  ASSERT_TRUE(writeInterRobotLoopsCsv(teamEvalTemp("loops.csv"), run().team, e, &error)) << error;
  std::ifstream csv(teamEvalTemp("loops.csv"));
  std::string line;
  std::size_t rows = 0;
  for (std::getline(csv, line); std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, e.loops.size());
}

TEST(TeamEvaluation, FramesBetweenRobotsAreEstimated) {
  const TeamMap& map = run().map;
  // A build without the backend has no map (team_map_unavailable.cpp), and says so.
  if (!map.computed && map.note.find("without the pose-graph backend") != std::string::npos) GTEST_SKIP() << map.note;
  ASSERT_TRUE(map.computed) << map.note;
  ASSERT_EQ(map.robots.size(), 2u);
  EXPECT_TRUE(map.robots[0].joined);
  EXPECT_NEAR(map.robots[0].frame_translation_error, 0.0, 1e-9);
  ASSERT_TRUE(map.robots[1].joined);
  EXPECT_LT(map.robots[1].frame_translation_error, 0.5);
  EXPECT_LT(map.robots[1].frame_rotation_error, 1.0);
  EXPECT_GT(map.robots[1].team_loops + map.robots[0].team_loops, 0u);
  EXPECT_EQ(map.corrected.poses,
            run().team.robots[0].sequence.frames.size() + run().team.robots[1].sequence.frames.size());
  EXPECT_LT(map.corrected.rmse, 0.5);
}

TEST(TeamSequence, BadTeamFilesAreRefusedNamingTheLine) {
  const std::string dir = teamEvalTemp("bad");
  std::string error;
  std::filesystem::create_directories(dir);
  const std::string pose = " 1 0 0 0 0 1 0 0 0 0 1 0\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"# a comment\nrobot1 0" + pose + "robot1 5" + pose, ":3: robot robot1 is there twice"},
      {"robot-1 0" + pose, ":1: robot id"},
      {"robot1 -1" + pose, ":1: expected a start"},
      {"robot1 0 1 0 0 0 0 1 0 0 0 0 1\n", ":1: expected exactly 12"},
      {"robot1 0 2 0 0 0 0 1 0 0 0 0 1 0\n", ":1: T_world<-robot_start's rotation"},
      {"# nobody\n", ": no robot"},
  };
  for (const auto& [text, expected] : cases) {
    std::ofstream(dir + "/team.txt") << text;
    TeamSequence team;
    EXPECT_FALSE(loadTeam(dir, SequenceOptions(), &team, &error)) << text;
    EXPECT_NE(error.find(expected), std::string::npos) << error;
  }
  // A good team file whose robot has no sequence.
  std::ofstream(dir + "/team.txt") << "robot1 0" + pose;
  TeamSequence team;
  EXPECT_FALSE(loadTeam(dir, SequenceOptions(), &team, &error));
  EXPECT_NE(error.find(dir + "/robot1"), std::string::npos) << error;
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop
