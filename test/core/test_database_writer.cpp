// Saving off the detector's thread: a snapshot taken in a moment is written later, on another thread,
// while the detector goes on, and the file is the one a save at that moment would have written.
#include <gtest/gtest.h>

#include <fstream>
#include <future>
#include <iterator>
#include <memory>
#include <thread>

#include "scan_context_loop/core/database_writer.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "../common/temp_dir.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

using test::TempDir;

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

KeyframeInfo keyframeAt(int i) {
  KeyframeInfo info;
  info.stamp = 1.0 + i;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(30.0 * i, 0.0, 0.0);
  info.pose = pose;
  return info;
}

void addStreets(LoopDetector* detector, int first, int count);

SaveOptions withClouds() {
  SaveOptions options;
  options.include_clouds = true;
  return options;
}

/// A verifying configuration whose registration budget is `share` times what the first `count` streets'
/// data take.
Config budgetFor(int count, double share) {
  Config config;
  config.exclude_recent_frames = 2;
  config.verification.enabled = true;
  LoopDetector probe(config);
  addStreets(&probe, 0, count);
  config.verification.max_bytes = share * static_cast<double>(probe.cloudStore().bytes());
  return config;
}

void addStreets(LoopDetector* detector, int first, int count) {
  for (int i = first; i < first + count; ++i) {
    ASSERT_TRUE(detector->process(viewOf(test::streetScene(500 + i)), keyframeAt(i)).accepted);
  }
}

TEST(DatabaseSnapshot, WrittenLaterItHoldsTheDatabaseAsItWasTaken) {
  TempDir dir;
  LoopDetector detector(budgetFor(6, 1.1));
  addStreets(&detector, 0, 6);
  std::string error;
  ASSERT_TRUE(saveDatabase(detector, dir.file("now.scl"), withClouds(), &error)) << error;
  const DatabaseSnapshot snapshot(detector, true);
  EXPECT_EQ(snapshot.size(), 6u);

  // The detector goes on: more keyframes, and the store halves, dropping the data of odd keyframes the
  // snapshot still shares (and freeing them, 64 per keyframe added, on the next keyframe).
  addStreets(&detector, 6, 12);
  ASSERT_GT(detector.cloudStore().stride(), 1u) << "the store never halved: the test proves nothing";
  ASSERT_EQ(detector.cloudStore().get(1), nullptr);
  ASSERT_TRUE(writeDatabase(snapshot, dir.file("later.scl"), false, &error)) << error;
  EXPECT_EQ(readAll(dir.file("later.scl")), readAll(dir.file("now.scl")));

  // Written on another thread while the detector adds keyframes (ThreadSanitizer checks this in
  // scripts/dev/test --sanitize).
  const DatabaseSnapshot busy(detector, true);
  ASSERT_TRUE(saveDatabase(detector, dir.file("busy_now.scl"), withClouds(), &error)) << error;
  bool written = false;
  std::string thread_error;
  std::thread writer([&] { written = writeDatabase(busy, dir.file("busy_later.scl"), false, &thread_error); });
  addStreets(&detector, 18, 6);
  writer.join();
  ASSERT_TRUE(written) << thread_error;
  EXPECT_EQ(readAll(dir.file("busy_later.scl")), readAll(dir.file("busy_now.scl")));
}

TEST(DatabaseSnapshot, AKeyframeGivenNewDataAfterwardsIsWrittenAsItWasTaken) {
  TempDir dir;
  LoopDetector detector(budgetFor(4, 100));
  addStreets(&detector, 0, 4);
  std::string error;
  ASSERT_TRUE(saveDatabase(detector, dir.file("now.scl"), withClouds(), &error)) << error;
  const DatabaseSnapshot snapshot(detector, true);

  // Keyframe 1 gets another gravity alignment and other data (as a team's fetched data replace a
  // keyframe's): the snapshot shares the chunk that held its alignment, which must be copied first.
  const Eigen::Matrix3f turned = Eigen::AngleAxisf(0.1f, Eigen::Vector3f::UnitX()).toRotationMatrix();
  ASSERT_NE(detector.cloudStore().get(2), nullptr);
  const VoxelCloud other = *detector.cloudStore().get(2);
  ASSERT_TRUE(detector.attachCloud(1, turned, other, &error)) << error;
  ASSERT_TRUE(detector.gravityAlignment(1).isApprox(turned));
  ASSERT_TRUE(writeDatabase(snapshot, dir.file("later.scl"), false, &error)) << error;
  EXPECT_EQ(readAll(dir.file("later.scl")), readAll(dir.file("now.scl")));

  // A snapshot taken after the change writes it.
  ASSERT_TRUE(writeDatabase(DatabaseSnapshot(detector, true), dir.file("after.scl"), false, &error)) << error;
  EXPECT_NE(readAll(dir.file("after.scl")), readAll(dir.file("now.scl")));
  PriorSessions read;
  ASSERT_TRUE(readDatabaseFile(dir.file("after.scl"), detector.config(), &read, &error)) << error;
  ASSERT_EQ(read.gravity_alignment.size(), 4u);
  EXPECT_TRUE(read.gravity_alignment[1].isApprox(turned, 1e-6f));
  EXPECT_TRUE(read.gravity_alignment[0].isApprox(detector.gravityAlignment(0), 1e-6f));
}

