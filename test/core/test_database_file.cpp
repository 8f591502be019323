// The database file: a saved and loaded database answers like the original; every damaged or
// mismatched file is refused with a clear error and leaves the running database as it was; saving
// replaces a file atomically.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <memory_resource>
#include <new>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "scan_context_loop/core/crc32.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/registration.h"
#include "test_scenes.h"
#include "../common/temp_dir.h"

namespace scan_context_loop {
namespace {

namespace fs = std::filesystem;

// Byte offsets of header fields (doc/database_file.md).
constexpr std::size_t kVersionAt = 5, kSectorsAt = 17, kKeyframesAt = 63, kSessionsAt = 71, kPayloadSizeAt = 75,
                      kPayloadCrcAt = 83, kHeaderCrcAt = 87, kHeaderBytes = 91;
// The verified drive's files: four keyframe records with poses (29 + 96 bytes and the 20 x 60
// descriptor's 1,584: occupied_columns, 20 x 60 i8 unit columns, 60 flags, 20 + 60 f32 keys), then the
// registration data; in the first keyframe's, its gravity alignment (9 f32), the flag, the voxel count,
// the compressed size, the LZ4 data.
constexpr std::size_t kColumnBytes = 20 * 60, kDescriptorBytes = 4 + kColumnBytes + 60 + 4 * (20 + 60);
constexpr std::size_t kRecordBytes = 29 + 96 + kDescriptorBytes, kDescriptorAt = kHeaderBytes + 29 + 96,
                      kCloudsAt = kHeaderBytes + 4 * kRecordBytes, kCloudFlagAt = kCloudsAt + 36;

using test::TempDir;

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
void put(std::vector<std::uint8_t>* bytes, std::size_t at, T value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) (*bytes)[at + i] = static_cast<std::uint8_t>(bits >> (8 * i));
}

/// Makes both checksums right again after an edit, so that only the edit itself can be refused.
void rewriteChecksums(std::vector<std::uint8_t>* bytes) {
  put(bytes, kPayloadSizeAt, std::uint64_t(bytes->size() - kHeaderBytes));
  put(bytes, kPayloadCrcAt, crc32(bytes->data() + kHeaderBytes, bytes->size() - kHeaderBytes));
  put(bytes, kHeaderCrcAt, crc32(bytes->data(), kHeaderCrcAt));
}

/// `raw` as an LZ4 block of literals only (a valid block that LZ4 decompresses back to `raw`).
std::vector<std::uint8_t> lz4Literals(const std::vector<std::uint8_t>& raw) {
  std::vector<std::uint8_t> block{static_cast<std::uint8_t>(std::min<std::size_t>(raw.size(), 15) << 4)};
  if (raw.size() >= 15) {
    std::size_t rest = raw.size() - 15;
    for (; rest >= 255; rest -= 255) block.push_back(255);
    block.push_back(static_cast<std::uint8_t>(rest));
  }
  block.insert(block.end(), raw.begin(), raw.end());
  return block;
}

/// A file's first registration data record (after its gravity alignment and flag) replaced by a voxel
/// count and compressed bytes, the sizes and checksums made right.
std::vector<std::uint8_t> withFirstCloud(const std::vector<std::uint8_t>& file, std::uint32_t voxels,
                                         const std::vector<std::uint8_t>& packed) {
  std::uint32_t old_packed = 0;
  for (int i = 3; i >= 0; --i) old_packed = old_packed << 8 | file[kCloudFlagAt + 5 + i];
  const std::size_t head = kCloudFlagAt + 9, tail = file.size() - head - old_packed;
  std::vector<std::uint8_t> bytes(head + packed.size() + tail);
  std::memcpy(bytes.data(), file.data(), head);
  std::memcpy(bytes.data() + head, packed.data(), packed.size());
  std::memcpy(bytes.data() + head + packed.size(), file.data() + head + old_packed, tail);
  put(&bytes, kCloudFlagAt + 1, voxels);
  put(&bytes, kCloudFlagAt + 5, static_cast<std::uint32_t>(packed.size()));
  rewriteChecksums(&bytes);
  return bytes;
}

/// The registration data of `means.size()` voxels: the means, then each normal (up, planar).
std::vector<std::uint8_t> voxelBytes(const std::vector<Eigen::Vector3f>& means) {
  std::vector<std::uint8_t> raw(means.size() * 16);
  for (std::size_t i = 0; i < means.size(); ++i) {
    for (int c = 0; c < 3; ++c) put(&raw, 12 * i + 4 * c, means[i][c]);
    const std::uint8_t normal[4] = {0, 0, 127, VoxelCloud::kPlanar};
    std::memcpy(&raw[12 * means.size() + 4 * i], normal, 4);
  }
  return raw;
}

KeyframeInfo taggedAt(double stamp, double x, std::int64_t tag = -1) {
  KeyframeInfo info;
  info.stamp = stamp;
  info.tag = tag;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, 0.5 * x, 0.1);
  pose.linear() = Eigen::AngleAxisd(0.01 * x, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  info.pose = pose;
  return info;
}

Config descriptorConfig() {
  Config c;
  c.verification.enabled = false;
  c.exclude_recent_frames = 3;
  return c;
}

/// Two sessions of streets: 12 places 10 m apart, then (stamps from 0 again) 6 more, one without a pose.
void drive(LoopDetector* detector) {
  for (int i = 0; i < 12; ++i) {
    ASSERT_TRUE(detector->process(viewOf(test::streetScene(300 + i)), taggedAt(100.0 + i, 10.0 * i, i)).accepted);
  }
  detector->startSession();
  for (int i = 0; i < 6; ++i) {
    KeyframeInfo info = taggedAt(1.0 + i, 5.0 * i, 100 + i);
    if (i == 2) info.pose.reset();
    ASSERT_TRUE(detector->process(viewOf(test::streetScene(400 + i)), info).accepted);
  }
}

/// The verification drive of test_consistency.cpp: four streets 30 m apart.
Config verifiedConfig() {
  Config c;
  c.exclude_recent_frames = 2;
  c.verification.enabled = true;
  c.consistency_min_support = 0;  // report each verified loop at once
  return c;
}

void verifiedDrive(LoopDetector* detector) {
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(detector->process(viewOf(test::streetScene(21 + i)), taggedAt(1.0 + i, 30.0 * i)).accepted);
  }
}

