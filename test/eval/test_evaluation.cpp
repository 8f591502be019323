#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/verification.h"
#include "scan_context_loop/eval/config_file.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/trajectory_correction.h"
#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/graph/pose_graph_settings.h"
#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/trajectory.h"
#include "../common/sim_drive.h"

namespace scan_context_loop {
namespace eval {
namespace {

std::string evalTemp(const std::string& name) { return testing::TempDir() + "/scl_eval_" + name; }

TEST(ConfigFile, ReadsNodeKeysIgnoresRosKeysAndRejectsBadValues) {
  std::ofstream(evalTemp("good.yaml")) << "# comment\nnum_sectors: 90\ndistance_threshold: 0.3\nring_key: mean_height\n"
                                      "pose_source: odom\nvoxel_leaf: 0.4\nverify_min_inlier_ratio: 0.6\n";
  Config config;
  std::string error;
  ASSERT_TRUE(loadConfigFile(evalTemp("good.yaml"), &config, &error)) << error;
  EXPECT_EQ(config.num_sectors, 90);
  EXPECT_DOUBLE_EQ(config.distance_threshold, 0.3);
  EXPECT_EQ(config.ring_key, RingKeyType::kMeanHeight);
  EXPECT_DOUBLE_EQ(config.verification.min_inlier_ratio, 0.6);
  // A key that is neither the core's nor the node's is an error that names it, like the node's.
  std::ofstream(evalTemp("mystery.yaml")) << "num_sectors: 90\nmystery: 1\n";
  Config before;
  EXPECT_FALSE(loadConfigFile(evalTemp("mystery.yaml"), &before, &error));
  EXPECT_NE(error.find("mystery"), std::string::npos) << error;
  EXPECT_EQ(before.num_sectors, Config().num_sectors);

  std::ofstream(evalTemp("bad.yaml")) << "num_rings: twenty\n";
  Config untouched;
  EXPECT_FALSE(loadConfigFile(evalTemp("bad.yaml"), &untouched, &error));
  EXPECT_NE(error.find("num_rings"), std::string::npos) << error;
  EXPECT_EQ(untouched.num_rings, Config().num_rings);
  EXPECT_FALSE(loadConfigFile(evalTemp("absent.yaml"), &untouched, &error));
  std::ofstream(evalTemp("list.yaml")) << "- 1\n- 2\n";
  EXPECT_FALSE(loadConfigFile(evalTemp("list.yaml"), &untouched, &error));

  EXPECT_TRUE(applyOverride("search_ratio=1.0", &config, &error));
  EXPECT_DOUBLE_EQ(config.search_ratio, 1.0);
  EXPECT_FALSE(applyOverride("search_ratio", &config, &error));
}

TEST(ConfigFile, DeprecatedKeyNamesSetTheNewKeysWithAWarning) {
  std::ofstream(evalTemp("old_names.yaml")) << "levelling: ground\nlevelling_max_tilt: 12\n";
  std::ofstream(evalTemp("new_names.yaml")) << "gravity_alignment: ground\ngravity_alignment_max_tilt: 12\n";
  Config old_config, new_config;
  std::string error;
  std::vector<std::string> old_warnings, new_warnings;
  ASSERT_TRUE(loadConfigFile(evalTemp("old_names.yaml"), &old_config, &error, &old_warnings)) << error;
  ASSERT_TRUE(loadConfigFile(evalTemp("new_names.yaml"), &new_config, &error, &new_warnings)) << error;
  EXPECT_EQ(old_config.gravity_alignment, GravityAlignmentMode::kGround);
  EXPECT_DOUBLE_EQ(old_config.trusted_pose_max_tilt_deg, 12.0);
  for (const auto& s : configSettings()) EXPECT_EQ(s.get(old_config), s.get(new_config)) << s.key;
  EXPECT_TRUE(new_warnings.empty());
  ASSERT_EQ(old_warnings.size(), 2u);
  EXPECT_NE(old_warnings[0].find("levelling is deprecated, use gravity_alignment"), std::string::npos);
  EXPECT_NE(old_warnings[1].find("levelling_max_tilt is deprecated, use gravity_alignment_max_tilt"),
            std::string::npos);

  // --set takes the old name too, with the same warning.
  Config set_old, set_new;
  std::vector<std::string> set_warnings;
  ASSERT_TRUE(applyOverride("levelling=off", &set_old, &error, &set_warnings)) << error;
  ASSERT_TRUE(applyOverride("gravity_alignment=off", &set_new, &error, &set_warnings)) << error;
  EXPECT_EQ(set_old.gravity_alignment, GravityAlignmentMode::kOff);
  for (const auto& s : configSettings()) EXPECT_EQ(s.get(set_old), s.get(set_new)) << s.key;
  ASSERT_EQ(set_warnings.size(), 1u);
  EXPECT_EQ(set_warnings[0], "levelling is deprecated, use gravity_alignment");
}

/// Checks that every key of the table is in the file (`name`, for messages) with the table's default,
/// and that the default keeps the table's own rule.
template <typename T>
void expectDefaults(const YAML::Node& file, const std::string& name, const std::vector<Setting<T>>& table,
                    std::vector<std::string>* seen) {
  const T defaults;
  for (const auto& s : table) {
    seen->push_back(s.key);
    ASSERT_TRUE(file[s.key]) << s.key << " is missing from " << name;
    T parsed;
    ASSERT_TRUE(s.set(&parsed, file[s.key].template as<std::string>())) << s.key;
    EXPECT_EQ(s.get(parsed), s.get(defaults)) << s.key << ": " << name << " disagrees with the code";
    EXPECT_EQ(s.check(defaults), "") << s.key << ": the default breaks its own rule";
  }
}

/// Checks that the file's keys are all among the tables' (`keys`) and, with `comment_each`, that every key
/// has a comment line right above it (default.yaml comments some keys as a group).
void expectOnlyKeys(const std::string& name, const std::vector<std::string>& keys, bool comment_each) {
  const std::string path = std::string(SCL_PACKAGE_DIR) + "/" + name;
  const YAML::Node file = YAML::LoadFile(path);
  for (const auto& item : file) {
    const std::string key = item.first.as<std::string>();
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key << " in " << name << " is no key";
  }
  if (!comment_each) return;
  std::ifstream text(path);
  std::string line, previous;
  for (; std::getline(text, line); previous = line) {
    if (line.empty() || line[0] == '#') continue;
    EXPECT_EQ(previous.rfind("#", 0), 0u) << name << ": '" << line << "' has no comment above it";
  }
}

TEST(ConfigFile, DefaultsFileListsEveryKeyWithTheCodesDefault) {
  const std::string name = "config/default.yaml";
  const YAML::Node file = YAML::LoadFile(std::string(SCL_PACKAGE_DIR) + "/" + name);
  std::vector<std::string> keys;
  expectDefaults(file, name, configSettings(), &keys);
  expectDefaults(file, name, nodeSettings(), &keys);
  expectOnlyKeys(name, keys, false);
  EXPECT_TRUE(Config().validate().empty());
}

TEST(ConfigFile, PoseGraphFileListsEveryKeyWithTheCodesDefault) {
  const std::string name = "config/pose_graph.yaml";
  const YAML::Node file = YAML::LoadFile(std::string(SCL_PACKAGE_DIR) + "/" + name);
  std::vector<std::string> keys;
  expectDefaults(file, name, poseGraphSettings(), &keys);
  expectDefaults(file, name, keyframeMapSettings(), &keys);
  expectDefaults(file, name, poseGraphNodeSettings(), &keys);
  expectOnlyKeys(name, keys, true);
  EXPECT_TRUE(PoseGraphConfig().validate().empty());
  EXPECT_TRUE(KeyframeMapConfig().validate().empty());
}

/// True when the key is in the table and `text` parses to a value other than the table's default.
template <typename T>
bool differsFromDefault(const std::vector<Setting<T>>& table, const std::string& key, const std::string& text) {
  const Setting<T>* s = findSetting(table, key);
  T parsed;
  return s != nullptr && s->set(&parsed, text) && s->get(parsed) != s->get(T());
}

TEST(ConfigFile, SensorPresetsHoldOnlyKeysThatDifferFromTheDefaultsEachWithAComment) {
  const std::string dir = std::string(SCL_PACKAGE_DIR) + "/config/sensors/";
  for (const std::string name : {"velodyne_hdl64", "velodyne_vlp16", "ouster_os1_64", "livox_avia", "livox_mid360"}) {
    const std::string path = dir + name + ".yaml";
    // Loaded on top of the defaults, as the evaluator's --config and the launch files do.
    Config config;
    std::string error;
    ASSERT_TRUE(loadConfigFile(path, &config, &error)) << error;
    EXPECT_TRUE(config.validate().empty()) << name;
    const YAML::Node file = YAML::LoadFile(path);
    ASSERT_TRUE(file.IsNull() || file.IsMap()) << name;
    std::ifstream text(path);
    std::string line, previous;
    for (; std::getline(text, line); previous = line) {
      if (line.empty() || line[0] == '#') continue;
      const std::string key = line.substr(0, line.find(':'));
      ASSERT_TRUE(file[key]) << name << ": '" << line << "' is not a key: value line";
      const std::string value = file[key].as<std::string>();
      EXPECT_TRUE(differsFromDefault(configSettings(), key, value) || differsFromDefault(nodeSettings(), key, value))
          << name << ": " << key << " is no key or repeats config/default.yaml";
      EXPECT_EQ(previous.rfind("#", 0), 0u) << name << ": " << key << " has no comment saying why";
    }
  }
}

TEST(Sequence, TimesShorterThanPosesIsALoadError) {
  const std::string dir = evalTemp("short_times");
  ASSERT_EQ(std::system(("mkdir -p " + dir + "/velodyne").c_str()), 0);
  std::ofstream poses(dir + "/poses.txt");
  for (int f = 0; f < 4; ++f) {
    poses << "1 0 0 " << f << " 0 1 0 0 0 0 1 0\n";
    std::ofstream(kitti::scanPath(dir, f), std::ios::binary);
  }
  poses.close();
  std::ofstream(dir + "/calib.txt") << "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  std::ofstream(dir + "/times.txt") << "0.0\n0.1\n0.2\n";
  Sequence sequence;
  std::string error;
  EXPECT_FALSE(loadSequence(dir, SequenceOptions(), &sequence, &error));
  EXPECT_NE(error.find(dir + "/times.txt"), std::string::npos) << error;
  EXPECT_NE(error.find("3 stamps"), std::string::npos) << error;
  EXPECT_NE(error.find("4 poses"), std::string::npos) << error;
  std::ofstream(dir + "/times.txt", std::ios::app) << "0.3\n";
  Sequence complete;
  EXPECT_TRUE(loadSequence(dir, SequenceOptions(), &complete, &error)) << error;
  EXPECT_EQ(complete.frames.size(), 4u);
}

/// Twice around a block, the second lap in reverse: every keyframe of lap 2 revisits lap 1. Written
/// once, in the KITTI layout with a drifting odometry.
const Sequence& simulatedLoop() {
  static Sequence sequence;
  if (!sequence.frames.empty()) return sequence;
  const std::string dir = evalTemp("loop");
  const test::Drive drive = test::blockDrive(true, 5);
  sim::SequenceData data;
  data.truth = drive.truth;
  data.times = drive.times;
  data.odometry = sim::driftedOdometry(data.truth, sim::DriftOptions());
  std::string error;
  EXPECT_GT(sim::writeSequence(dir, drive.world, drive.sensor, data, 0.0, 1, 2, &error), 1000.0) << error;
  EXPECT_TRUE(loadSequence(dir, SequenceOptions(), &sequence, &error)) << error;
  EXPECT_TRUE(sequence.odometry_from_file);
  EXPECT_EQ(sequence.frames.size(), data.truth.size());
  return sequence;
}

/// The settings the simulated loop's verified tests use: 30 recent keyframes excluded, verification on.
Config verifiedLoopConfig() {
  Config config;
  config.exclude_recent_frames = 30;
  config.verification.enabled = true;
  return config;
}

TEST(Evaluation, SimulatedLoopEndToEnd) {
  const Sequence& sequence = simulatedLoop();
  ASSERT_FALSE(sequence.frames.empty());
  std::string error;
  Config config;
  config.exclude_recent_frames = 30;
  const Evaluation e = evaluate(sequence, config, 5.0);
  EXPECT_EQ(e.rejected, 0u);
  EXPECT_EQ(e.outcomes.size(), sequence.frames.size() - 1);
  // The whole second lap revisits the first (in reverse).
  EXPECT_GT(e.metrics.revisits, 80u);
  EXPECT_GE(e.metrics.f1_max, 0.8);
  EXPECT_GE(e.metrics.recall_at_full_precision, 0.5);
  EXPECT_LT(e.metrics.yaw_error_median, 3.0);

  ASSERT_TRUE(writeResultsCsv(evalTemp("results.csv"), e, &error));
  std::ifstream csv(evalTemp("results.csv"));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("query,match,distance,yaw_rad", 0), 0u);
  ASSERT_TRUE(writeMetricsJson(evalTemp("metrics.json"), e, sequence, config, 5.0, &error));
  std::stringstream json;
  json << std::ifstream(evalTemp("metrics.json")).rdbuf();
  EXPECT_NE(json.str().find("\"recall_at_100_precision\""), std::string::npos);
}

TEST(Evaluation, VerifiedLoopsAreScoredOnTheirOwnQueriesWhenReportedLate) {
  const Sequence& sequence = simulatedLoop();
  ASSERT_FALSE(sequence.frames.empty());
  Config config;
  config.exclude_recent_frames = 30;
  config.verification.enabled = true;  // with the consistency check (on by default)
  const Evaluation e = evaluate(sequence, config, 5.0);
  ASSERT_TRUE(e.verification);
  const VerifiedMetrics& v = e.verified;
  EXPECT_GE(v.recall, 0.5);
  EXPECT_EQ(v.false_positives, 0u);
  EXPECT_LT(v.translation_error_median, 0.3);
  EXPECT_LT(v.yaw_error_median, 1.0);
  // The first loop of the revisit waits for the second and is scored on its own query.
  EXPECT_GE(v.reported_late, 1u);
  std::size_t late = 0;
  for (const auto& o : e.outcomes) {
    if (!o.reported_late) continue;
    ++late;
    EXPECT_GE(o.verified_match, 0);
    EXPECT_TRUE(o.verified_correct) << "query " << o.query;
  }
  EXPECT_EQ(late, v.reported_late);
  std::string error;
  ASSERT_TRUE(writeMetricsJson(evalTemp("verified.json"), e, sequence, config, 5.0, &error));
  std::stringstream json;
  json << std::ifstream(evalTemp("verified.json")).rdbuf();
  EXPECT_NE(json.str().find("\"reported_late\""), std::string::npos);
  EXPECT_NE(json.str().find("\"dropped_by_consistency\""), std::string::npos);
}

TEST(Evaluation, VerifiedLoopsCorrectTheDriftedTrajectoryAndHoldOffAFalseOne) {
  // The reference pose graph over the simulated loop's drifting odometry and its verified loops.
  const Sequence& sequence = simulatedLoop();
  ASSERT_FALSE(sequence.frames.empty());
  const Config config = verifiedLoopConfig();
  const Evaluation e = evaluate(sequence, config, 5.0);
  const TrajectoryCorrection c = correctTrajectory(sequence, e, config);
  ASSERT_TRUE(c.computed) << c.note;
  std::printf(
      "ATE RMSE: odometry %.3f m, corrected %.3f m (%zu loops), plain Scan Context %.3f m (%zu loops), "
      "with a false loop %.3f m\n",
      c.odometry.rmse, c.corrected.rmse, c.loops, c.plain.rmse, c.plain_loops, c.with_false_loop.rmse);
  EXPECT_EQ(c.loops, e.verified.true_positives + e.verified.false_positives);
  EXPECT_GT(c.odometry.rmse, 0.15) << "the simulated odometry should drift";
  EXPECT_LT(c.corrected.rmse, 0.6 * c.odometry.rmse);
  EXPECT_GE(c.false_loop_gap, 40.0) << "a false loop was added";
  EXPECT_LT(c.with_false_loop.rmse, c.corrected.rmse + 0.2 * c.odometry.rmse);
  ASSERT_EQ(c.corrected_poses.size(), sequence.frames.size());

  std::string error;
  ASSERT_TRUE(writeTrajectoryErrorJson(evalTemp("trajectory_error.json"), c, &error)) << error;
  std::stringstream json;
  json << std::ifstream(evalTemp("trajectory_error.json")).rdbuf();
  for (const char* key : {"\"odometry\"", "\"corrected\"", "\"plain_scan_context\"", "\"with_one_false_loop\""}) {
    EXPECT_NE(json.str().find(key), std::string::npos) << key;
  }
  ASSERT_TRUE(writeCorrectedTrajectoryCsv(evalTemp("trajectory_corrected.csv"), sequence, c, &error)) << error;
  std::ifstream csv(evalTemp("trajectory_corrected.csv"));
  std::string line;
  std::size_t rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, sequence.frames.size() + 1);