// A robot of a team serves each of its keyframes from a snapshot kept as long as the node runs: held
// weakly, the registration data the store drops for its budget are freed, and the snapshot says so.
TEST(DatabaseSnapshot, HeldWeaklyItLetsTheStoreFreeWhatItDrops) {
  LoopDetector detector(budgetFor(4, 1.0));
  addStreets(&detector, 0, 2);
  DatabaseSnapshot odd(detector, true, nullptr, 1, 1), even(detector, true, nullptr, 0, 1);
  odd.holdCloudsWeakly();
  even.holdCloudsWeakly();
  bool complete = false;
  const std::vector<std::uint8_t> before = encodeDatabase(odd.strengthened(&complete));
  EXPECT_TRUE(complete);
  ASSERT_EQ(before, encodeDatabase(DatabaseSnapshot(detector, true, nullptr, 1, 1)));
  // Past the budget the store keeps every second keyframe: keyframe 1's data go, 0's stay.
  addStreets(&detector, 2, 8);  // the dropped clouds are freed by the adds after the halving
  ASSERT_GT(detector.cloudStore().stride(), 1u);
  ASSERT_EQ(detector.cloudStore().get(1), nullptr);
  (void)odd.strengthened(&complete);
  EXPECT_FALSE(complete) << "a weak snapshot kept a dropped cloud alive";
  (void)even.strengthened(&complete);
  EXPECT_TRUE(complete);
}

TEST(DatabaseSnapshot, ItsOwnerKeepsTheKeyframesAliveAfterTheDetectorIsReplaced) {
  TempDir dir;
  auto detector = std::make_shared<LoopDetector>(budgetFor(1, 100));
  addStreets(detector.get(), 0, 4);
  std::string error;
  ASSERT_TRUE(saveDatabase(*detector, dir.file("now.scl"), withClouds(), &error)) << error;
  const DatabaseSnapshot snapshot(*detector, true, detector);
  detector = std::make_shared<LoopDetector>(budgetFor(1, 100));  // a reset: the snapshot holds the old one
  ASSERT_TRUE(writeDatabase(snapshot, dir.file("later.scl"), false, &error)) << error;
  EXPECT_EQ(readAll(dir.file("later.scl")), readAll(dir.file("now.scl")));
}

// cancel() stops the background write in progress: it reports the cancellation, the file it would have
// replaced stays whole, and nothing else is left; the writer takes the next write as usual.
TEST(DatabaseWriter, ACancelledBackgroundWriteKeepsTheOldFile) {
  TempDir dir;
  LoopDetector detector(budgetFor(1, 100));
  addStreets(&detector, 0, 3);
  DatabaseWriter writer;
  std::string error;
  ASSERT_TRUE(writer.write(DatabaseSnapshot(detector, false), dir.file("a.scl"), false, &error)) << error;
  const std::string before = readAll(dir.file("a.scl"));
  addStreets(&detector, 3, 2);
  std::promise<std::string> reported;
  ASSERT_TRUE(writer.writeInBackground(DatabaseSnapshot(detector, true), dir.file("a.scl"), false,
                                       [&](const std::string& e, double) { reported.set_value(e); }));
  writer.cancel();
  const std::string outcome = reported.get_future().get();
  // The write may have ended before the cancel reached it (a slow test machine); if not, it says it was
  // cancelled. AtomicFileWriter.ACancelledWriteLeavesTheTargetAndNoTemporaryFile fixes the order.
  if (!outcome.empty()) {
    EXPECT_NE(outcome.find("cancelled"), std::string::npos) << outcome;
    EXPECT_EQ(readAll(dir.file("a.scl")), before) << "a cancelled write replaced the file";
  }
  EXPECT_TRUE(dir.entries() == std::vector<std::string>{"a.scl"}) << "the cancelled write left a file";
  EXPECT_FALSE(writer.busy());
  EXPECT_TRUE(writer.waitFor(0.0));
  ASSERT_TRUE(writer.write(DatabaseSnapshot(detector, false), dir.file("a.scl"), false, &error)) << error;
  EXPECT_NE(readAll(dir.file("a.scl")), before);
}

TEST(DatabaseWriter, OneBackgroundWriteAtATimeReportedWhenItEnds) {
  TempDir dir;
  LoopDetector detector(budgetFor(1, 100));
  addStreets(&detector, 0, 3);
  DatabaseWriter writer;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::promise<std::string> reported;
  ASSERT_TRUE(writer.writeInBackground(DatabaseSnapshot(detector, false), dir.file("a.scl"), false,
                                       [&](const std::string& error, double seconds) {
                                         EXPECT_GE(seconds, 0.0);
                                         released.wait();  // the write is done; its thread waits here
                                         reported.set_value(error);
                                       }));
  EXPECT_TRUE(writer.busy());
  EXPECT_FALSE(writer.writeInBackground(DatabaseSnapshot(detector, false), dir.file("b.scl"), false, nullptr))
      << "a second background write started while the first was in progress";
  release.set_value();
  EXPECT_EQ(reported.get_future().get(), "");
  writer.wait();
  EXPECT_FALSE(writer.busy());
  PriorSessions sessions;
  std::string error;
  ASSERT_TRUE(readDatabaseFile(dir.file("a.scl"), detector.config(), &sessions, &error)) << error;
  EXPECT_EQ(sessions.keyframes.size(), 3u);
  EXPECT_TRUE(dir.entries() == std::vector<std::string>{"a.scl"}) << "the refused write wrote something";

  // A write that fails reports why, and the writer takes the next one.
  std::promise<std::string> failed;
  ASSERT_TRUE(writer.writeInBackground(DatabaseSnapshot(detector, false), dir.file("missing/c.scl"), false,
                                       [&](const std::string& error, double) { failed.set_value(error); }));
  EXPECT_NE(failed.get_future().get(), "");
  writer.wait();
  ASSERT_TRUE(writer.write(DatabaseSnapshot(detector, true), dir.file("a.scl"), true, &error)) << error;
  EXPECT_TRUE((dir.entries() == std::vector<std::string>{"a.scl", "a.scl.bak"}));
}

}  // namespace
}  // namespace scan_context_loop