void expectSameDetection(const Detection& a, const Detection& b) {
  EXPECT_EQ(a.accepted, b.accepted);
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.query.eligible, b.query.eligible);
  EXPECT_EQ(a.query.matched, b.query.matched);
  ASSERT_EQ(a.query.candidates.size(), b.query.candidates.size());
  for (std::size_t i = 0; i < a.query.candidates.size(); ++i) {
    const Candidate &x = a.query.candidates[i], &y = b.query.candidates[i];
    EXPECT_EQ(x.index, y.index);
    EXPECT_EQ(x.ring_key_distance, y.ring_key_distance);
    EXPECT_EQ(x.alignment.distance, y.alignment.distance);
    EXPECT_EQ(x.alignment.shift, y.alignment.shift);
    EXPECT_EQ(x.alignment.yaw, y.alignment.yaw);
    EXPECT_EQ(x.viewpoint, y.viewpoint);
  }
  EXPECT_EQ(a.verified, b.verified);
  ASSERT_EQ(a.verifications.size(), b.verifications.size());
  for (std::size_t i = 0; i < a.verifications.size(); ++i) {
    const VerificationResult &x = a.verifications[i].result, &y = b.verifications[i].result;
    EXPECT_EQ(a.verifications[i].index, b.verifications[i].index);
    EXPECT_EQ(x.accepted, y.accepted);
    EXPECT_EQ(x.reason, y.reason);
    EXPECT_EQ(x.inlier_ratio, y.inlier_ratio);
    EXPECT_TRUE(x.relative.matrix() == y.relative.matrix());
  }
  ASSERT_EQ(a.loops.size(), b.loops.size());
  for (std::size_t i = 0; i < a.loops.size(); ++i) EXPECT_EQ(a.loops[i].match, b.loops[i].match);
}

/// Queries: revisits of both sessions (turned, moved a little) and a street never seen.
std::vector<pcl::PointCloud<pcl::PointXYZ>> queries() {
  return {test::rotateTranslate(test::streetScene(303), 0.7, 0.5, -0.3),
          test::rotateTranslate(test::streetScene(310), -2.0), test::rotateTranslate(test::streetScene(402), 3.1, 1.0),
          test::streetScene(999)};
}

TEST(Crc32, MatchesTheStandardCheckValueWholeAndInPieces) {
  const char* text = "123456789";
  EXPECT_EQ(crc32(text, 9), 0xCBF43926u);
  EXPECT_EQ(crc32(text + 4, 5, crc32(text, 4)), 0xCBF43926u);
  EXPECT_EQ(crc32(text, 0), 0u);
}

TEST(DatabaseFile, ALoadedDatabaseHoldsTheSameKeyframesAndAnswersEveryQueryExactly) {
  TempDir dir;
  LoopDetector original(descriptorConfig());
  drive(&original);
  std::string error;
  ASSERT_TRUE(saveDatabase(original, dir.file("db.scl"), SaveOptions(), &error)) << error;
  LoopDetector loaded(descriptorConfig());
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &loaded, &error)) << error;

  const Database &a = original.database(), &b = loaded.database();
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Keyframe &x = a.keyframe(i), &y = b.keyframe(i);
    EXPECT_EQ(x.session, y.session) << i;
    EXPECT_EQ(x.info.stamp, y.info.stamp);
    EXPECT_EQ(x.info.tag, y.info.tag);
    EXPECT_EQ(x.path_length, y.path_length);
    ASSERT_EQ(x.info.pose.has_value(), y.info.pose.has_value()) << i;
    if (x.info.pose) EXPECT_TRUE(x.info.pose->matrix() == y.info.pose->matrix());
    EXPECT_EQ(x.descriptor.unit_columns, y.descriptor.unit_columns);
    EXPECT_EQ(x.descriptor.column_occupied, y.descriptor.column_occupied);
    EXPECT_EQ(x.descriptor.ring_key, y.descriptor.ring_key);
    EXPECT_EQ(x.descriptor.sector_key, y.descriptor.sector_key);
    EXPECT_EQ(x.descriptor.occupied_columns, y.descriptor.occupied_columns);
  }
  // A file this small (under 1 MB of descriptors: a team's record, a few keyframes) is decoded onto the
  // heap; a large one into an arena (ALargeFileIsDecodedIntoOneArenaThatTheDatabaseKeeps).
  const std::pmr::memory_resource* memory = b.keyframe(0).descriptor.unit_columns.get_allocator().resource();
  EXPECT_EQ(memory, std::pmr::get_default_resource());
  EXPECT_EQ(b.keyframe(a.size() - 1).descriptor.sector_key.get_allocator().resource(), memory);
  EXPECT_EQ(a.keyframe(17).session, 1u);
  // Into an empty database the sessions keep their numbers, and the next keyframe starts session 2.
  EXPECT_EQ(b.session(), 2u);
  EXPECT_EQ(b.sessionStart(), a.size());
  EXPECT_EQ(b.indexedCount(), a.size()) << "every loaded keyframe is searchable at once";

  // The original in the same state (its keyframes all in earlier sessions) and the loaded one give the
  // same candidates, distances and shifts for every query, and stay in step as keyframes are added.
  original.startSession();
  const std::size_t saved = a.size();
  int matched = 0;
  double stamp = 0.0;
  for (const auto& cloud : queries()) {
    stamp += 1.0;
    const Detection x = original.process(viewOf(cloud), taggedAt(stamp, 0.0));
    const Detection y = loaded.process(viewOf(cloud), taggedAt(stamp, 0.0));
    SCOPED_TRACE(stamp);
    expectSameDetection(x, y);
    EXPECT_EQ(x.query.eligible, saved) << "all saved keyframes are candidates, the new ones are recent";
    matched += x.query.matched;
  }
  EXPECT_EQ(matched, 3) << "the three revisits match, the new street does not";
}

// A large file's descriptors are decoded into one arena (far fewer page faults in a new process), and they
// stay there when the database takes them (moved, not copied to the heap).
TEST(DatabaseFile, ALargeFileIsDecodedIntoOneArenaThatTheDatabaseKeeps) {
  TempDir dir;
  LoopDetector small(descriptorConfig());
  drive(&small);
  PriorSessions many;
  for (std::size_t i = 0; i < 800; ++i) {  // 800 descriptors of about 1.7 KB: over the 1 MB threshold
    Keyframe k = small.database().keyframe(i % small.database().size());
    k.info.stamp = 1.0 + 0.1 * static_cast<double>(i);
    k.session = 0;
    many.keyframes.push_back(std::move(k));
  }
  LoopDetector original(descriptorConfig());
  std::string error;
  ASSERT_TRUE(original.appendSessions(std::move(many), &error)) << error;
  ASSERT_TRUE(saveDatabase(original, dir.file("many.scl"), SaveOptions(), &error)) << error;
  LoopDetector loaded(descriptorConfig());
  ASSERT_TRUE(loadDatabase(dir.file("many.scl"), &loaded, &error)) << error;
  ASSERT_EQ(loaded.database().size(), 800u);
  const std::pmr::memory_resource* memory =
      loaded.database().keyframe(0).descriptor.unit_columns.get_allocator().resource();
  EXPECT_NE(memory, std::pmr::get_default_resource());
  EXPECT_EQ(loaded.database().keyframe(799).descriptor.sector_key.get_allocator().resource(), memory);
  EXPECT_EQ(loaded.database().keyframe(799).descriptor.ring_key,
            small.database().keyframe(799 % small.database().size()).descriptor.ring_key);
}

TEST(DatabaseFile, LoadedSessionsFollowTheRunningOnesAndANewSessionBegins) {
  TempDir dir;
  LoopDetector saved(descriptorConfig());
  drive(&saved);
  std::string error;
  ASSERT_TRUE(saveDatabase(saved, dir.file("db.scl"), SaveOptions(), &error)) << error;

  LoopDetector running(descriptorConfig());
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(running.process(viewOf(test::streetScene(500 + i)), taggedAt(50.0 + i, i)).accepted);
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &running, &error)) << error;
  const Database& db = running.database();
  ASSERT_EQ(db.size(), 3 + saved.database().size());
  EXPECT_EQ(db.keyframe(2).session, 0u);
  EXPECT_EQ(db.keyframe(3).session, 1u);
  EXPECT_EQ(db.keyframe(db.size() - 1).session, 2u);
  EXPECT_EQ(db.session(), 3u);
  EXPECT_EQ(db.sessionStart(), db.size());
  // The new session may restart its stamps, and every keyframe before it is a candidate, including the
  // three running ones the recent-keyframe window hid until now.
  const Detection next = running.process(viewOf(test::streetScene(303)), taggedAt(0.0, 0.0));
  ASSERT_TRUE(next.accepted) << next.error;
  EXPECT_EQ(next.query.eligible, db.size() - 1);
  ASSERT_TRUE(next.query.best());
  EXPECT_EQ(next.query.best()->index, 3u + 3u) << "street 303 is the saved keyframe 3";

  // A second load joins after the new session, which is empty: it takes that session's number.
  LoopDetector twice(descriptorConfig());
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &twice, &error)) << error;
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &twice, &error)) << error;
  EXPECT_EQ(twice.database().keyframe(saved.database().size()).session, 2u);
  EXPECT_EQ(twice.database().session(), 4u);
}

TEST(DatabaseFile, WithCloudsTheLoadedKeyframesVerifyTheSameLoop) {
  TempDir dir;
  LoopDetector original(verifiedConfig());
  verifiedDrive(&original);
  std::string error;
  SaveOptions with_clouds;
  with_clouds.include_clouds = true;
  ASSERT_TRUE(saveDatabase(original, dir.file("clouds.scl"), with_clouds, &error)) << error;
  ASSERT_TRUE(saveDatabase(original, dir.file("plain.scl"), SaveOptions(), &error)) << error;
  EXPECT_GT(fs::file_size(dir.file("clouds.scl")), fs::file_size(dir.file("plain.scl")) + 4 * 1000);

  LoopDetector loaded(verifiedConfig()), without(verifiedConfig());
  ASSERT_TRUE(loadDatabase(dir.file("clouds.scl"), &loaded, &error)) << error;
  ASSERT_TRUE(loadDatabase(dir.file("plain.scl"), &without, &error)) << error;
  EXPECT_EQ(loaded.cloudStore().stored(), 4u);
  EXPECT_EQ(without.cloudStore().stored(), 0u);
  for (std::size_t i = 0; i < 4; ++i) {
    const VoxelCloud &x = *original.cloudStore().get(i), &y = *loaded.cloudStore().get(i);
    EXPECT_EQ(x.means, y.means);
    EXPECT_EQ(x.normals, y.normals);
    EXPECT_EQ(x.resolution, y.resolution);
    EXPECT_TRUE(original.gravityAlignment(i) == loaded.gravityAlignment(i));
  }

  // The drive comes back to street 21 in a new session.
  original.startSession();
  const KeyframeInfo back = taggedAt(0.5, 0.0);
  const auto cloud = test::rotateTranslate(test::streetScene(21), 0.2, 1.0);
  const Detection x = original.process(viewOf(cloud), back);
  const Detection y = loaded.process(viewOf(cloud), back);
  ASSERT_TRUE(x.verified);
  ASSERT_EQ(x.loops.size(), 1u);
  EXPECT_EQ(x.loops[0].match, 0u);
  expectSameDetection(x, y);
  // Without the clouds the same candidate is found but cannot be verified.
  const Detection z = without.process(viewOf(cloud), back);
  EXPECT_FALSE(z.verified);
  ASSERT_FALSE(z.verifications.empty());
  EXPECT_EQ(z.verifications[0].index, 0u);
  EXPECT_NE(z.verifications[0].result.reason.find("unverifiable"), std::string::npos);
}

TEST(DatabaseFile, AnEmptyDatabaseRoundTrips) {
  TempDir dir;
  LoopDetector empty(descriptorConfig()), loaded(descriptorConfig());
  std::string error;
  ASSERT_TRUE(saveDatabase(empty, dir.file("empty.scl"), SaveOptions(), &error)) << error;
  EXPECT_EQ(fs::file_size(dir.file("empty.scl")), kHeaderBytes);
  ASSERT_TRUE(loadDatabase(dir.file("empty.scl"), &loaded, &error)) << error;
  EXPECT_EQ(loaded.database().size(), 0u);
  EXPECT_EQ(loaded.database().session(), 0u);
}

// Corrected poses (a backend's, DatabaseSnapshot::correctPoses): the session holding them is saved
// wholly in the corrected frame with pose flag 2, the other session as before; a load keeps them marked,
// and saving the loaded database again writes the same bytes. Without corrections the bytes are today's.
TEST(DatabaseFile, CorrectedPosesAreSavedMarkedForTheirWholeSessionAndSurviveALoad) {
  TempDir dir;
  LoopDetector original(descriptorConfig());
  drive(&original);  // session 0: keyframes 0-11; session 1: 12-17, keyframe 14 without a pose
  std::string error;
  ASSERT_TRUE(saveDatabase(original, dir.file("plain.scl"), SaveOptions(), &error)) << error;
  DatabaseSnapshot none(original, false), empty(original, false);
  empty.correctPoses(std::make_shared<const PoseCorrections>());
  ASSERT_TRUE(writeDatabase(none, dir.file("none.scl"), false, &error)) << error;
  ASSERT_TRUE(writeDatabase(empty, dir.file("empty.scl"), false, &error)) << error;
  EXPECT_EQ(readBytes(dir.file("none.scl")), readBytes(dir.file("plain.scl")));
  EXPECT_EQ(readBytes(dir.file("empty.scl")), readBytes(dir.file("plain.scl"))) << "no correction, no change";

  const Database& a = original.database();
  Eigen::Isometry3d first = Eigen::Isometry3d::Identity(), second = Eigen::Isometry3d::Identity();
  first.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  first.translation() = Eigen::Vector3d(5.0, -2.0, 0.5);
  second.translation() = Eigen::Vector3d(-1.0, 3.0, 0.0);
  auto corrections = std::make_shared<PoseCorrections>();
  (*corrections)[13] = first * *a.keyframe(13).info.pose;
  (*corrections)[16] = second * *a.keyframe(16).info.pose;
  DatabaseSnapshot corrected(original, false);
  corrected.correctPoses(corrections);
  ASSERT_TRUE(writeDatabase(corrected, dir.file("corrected.scl"), false, &error)) << error;

  LoopDetector loaded(descriptorConfig());
  ASSERT_TRUE(loadDatabase(dir.file("corrected.scl"), &loaded, &error)) << error;
  const Database& b = loaded.database();
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Keyframe &x = a.keyframe(i), &y = b.keyframe(i);
    SCOPED_TRACE("keyframe " + std::to_string(i));
    EXPECT_EQ(x.info.stamp, y.info.stamp);
    EXPECT_EQ(x.info.tag, y.info.tag);
    EXPECT_EQ(x.descriptor.unit_columns, y.descriptor.unit_columns);
    ASSERT_EQ(x.info.pose.has_value(), y.info.pose.has_value());
    if (i < 12 || i == 14) {  // session 0, and the keyframe without a pose
      EXPECT_FALSE(y.corrected_pose);
      if (x.info.pose) {
        EXPECT_TRUE(x.info.pose->matrix() == y.info.pose->matrix());
      }
      continue;
    }
    EXPECT_TRUE(y.corrected_pose);
    const Eigen::Isometry3d expected = (i < 16 ? first : second) * *x.info.pose;
    EXPECT_LT((y.info.pose->matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  }
  EXPECT_FALSE(original.database().keyframe(13).corrected_pose) << "the stored keyframes are untouched";

  // The loaded database saved again: the same bytes, its corrected poses still marked.
  ASSERT_TRUE(saveDatabase(loaded, dir.file("again.scl"), SaveOptions(), &error)) << error;
  EXPECT_EQ(readBytes(dir.file("again.scl")), readBytes(dir.file("corrected.scl")));
  // Only the pose flags of session 1's keyframes with a pose, and their poses, differ from the plain file.
  const std::vector<std::uint8_t> plain = readBytes(dir.file("plain.scl")),
                                  marked = readBytes(dir.file("corrected.scl"));
  ASSERT_EQ(plain.size(), marked.size());
  std::size_t at = kHeaderBytes;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::size_t flag = at + 8 + 4 + 8 + 8;
    EXPECT_EQ(int(plain[flag]), a.keyframe(i).info.pose ? 1 : 0) << i;
    EXPECT_EQ(int(marked[flag]), !a.keyframe(i).info.pose ? 0 : i < 12 ? 1 : 2) << i;
    at = flag + 1 + (plain[flag] ? 96 : 0) + kDescriptorBytes;
  }
  EXPECT_EQ(at, plain.size());
}

TEST(DatabaseFile, APipelineForgetsItsOdometryOnLoad) {
  TempDir dir;
  LoopDetector saved(descriptorConfig());
  drive(&saved);
  std::string error;
  ASSERT_TRUE(saveDatabase(saved, dir.file("db.scl"), SaveOptions(), &error)) << error;
  Config c = descriptorConfig();
  c.keyframe_min_distance = 5.0;
  KeyframePipeline pipeline(c);
  ASSERT_TRUE(pipeline.process(viewOf(test::streetScene(1)), taggedAt(1.0, 0.0)).accepted);
  EXPECT_FALSE(pipeline.process(viewOf(test::streetScene(1)), taggedAt(2.0, 0.0)).selected) << "has not moved";
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &pipeline, &error)) << error;
  const Detection d = pipeline.process(viewOf(test::streetScene(1)), taggedAt(3.0, 0.0));
  EXPECT_TRUE(d.selected) << "the first keyframe of the new session";
  EXPECT_TRUE(d.accepted) << d.error;
  EXPECT_EQ(pipeline.detector().database().keyframe(d.index).session, 3u);
}

/// Damaged and mismatched files: each is refused with an error naming the problem, and the detector
/// that tried to load it is exactly as it was (same size and session, and a query answers as in a twin
/// that never tried).
class DamagedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    LoopDetector source(verifiedConfig());
    verifiedDrive(&source);
    std::string error;
    SaveOptions with_clouds;
    with_clouds.include_clouds = true;
    ASSERT_TRUE(saveDatabase(source, dir_.file("good.scl"), with_clouds, &error)) << error;
    ASSERT_TRUE(saveDatabase(source, dir_.file("plain.scl"), SaveOptions(), &error)) << error;
    good_ = readBytes(dir_.file("good.scl"));
    plain_ = readBytes(dir_.file("plain.scl"));
    ASSERT_GT(good_.size(), kHeaderBytes + 1000);
  }

  /// A running detector with three keyframes of its own, the streets of the saved file (the twin is
  /// made the same way).
  static std::unique_ptr<LoopDetector> running() {
    auto detector = std::make_unique<LoopDetector>(verifiedConfig());
    for (int i = 0; i < 3; ++i) detector->process(viewOf(test::streetScene(21 + i)), taggedAt(1.0 + i, 30.0 * i));
    return detector;
  }

  /// Loads `path` into a running detector, expects an error containing every one of `words`, then
  /// checks that nothing changed.
  void expectRefused(const std::string& path, const std::vector<std::string>& words) {
    auto tried = running(), twin = running();
    std::string error;
    EXPECT_FALSE(loadDatabase(path, tried.get(), &error));
    for (const std::string& w : words) EXPECT_NE(error.find(w), std::string::npos) << "'" << w << "' in: " << error;
    EXPECT_EQ(tried->database().size(), 3u);
    EXPECT_EQ(tried->database().session(), 0u);
    EXPECT_EQ(tried->database().sessionStart(), 0u);
    EXPECT_EQ(tried->cloudStore().stored(), 3u);
    // Street 21 again, turned a little (within what the odometry rotation check allows).
    const auto query = test::rotateTranslate(test::streetScene(21), 0.05, 0.5);
    const Detection a = tried->process(viewOf(query), taggedAt(10.0, 0.0));
    const Detection b = twin->process(viewOf(query), taggedAt(10.0, 0.0));
    EXPECT_TRUE(a.verified) << "the running keyframes are still found";
    expectSameDetection(a, b);
  }

  void expectRefused(const std::vector<std::uint8_t>& bytes, const std::vector<std::string>& words) {
    writeBytes(dir_.file("damaged.scl"), bytes);
    expectRefused(dir_.file("damaged.scl"), words);
  }

  TempDir dir_;
  std::vector<std::uint8_t> good_, plain_;
};

TEST_F(DamagedFile, TheUndamagedFileLoads) {
  auto detector = running();
  std::string error;
  ASSERT_TRUE(loadDatabase(dir_.file("good.scl"), detector.get(), &error)) << error;
  EXPECT_EQ(detector->database().size(), 7u);
  EXPECT_EQ(detector->cloudStore().stored(), 7u);
}

TEST_F(DamagedFile, WrongMagic) {
  std::vector<std::uint8_t> bytes = good_;
  bytes[1] = 'X';
  expectRefused(bytes, {"damaged.scl", "not a Scan Context database"});
}

TEST_F(DamagedFile, FutureVersion) {
  std::vector<std::uint8_t> bytes = good_;
  put(&bytes, kVersionAt, std::uint32_t(3));
  expectRefused(bytes, {"format version 3", "reads versions 1 and 2"});
}

/// `v2` (a file of four keyframe records with poses, without registration data) as format version 1
/// wrote it: each unit column as f32, `column_value` of its int8 entries (the float unit column).
std::vector<std::uint8_t> asVersion1(const std::vector<std::uint8_t>& v2,
                                     const std::function<std::vector<float>(const std::int8_t*)>& column_value) {
  std::vector<std::uint8_t> v1(v2.begin(), v2.begin() + kHeaderBytes);
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t record = kHeaderBytes + k * kRecordBytes, columns = record + 29 + 96 + 4;
    v1.insert(v1.end(), v2.begin() + record, v2.begin() + columns);
    for (std::size_t c = 0; c < kColumnBytes; c += 20) {
      for (float f : column_value(reinterpret_cast<const std::int8_t*>(v2.data() + columns + c))) {
        v1.resize(v1.size() + 4);
        put(&v1, v1.size() - 4, f);
      }
    }
    v1.insert(v1.end(), v2.begin() + columns + kColumnBytes, v2.begin() + record + kRecordBytes);
  }
  EXPECT_EQ(v2.size(), kHeaderBytes + 4 * kRecordBytes);
  put(&v1, kVersionAt, std::uint32_t(1));
  rewriteChecksums(&v1);
  return v1;
}

/// A column's int8 entries as the unit-length float column they stand for.
std::vector<float> unitFloats(const std::int8_t* q) {
  Eigen::VectorXf v(20);
  for (int r = 0; r < 20; ++r) v[r] = q[r];
  if (v.norm() > 0.0f) v.normalize();
  return std::vector<float>(v.data(), v.data() + 20);
}

TEST_F(DamagedFile, AVersion1FileLoadsItsFloatColumnsQuantised) {
  writeBytes(dir_.file("v1.scl"), asVersion1(plain_, unitFloats));
  auto v1 = running(), v2 = running();
  std::string error;
  ASSERT_TRUE(loadDatabase(dir_.file("v1.scl"), v1.get(), &error)) << error;
  ASSERT_TRUE(loadDatabase(dir_.file("plain.scl"), v2.get(), &error)) << error;
  ASSERT_EQ(v1->database().size(), 7u);
  for (std::size_t i = 3; i < 7; ++i) {
    const Descriptor& a = v1->database().keyframe(i).descriptor;
    const Descriptor& b = v2->database().keyframe(i).descriptor;
    EXPECT_EQ(a.ring_key, b.ring_key);
    EXPECT_EQ(a.column_occupied, b.column_occupied);
    // Quantised again from floats: each entry within a step of the version-2 file's.
    for (std::size_t e = 0; e < a.unit_columns.size(); ++e)
      ASSERT_LE(std::abs(a.unit_columns[e] - b.unit_columns[e]), 1);
    EXPECT_EQ(descriptorImplausibility(a, verifiedConfig().ring_key), "");
  }
  // The loaded keyframes answer a query as the version-2 file's do.
  const auto query = test::rotateTranslate(test::streetScene(21), 0.05, 0.5);
  const Detection a = v1->process(viewOf(query), taggedAt(10.0, 0.0));
  const Detection b = v2->process(viewOf(query), taggedAt(10.0, 0.0));
  ASSERT_EQ(a.query.matched, b.query.matched);
  if (a.query.matched) {
    EXPECT_EQ(a.query.best()->index, b.query.best()->index);
    EXPECT_NEAR(a.query.best()->alignment.distance, b.query.best()->alignment.distance, 0.005);
  }
  // A version-1 column entry beyond [-1, 1] is refused before it is rounded.
  std::vector<std::uint8_t> beyond = asVersion1(plain_, [](const std::int8_t* q) {
    std::vector<float> v = unitFloats(q);
    v[0] = 300.0f;
    return v;
  });
  expectRefused(beyond, {"keyframe 0", "unit column entry 0 is 300"});
}

TEST_F(DamagedFile, OtherDescriptorSettingsAreNamedWithBothValues) {
  Config other = verifiedConfig();
  other.num_sectors = 30;
  LoopDetector source(other);
  verifiedDrive(&source);
  std::string error;
  ASSERT_TRUE(saveDatabase(source, dir_.file("sectors.scl"), SaveOptions(), &error)) << error;
  expectRefused(dir_.file("sectors.scl"), {"num_sectors 30", "has 60"});

  Config occupancy = verifiedConfig();
  occupancy.ring_key = RingKeyType::kOccupancy;
  occupancy.lidar_height = 1.5;
  LoopDetector second(occupancy);
  verifiedDrive(&second);
  ASSERT_TRUE(saveDatabase(second, dir_.file("height.scl"), SaveOptions(), &error)) << error;
  expectRefused(dir_.file("height.scl"), {"lidar_height 1.5", "has 2"});
}