  EXPECT_TRUE(c.own_odometry);
  EXPECT_FALSE(c.in_prior);
  EXPECT_EQ(c.prior_loops, 0u);
  EXPECT_NE(json.str().find("\"odometry_source\": \"odom_poses.txt\""), std::string::npos);
  const std::string printed = trajectoryErrorLine(c);
  EXPECT_EQ(printed.rfind("trajectory error (ATE RMSE / max): odometry ", 0), 0u) << printed;
  EXPECT_NE(printed.find("corrected with the " + std::to_string(c.loops) + " loops"), std::string::npos) << printed;

  // Too few keyframes: nothing is computed, and the note and the printed line say why.
  Sequence three = sequence;
  three.frames.resize(2);
  three.truth.resize(2);
  three.odometry.resize(2);
  const TrajectoryCorrection none = correctTrajectory(three, e, config);
  EXPECT_FALSE(none.computed);
  EXPECT_EQ(trajectoryErrorLine(none), "trajectory error: not computed (fewer than 3 keyframes)");
}

TEST(Evaluation, WithoutOdometryTheLoopsCorrectThePerfectTrajectoryOnlyByTheirErrors) {
  // The loop sequence read without its odom_poses.txt (as --truth-odometry does, and as a real KITTI
  // sequence is): the truth is the odometry, its error 0; the verified loops' registration errors are
  // all that moves the corrected trajectory, by centimetres.
  ASSERT_FALSE(simulatedLoop().frames.empty());
  SequenceOptions options;
  options.use_odometry_file = false;
  Sequence sequence;
  std::string error;
  ASSERT_TRUE(loadSequence(simulatedLoop().dir, options, &sequence, &error)) << error;
  ASSERT_FALSE(sequence.odometry_from_file);
  const Config config = verifiedLoopConfig();
  const Evaluation e = evaluate(sequence, config, 5.0);
  const TrajectoryCorrection c = correctTrajectory(sequence, e, config);
  ASSERT_TRUE(c.computed) << c.note;
  std::printf("truth as the odometry: corrected ATE %.4f m (max %.4f m) with %zu loops\n", c.corrected.rmse,
              c.corrected.max, c.loops);
  EXPECT_FALSE(c.own_odometry);
  EXPECT_EQ(c.odometry.poses, sequence.frames.size());
  EXPECT_LT(c.odometry.rmse, 1e-9);
  EXPECT_GT(c.loops, 20u);
  EXPECT_GT(c.corrected.rmse, 0.0);
  EXPECT_LT(c.corrected.rmse, 0.1);
  EXPECT_NE(c.note.find("the truth is the odometry"), std::string::npos) << c.note;
  ASSERT_TRUE(writeTrajectoryErrorJson(evalTemp("truth_odometry.json"), c, &error)) << error;
  std::stringstream json;
  json << std::ifstream(evalTemp("truth_odometry.json")).rdbuf();
  for (const char* key : {"\"computed\": true", "\"odometry_source\": \"truth\"", "\"note\": \"no odometry",
                          "\"corrected\": {", "\"with_one_false_loop\""}) {
    EXPECT_NE(json.str().find(key), std::string::npos) << key << " in " << json.str();
  }
  EXPECT_NE(trajectoryErrorLine(c).find("odometry (the truth: no odometry of its own) 0.000 / 0.000 m"),
            std::string::npos)
      << trajectoryErrorLine(c);
}

TEST(Evaluation, CandidatesWhoseDataWasDroppedLeaveTheirTurnToKeptOnes) {
  // On a long run the cloud store keeps one keyframe's registration data in two, four, ... With one
  // registration per keyframe (verify_max_candidates 1), a best candidate without data must not take
  // the turn of the next one with data, or verified recall fades as the store thins.
  const Sequence& sequence = simulatedLoop();
  ASSERT_FALSE(sequence.frames.empty());
  Config config;
  config.exclude_recent_frames = 30;
  config.track_distance = 0.0;  // the descriptor's candidates alone
  config.verification.max_candidates = 1;
  const Evaluation full = evaluate(sequence, config, 5.0);
  pcl::PointCloud<pcl::PointXYZI> scan;
  std::string error;
  ASSERT_TRUE(kitti::readScan(kitti::scanPath(sequence.dir, sequence.frames.front()), &scan, &error)) << error;
  const double bytes = static_cast<double>(prepareCloud(viewOf(scan), config.verification).bytes());
  config.verification.max_bytes = std::max(1e6, bytes * static_cast<double>(sequence.frames.size()) / 3.0);
  const Evaluation thinned = evaluate(sequence, config, 5.0);
  std::size_t unverifiable = 0;
  for (const VerificationAttempt& a : thinned.attempts) {
    unverifiable += a.result.reason.find("unverifiable") != std::string::npos;
  }
  EXPECT_GT(unverifiable, 10u);  // the store did thin, and the best candidates were often dropped ones
  EXPECT_EQ(thinned.verified.false_positives, 0u);
  EXPECT_GE(full.verified.recall, 0.5);
  EXPECT_GE(thinned.verified.recall, 0.8 * full.verified.recall);
}

TEST(Evaluation, RealKittiFramesThatExist) {
  const char* env = std::getenv("SCL_SHARED_DATA");
  const std::string data = env ? env : SCL_SHARED_DATA;
  Sequence sequence;
  std::string error;
  SequenceOptions options;
  options.first = 700;
  options.last = 1600;
  ASSERT_TRUE(loadSequence(data + "/kitti/08", options, &sequence, &error)) << error;
  ASSERT_EQ(sequence.frames, (std::vector<int>{720, 1500}));
  EXPECT_EQ(sequence.missing_scans, 901u - 2u);
  Config config;
  config.exclude_recent_frames = 0;
  const Evaluation e = evaluate(sequence, config, 5.0);
  ASSERT_EQ(e.outcomes.size(), 1u);
  EXPECT_EQ(e.outcomes[0].query, 1500);
  EXPECT_EQ(e.outcomes[0].match, 720);
  EXPECT_TRUE(e.outcomes[0].revisit);
  EXPECT_TRUE(e.outcomes[0].correct);
  EXPECT_NEAR(e.outcomes[0].match_gap, 3.09, 0.01);
  EXPECT_LT(std::fabs(e.outcomes[0].yaw - e.outcomes[0].true_yaw), 6.0 * M_PI / 180.0);
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop
