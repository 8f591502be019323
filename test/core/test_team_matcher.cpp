// Several robots: records of one robot's keyframes joining another's TeamMatcher, registration data fetched
// on demand, loops between the robots on real scans, and the records a matcher refuses.
#include <unistd.h>

#include <fstream>

#include <gtest/gtest.h>

#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/team_matcher.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

Config teamConfig() {
  Config config;
  config.exclude_recent_frames = 0;
  config.consistency_min_support = 0;
  return config;
}

/// Robot A's keyframes: KITTI 08 720 and KITTI 00 94.
void robotA(LoopDetector* detector) {
  KeyframeInfo info;
  for (const auto& [sequence, frame] : {std::pair<const char*, int>{"08", 720}, {"00", 94}}) {
    info.stamp += 1.0;
    ASSERT_TRUE(detector->process(viewOf(test::kittiScan(sequence, frame)), info).accepted);
  }
}

TeamKeyframeId idOf(std::uint32_t keyframe) { return {"robot_a", 7, keyframe}; }

/// B's matcher holding A's two records.
void shareA(const LoopDetector& a, TeamMatcher* team) {
  for (std::uint32_t k = 0; k < 2; ++k) {
    const std::vector<std::uint8_t> record = keyframeRecord(a, k);
    std::string error;
    ASSERT_EQ(team->add(idOf(k), 0, record.data(), record.size(), &error), TeamMatcher::Added::kAdded) << error;
  }
}

TEST(TeamMatcher, FindsALoopIntoAnotherRobotsKeyframeOnceItsDataAreFetched) {
  LoopDetector a(teamConfig());
  robotA(&a);
  TeamMatcher team(teamConfig());
  shareA(a, &team);
  ASSERT_EQ(team.size(), 2u);
  EXPECT_EQ(team.clouds(), 0u);

  // Robot B sees KITTI 00 95, next to A's 94: the candidate's data are not here yet.
  const auto scan = test::kittiScan("00", 95);
  TeamMatch first = team.match(viewOf(scan), 2);
  EXPECT_FALSE(first.detection.verified);
  ASSERT_FALSE(first.to_fetch.empty());
  EXPECT_EQ(first.to_fetch.front(), idOf(1));  // the best candidate first
  // Asked for once: the next match waits for them instead of asking again.
  const TeamMatch again = team.match(viewOf(scan), 2);
  EXPECT_TRUE(again.to_fetch.empty());
  EXPECT_EQ(again.waiting, first.to_fetch);

  const std::vector<std::uint8_t> data = keyframeCloud(a, 1);
  std::string error;
  ASSERT_TRUE(team.attachCloud(idOf(1), data.data(), data.size(), &error)) << error;
  EXPECT_EQ(team.clouds(), 1u);
  const TeamMatch found = team.match(viewOf(scan), 2);
  ASSERT_TRUE(found.detection.verified);
  EXPECT_EQ(found.match, 1u);
  EXPECT_EQ(team.id(found.match), idOf(1));
  const Eigen::Isometry3d truth = test::kittiRelative("00", 95, 94);
  EXPECT_LT((found.detection.verifications.back().result.relative.translation() - truth.translation()).norm(), 0.1);
  // The record is the descriptor without the registration data: a few kilobytes, far less than the data.
  const std::size_t record_bytes = keyframeRecord(a, 1).size();
  EXPECT_LT(record_bytes, 6000u);
  EXPECT_GT(data.size(), 2 * record_bytes);
}

TEST(TeamMatcher, FindsAReverseRevisitAcrossRobots) {
  LoopDetector a(teamConfig());
  robotA(&a);
  TeamMatcher team(teamConfig());
  shareA(a, &team);
  const auto scan = test::kittiScan("08", 1500);  // 720's street, driven the other way
  const TeamMatch first = team.match(viewOf(scan), 2);
  ASSERT_FALSE(first.to_fetch.empty());
  EXPECT_EQ(first.to_fetch.front(), idOf(0));
  for (const TeamKeyframeId& id : first.to_fetch) {
    const std::vector<std::uint8_t> data = keyframeCloud(a, id.keyframe);
    ASSERT_TRUE(team.attachCloud(id, data.data(), data.size()));
  }
  const TeamMatch found = team.match(viewOf(scan), 2);
  ASSERT_TRUE(found.detection.verified);
  EXPECT_EQ(team.id(found.match), idOf(0));
  // A place A never saw is matched nowhere.
  const auto elsewhere = test::kittiScan("00", 198);
  TeamMatch none = team.match(viewOf(elsewhere), 2);
  for (const TeamKeyframeId& id : none.to_fetch) {
    const std::vector<std::uint8_t> data = keyframeCloud(a, id.keyframe);
    ASSERT_TRUE(team.attachCloud(id, data.data(), data.size()));
  }
  EXPECT_FALSE(team.match(viewOf(elsewhere), 2).detection.verified);
}