TEST_F(DamagedFile, OtherVoxelSettingsMatterOnlyWithClouds) {
  Config coarse = verifiedConfig();
  coarse.verification.voxel_leaf = 2.0;
  LoopDetector source(coarse);
  verifiedDrive(&source);
  std::string error;
  SaveOptions with_clouds;
  with_clouds.include_clouds = true;
  ASSERT_TRUE(saveDatabase(source, dir_.file("coarse.scl"), with_clouds, &error)) << error;
  expectRefused(dir_.file("coarse.scl"), {"verify_voxel_leaf 2", "has 1"});
  ASSERT_TRUE(saveDatabase(source, dir_.file("coarse_plain.scl"), SaveOptions(), &error)) << error;
  auto detector = running();
  EXPECT_TRUE(loadDatabase(dir_.file("coarse_plain.scl"), detector.get(), &error)) << error;
}

TEST_F(DamagedFile, TruncatedAnywhere) {
  for (std::size_t size : {std::size_t(3), std::size_t(7), std::size_t(40), kHeaderBytes - 1, kHeaderBytes,
                           kHeaderBytes + 10, good_.size() / 2, good_.size() - 1}) {
    SCOPED_TRACE(size);
    expectRefused(std::vector<std::uint8_t>(good_.begin(), good_.begin() + static_cast<long>(size)), {"truncated"});
  }
}

TEST_F(DamagedFile, AFlippedByteFailsAChecksum) {
  for (std::size_t at : {kHeaderBytes + 3, good_.size() / 2, good_.size() - 1}) {
    SCOPED_TRACE(at);
    std::vector<std::uint8_t> bytes = good_;
    bytes[at] ^= 0x10;
    expectRefused(bytes, {"payload checksum mismatch"});
  }
  std::vector<std::uint8_t> bytes = good_;
  bytes[kSectorsAt] ^= 0x01;
  expectRefused(bytes, {"header checksum mismatch"});
}

TEST_F(DamagedFile, EmptyMissingOrADirectory) {
  expectRefused(std::vector<std::uint8_t>(), {"empty"});
  expectRefused(dir_.file("missing.scl"), {"missing.scl", "No such file"});
  fs::create_directory(dir_.file("folder.scl"));
  expectRefused(dir_.file("folder.scl"), {"folder.scl", "is a directory"});
}

TEST_F(DamagedFile, CountsThatDisagreeWithThePayload) {
  std::vector<std::uint8_t> more = plain_;
  put(&more, kKeyframesAt, std::uint64_t(5));
  rewriteChecksums(&more);
  expectRefused(more, {"5 keyframes", "more than"});
  std::vector<std::uint8_t> fewer = plain_;
  put(&fewer, kKeyframesAt, std::uint64_t(3));
  rewriteChecksums(&fewer);
  expectRefused(fewer, {"follow the last record"});
  std::vector<std::uint8_t> sessions = plain_;
  put(&sessions, kSessionsAt, std::uint32_t(2));
  rewriteChecksums(&sessions);
  expectRefused(sessions, {"2 sessions"});
  std::vector<std::uint8_t> longer = plain_;
  longer.push_back(0);
  expectRefused(longer, {"follows the payload"});
  std::vector<std::uint8_t> huge = plain_;
  put(&huge, kKeyframesAt, std::numeric_limits<std::uint64_t>::max());
  rewriteChecksums(&huge);
  expectRefused(huge, {"more than"});
}

TEST_F(DamagedFile, APoseFlagOtherThanNoneOdometryOrCorrected) {
  // The first keyframe's pose flag follows its stamp, session, tag and path length.
  std::vector<std::uint8_t> bytes = plain_;
  ASSERT_EQ(bytes[kHeaderBytes + 8 + 4 + 8 + 8], 1);
  bytes[kHeaderBytes + 8 + 4 + 8 + 8] = 3;
  rewriteChecksums(&bytes);
  expectRefused(bytes, {"keyframe 0", "pose flag 3"});
}

TEST_F(DamagedFile, ValuesThatAreNotFinite) {
  // The first keyframe's record begins with its stamp; with a pose (12 doubles), its descriptor's first
  // ring key follows 8 + 4 + 8 + 8 + 1 + 96 bytes, occupied_columns, the unit columns and the flags in.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::uint8_t> stamp = plain_;
  put(&stamp, kHeaderBytes, nan);
  rewriteChecksums(&stamp);
  expectRefused(stamp, {"keyframe 0", "stamp is not finite"});
  std::vector<std::uint8_t> column = plain_;
  put(&column, kHeaderBytes + 8 + 4 + 8 + 8 + 1 + 96 + 4 + kColumnBytes + 60, std::numeric_limits<float>::infinity());
  rewriteChecksums(&column);
  expectRefused(column, {"keyframe 0", "not finite"});
  std::vector<std::uint8_t> pose = plain_;
  put(&pose, kHeaderBytes + 8 + 4 + 8 + 8 + 1 + 8, nan);
  rewriteChecksums(&pose);
  expectRefused(pose, {"keyframe 0", "pose is not finite"});
}

TEST_F(DamagedFile, BadRegistrationData) {
  // Four keyframe records, then the first keyframe's registration data: its gravity alignment (9 f32),
  // the flag, the voxel count, the compressed size.
  const std::size_t clouds = kCloudsAt, flag = kCloudFlagAt;
  std::vector<std::uint8_t> gravity_alignment = good_;
  put(&gravity_alignment, clouds, std::numeric_limits<float>::quiet_NaN());
  rewriteChecksums(&gravity_alignment);
  expectRefused(gravity_alignment, {"keyframe 0", "gravity alignment rotation", "not finite"});
  std::vector<std::uint8_t> flagged = good_;
  flagged[flag] = 2;
  rewriteChecksums(&flagged);
  expectRefused(flagged, {"keyframe 0", "registration data flag 2"});
  std::vector<std::uint8_t> count = good_;
  put(&count, flag + 1, std::uint32_t(100000000));
  rewriteChecksums(&count);
  expectRefused(count, {"keyframe 0", "100000000 voxels cannot come from"});
  std::vector<std::uint8_t> fewer = good_;
  std::uint32_t voxels = 0;
  for (int i = 3; i >= 0; --i) voxels = voxels << 8 | good_[flag + 1 + i];
  put(&fewer, flag + 1, voxels - 1);
  rewriteChecksums(&fewer);
  expectRefused(fewer, {"keyframe 0", "do not decompress to " + std::to_string(voxels - 1) + " voxels"});
}

TEST_F(DamagedFile, ANamedPipeIsRefusedWithoutBlocking) {
  const std::string pipe = dir_.file("pipe.scl");
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  LoopDetector detector(verifiedConfig());
  // Loaded on another thread, so that a load blocking on the pipe fails the test instead of hanging it.
  auto loaded = std::async(std::launch::async, [&] {
    std::string error;
    const bool ok = loadDatabase(pipe, &detector, &error);
    return std::make_pair(ok, error);
  });
  if (loaded.wait_for(std::chrono::seconds(1)) != std::future_status::ready) {
    ADD_FAILURE() << "loading a FIFO blocked";
    ::close(::open(pipe.c_str(), O_WRONLY | O_NONBLOCK));  // a writer comes and goes: the open returns
  }
  const auto [ok, error] = loaded.get();
  EXPECT_FALSE(ok);
  EXPECT_NE(error.find("pipe.scl is a named pipe (FIFO)"), std::string::npos) << error;
  EXPECT_EQ(detector.database().size(), 0u);
}

TEST_F(DamagedFile, DescriptorValuesNoDescriptorCanHold) {
  // Keyframe 1's first unit column all 127s (4.5 times unit length): its distance to any query would be
  // negative.
  std::vector<std::uint8_t> column = plain_;
  for (int r = 0; r < 20; ++r) put(&column, kDescriptorAt + kRecordBytes + 4 + r, std::int8_t(127));
  rewriteChecksums(&column);
  expectRefused(column, {"keyframe 1", "column 0"});
  // A column flagged empty (its flag 0 and occupied_columns one less) that holds values.
  std::vector<std::uint8_t> empty = plain_;
  const std::size_t flags = kDescriptorAt + 4 + kColumnBytes;
  ASSERT_EQ(plain_[flags + 5], 1) << "keyframe 0's column 5 is occupied";
  empty[flags + 5] = 0;
  std::uint32_t occupied = 0;
  for (int i = 3; i >= 0; --i) occupied = occupied << 8 | plain_[kDescriptorAt + i];
  put(&empty, kDescriptorAt, occupied - 1);
  rewriteChecksums(&empty);
  expectRefused(empty, {"keyframe 0", "column 5 is flagged empty but holds values"});
  // A ring key no height reaches (mean-height ring keys: at most kMaxPointHeight).
  std::vector<std::uint8_t> ring = plain_;
  put(&ring, flags + 60 + 4 * 3, 1e9f);
  rewriteChecksums(&ring);
  expectRefused(ring, {"keyframe 0", "ring key 3 is 1e+09"});
  std::vector<std::uint8_t> sector = plain_;
  put(&sector, flags + 60 + 4 * 20 + 4 * 7, -1e6f);
  rewriteChecksums(&sector);
  expectRefused(sector, {"keyframe 0", "sector key 7 is -1e+06"});
}

TEST_F(DamagedFile, VoxelsOutsideTheCropOrBeyondTheGrid) {
  // A cloud of plausible voxels loads (the records below differ from it in one value only).
  std::vector<Eigen::Vector3f> means = {{1, 2, 0.5f}, {-30, 20, 3}, {0, -39.5f, -7.5f}, {5, 5, 23}};
  auto detector = running();
  std::string error;
  writeBytes(dir_.file("synthetic.scl"), withFirstCloud(good_, 4, lz4Literals(voxelBytes(means))));
  ASSERT_TRUE(loadDatabase(dir_.file("synthetic.scl"), detector.get(), &error)) << error;
  EXPECT_EQ(detector->cloudStore().get(3)->size(), 4u);

  means[2].x() = 1e30f;  // registration's float-to-int cell index would overflow
  expectRefused(withFirstCloud(good_, 4, lz4Literals(voxelBytes(means))),
                {"keyframe 0", "voxel 2", "outside the crop", "verify_max_range 40"});
  means[2] = Eigen::Vector3f(0, 0, 100);
  expectRefused(withFirstCloud(good_, 4, lz4Literals(voxelBytes(means))),
                {"keyframe 0", "voxel 2", "outside the crop"});
  means[2] = Eigen::Vector3f(0, -39.5f, -7.5f);
  std::vector<std::uint8_t> raw = voxelBytes(means);
  raw[12 * 4 + 4 * 1] = 127;  // voxel 1's normal (127, 0, 127): longer than a unit vector
  expectRefused(withFirstCloud(good_, 4, lz4Literals(raw)), {"keyframe 0", "voxel 1", "normal is longer"});

  std::vector<std::uint8_t> scaled = good_;
  put(&scaled, kCloudsAt, 2.0f);  // the gravity alignment's first entry: no longer a rotation
  rewriteChecksums(&scaled);
  expectRefused(scaled, {"keyframe 0", "gravity alignment rotation is not a rotation"});

  // At 1 m voxels and 40 m range the grid has 81 x 81 x 33 cells; more voxels than the points read
  // (kVoxelCloudMaxPoints) no cloud holds.
  EXPECT_EQ(maxVoxels(VoxelOptions()), kVoxelCloudMaxPoints);
  VoxelOptions coarse;
  coarse.resolution = 4.0f;
  EXPECT_EQ(maxVoxels(coarse), std::size_t(21 * 21 * 9));
  const std::vector<std::uint8_t> zeros((kVoxelCloudMaxPoints + 1) * 16 / 255 + 1, 0);
  expectRefused(withFirstCloud(good_, kVoxelCloudMaxPoints + 1, zeros),
                {"keyframe 0", std::to_string(kVoxelCloudMaxPoints + 1) + " voxels, more than the 60000"});
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

/// Reads `path` in a child process whose address space may grow by `headroom` bytes at most: 0 when
/// the file was refused, 1 when it loaded, 2 when memory ran out, 3 when the child did not finish.
int readWithHeadroom(const std::string& path, std::size_t headroom) {
  const pid_t child = ::fork();
  if (child == 0) {
    long pages = 0;
    std::ifstream("/proc/self/statm") >> pages;
    const rlim_t limit = static_cast<rlim_t>(pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE)) + headroom;
    const rlimit address_space{limit, limit};
    ::setrlimit(RLIMIT_AS, &address_space);
    try {
      PriorSessions sessions;
      std::string error;
      ::_exit(readDatabaseFile(path, verifiedConfig(), &sessions, &error) ? 1 : 0);
    } catch (const std::bad_alloc&) {
      ::_exit(2);
    }
  }
  for (int waited = 0; waited < 600; ++waited) {
    int status = 0;
    if (::waitpid(child, &status, WNOHANG) == child) return WIFEXITED(status) ? WEXITSTATUS(status) : 2;
    ::usleep(50 * 1000);
  }
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  return 3;
}