TEST(TeamMatcher, RefusesDuplicatesBadRecordsAndOtherSettingsByName) {
  LoopDetector a(teamConfig());
  robotA(&a);
  TeamMatcher team(teamConfig());
  shareA(a, &team);
  std::vector<std::uint8_t> record = keyframeRecord(a, 0);
  std::string error;
  EXPECT_EQ(team.add(idOf(0), 0, record.data(), record.size(), &error), TeamMatcher::Added::kDuplicate);
  EXPECT_EQ(team.size(), 2u);
  // A restarted node is another run: its keyframe 0 is new.
  EXPECT_EQ(team.add({"robot_a", 8, 0}, 0, record.data(), record.size(), &error), TeamMatcher::Added::kAdded);

  // A flipped byte fails a checksum; a truncated image, the size check; an invalid robot id, the name check.
  std::vector<std::uint8_t> corrupt = record;
  corrupt[corrupt.size() / 2] ^= 0x40;
  EXPECT_EQ(team.add(idOf(5), 0, corrupt.data(), corrupt.size(), &error), TeamMatcher::Added::kRefused);
  EXPECT_NE(error.find("checksum"), std::string::npos) << error;
  EXPECT_EQ(team.add(idOf(6), 0, record.data(), record.size() / 2, &error), TeamMatcher::Added::kRefused);
  EXPECT_EQ(team.add({"robot a/..", 7, 9}, 0, record.data(), record.size(), &error), TeamMatcher::Added::kRefused);
  EXPECT_EQ(team.add(idOf(7), 0, nullptr, 0, &error), TeamMatcher::Added::kRefused);

  // A robot describing with 72 sectors: refused, the setting named.
  Config other = teamConfig();
  other.num_sectors = 72;
  LoopDetector b(other);
  KeyframeInfo info;
  info.stamp = 1.0;
  ASSERT_TRUE(b.process(viewOf(test::kittiScan("00", 94)), info).accepted);
  const std::vector<std::uint8_t> foreign = keyframeRecord(b, 0);
  EXPECT_EQ(team.add({"robot_b", 1, 0}, 0, foreign.data(), foreign.size(), &error), TeamMatcher::Added::kRefused);
  EXPECT_NE(error.find("num_sectors"), std::string::npos) << error;
  EXPECT_EQ(team.size(), 3u);

  // Registration data: of an unknown keyframe, of another keyframe, or a record without data: refused.
  const std::vector<std::uint8_t> data0 = keyframeCloud(a, 0);
  EXPECT_FALSE(team.attachCloud(idOf(9), data0.data(), data0.size(), &error));
  EXPECT_FALSE(team.attachCloud(idOf(1), data0.data(), data0.size(), &error));
  EXPECT_NE(error.find("another keyframe"), std::string::npos) << error;
  EXPECT_FALSE(team.attachCloud(idOf(0), record.data(), record.size(), &error));
  EXPECT_EQ(team.clouds(), 0u);
}

/// The process's mapped memory (VmSize) [bytes]: what an arena maps counts whether or not the kernel has
/// backed it yet, so the figure does not depend on the machine's transparent huge page setting.
std::size_t mappedBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  statm >> pages;
  return pages * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

// A record held costs about what a keyframe of this robot's own costs (a descriptor, keys and bookkeeping,
// about 2.4 KB), not a 2 MB arena of its own each.
TEST(TeamMatcher, ARecordHeldCostsKilobytesNotAnArenaEach) {
  LoopDetector a(teamConfig());
  robotA(&a);
  TeamMatcher team(teamConfig());
  shareA(a, &team);  // the matcher's first chunks are mapped
  const std::vector<std::uint8_t> record = keyframeRecord(a, 0);
  constexpr std::uint32_t kRecords = 500;
  const std::size_t before = mappedBytes();
  for (std::uint32_t k = 0; k < kRecords; ++k) {
    ASSERT_EQ(team.add({"robot_c", 3, k}, 0, record.data(), record.size()), TeamMatcher::Added::kAdded);
  }
  const double per_record = (static_cast<double>(mappedBytes()) - before) / kRecords;
  EXPECT_LT(per_record, 20e3) << "bytes mapped per record held (" << record.size() << "-byte records)";
  EXPECT_EQ(team.size(), kRecords + 2u);
}

TEST(TeamMatcher, RobotIdsAreNamesThatRosAccepts) {
  EXPECT_TRUE(validRobotId("robot1"));
  EXPECT_TRUE(validRobotId("R_2"));
  EXPECT_TRUE(validRobotId(std::string(64, 'a')));
  EXPECT_FALSE(validRobotId(std::string(65, 'a')));
  EXPECT_FALSE(validRobotId(""));
  EXPECT_FALSE(validRobotId("1robot")) << "a ROS name must not begin with a digit";
  EXPECT_FALSE(validRobotId("_robot"));
  EXPECT_FALSE(validRobotId("robot/1"));
  EXPECT_FALSE(validRobotId("robot 1"));
}

TEST(TeamMatcher, FirstMissingFindsTheGapToFill) {
  LoopDetector a(teamConfig());
  robotA(&a);
  TeamMatcher team(teamConfig());
  EXPECT_EQ(team.firstMissing("robot_a", 7, 2), 0u);
  const std::vector<std::uint8_t> record = keyframeRecord(a, 1);
  ASSERT_EQ(team.add(idOf(1), 0, record.data(), record.size()), TeamMatcher::Added::kAdded);
  EXPECT_EQ(team.firstMissing("robot_a", 7, 2), 0u);  // 0 is missing
  const std::vector<std::uint8_t> first = keyframeRecord(a, 0);
  ASSERT_EQ(team.add(idOf(0), 0, first.data(), first.size()), TeamMatcher::Added::kAdded);
  EXPECT_EQ(team.firstMissing("robot_a", 7, 2), 2u);
  EXPECT_EQ(team.firstMissing("robot_a", 7, 5), 2u);
  EXPECT_EQ(team.firstMissing("robot_a", 7, 1), 1u);
  EXPECT_TRUE(keyframeRecord(a, 2).empty());
}

}  // namespace
}  // namespace scan_context_loop