TEST_F(DamagedFile, AHugeCountInASmallFileIsRefusedWithinBoundedMemory) {
  if (kSanitized) GTEST_SKIP() << "a sanitizer reserves far more address space than any limit here allows";
  // Under 1 MB: 800,000 compressed bytes could hold 12.75 million voxels (204 MB) by LZ4's 255-fold
  // bound alone, far more than any grid of the header's voxel settings holds.
  const std::uint32_t voxels = 800000u * 255u / 16u;
  const std::vector<std::uint8_t> huge = withFirstCloud(good_, voxels, std::vector<std::uint8_t>(800000, 0));
  ASSERT_LT(huge.size(), std::size_t(1) << 20);
  writeBytes(dir_.file("huge.scl"), huge);
  EXPECT_EQ(readWithHeadroom(dir_.file("huge.scl"), std::size_t(128) << 20), 0)
      << "refused (0), not loaded (1), out of memory (2) or hanging (3) within 128 MB more";
  expectRefused(huge, {"keyframe 0", std::to_string(voxels) + " voxels, more than the 60000"});
  std::vector<std::uint8_t> keyframes = good_;
  put(&keyframes, kKeyframesAt, std::uint64_t(1) << 40);
  put(&keyframes, kSessionsAt, std::uint32_t(1));
  rewriteChecksums(&keyframes);
  writeBytes(dir_.file("keyframes.scl"), keyframes);
  EXPECT_EQ(readWithHeadroom(dir_.file("keyframes.scl"), std::size_t(128) << 20), 0);
  // The good file itself loads within the same limit: the limit leaves room for a real load.
  EXPECT_EQ(readWithHeadroom(dir_.file("good.scl"), std::size_t(128) << 20), 1);
}

TEST_F(DamagedFile, MoreSessionsThanKeyframes) {
  std::vector<std::uint8_t> sessions = plain_;
  put(&sessions, kSessionsAt, std::uint32_t(4000000000u));
  rewriteChecksums(&sessions);
  expectRefused(sessions, {"4000000000 sessions for 4 keyframes"});
}

TEST(DatabaseFileSave, AMissingDirectoryFailsAndLeavesNothingBehind) {
  TempDir dir;
  LoopDetector detector(descriptorConfig());
  drive(&detector);
  std::string error;
  EXPECT_FALSE(saveDatabase(detector, dir.file("missing/db.scl"), SaveOptions(), &error));
  EXPECT_NE(error.find("missing"), std::string::npos) << error;
  EXPECT_NE(error.find("No such file"), std::string::npos) << error;
  EXPECT_TRUE(dir.entries().empty());
  fs::create_directory(dir.file("folder"));
  EXPECT_FALSE(saveDatabase(detector, dir.file("folder"), SaveOptions(), &error));
  EXPECT_NE(error.find("is a directory"), std::string::npos) << error;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"folder"});
  EXPECT_TRUE(fs::is_empty(dir.file("folder")));
}

TEST(DatabaseFileSave, SavingOverAFileThatIsNoDatabaseIsRefusedAndOverADatabaseReplacesItWhole) {
  TempDir dir;
  const std::vector<std::uint8_t> other(4 << 20, 'x');
  writeBytes(dir.file("db.scl"), other);
  LoopDetector detector(descriptorConfig());
  drive(&detector);
  std::string error;
  EXPECT_FALSE(saveDatabase(detector, dir.file("db.scl"), SaveOptions(), &error));
  EXPECT_NE(error.find("not a Scan Context database"), std::string::npos) << error;
  EXPECT_EQ(readBytes(dir.file("db.scl")), other) << "the other file is left as it was";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"db.scl"}) << "no temporary file is left";
  // An empty file holds nothing to lose: it is replaced.
  writeBytes(dir.file("db.scl"), {});
  ASSERT_TRUE(saveDatabase(detector, dir.file("db.scl"), SaveOptions(), &error)) << error;
  LoopDetector loaded(descriptorConfig());
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &loaded, &error)) << error;
  EXPECT_EQ(loaded.database().size(), detector.database().size());
  // Saved over a database, the file is replaced whole: the same byte for byte.
  const std::vector<std::uint8_t> first = readBytes(dir.file("db.scl"));
  ASSERT_TRUE(saveDatabase(detector, dir.file("db.scl"), SaveOptions(), &error)) << error;
  EXPECT_EQ(readBytes(dir.file("db.scl")), first);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"db.scl"});
}

TEST(DatabaseFileSave, TheReplacedFileIsKeptAsABackupAndKeepsItsMode) {
  TempDir dir;
  LoopDetector empty(descriptorConfig());
  LoopDetector detector(descriptorConfig());
  drive(&detector);
  SaveOptions save;
  save.keep_backup = true;
  std::string error;
  ASSERT_TRUE(saveDatabase(empty, dir.file("db.scl"), save, &error)) << error;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"db.scl"}) << "no backup of a file that was not there";
  EXPECT_EQ(fs::status(dir.file("db.scl")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read);
  const std::vector<std::uint8_t> first = readBytes(dir.file("db.scl"));
  fs::permissions(dir.file("db.scl"), fs::perms::owner_read | fs::perms::owner_write);
  ASSERT_TRUE(saveDatabase(detector, dir.file("db.scl"), save, &error)) << error;
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"db.scl", "db.scl.bak"}));
  EXPECT_EQ(readBytes(dir.file("db.scl.bak")), first);
  EXPECT_NE(readBytes(dir.file("db.scl")), first);
  EXPECT_EQ(fs::status(dir.file("db.scl")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write)
      << "the replaced file's mode is kept";
  // A third save: the backup is now the second save's file.
  const std::vector<std::uint8_t> second = readBytes(dir.file("db.scl"));
  ASSERT_TRUE(saveDatabase(empty, dir.file("db.scl"), save, &error)) << error;
  EXPECT_EQ(readBytes(dir.file("db.scl.bak")), second);
  EXPECT_EQ(readBytes(dir.file("db.scl")), first);
}

}  // namespace
}  // namespace scan_context_loop
