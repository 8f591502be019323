// The database file: a saved and loaded database answers like the original; every damaged or
// mismatched file is refused with a clear error and leaves the running database as it was; saving
// replaces a file atomically.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <memory_resource>

#include "scan_context_loop/core/crc32.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

namespace fs = std::filesystem;

// Byte offsets of header fields (doc/database_file.md).
constexpr std::size_t kVersionAt = 5, kSectorsAt = 17, kKeyframesAt = 63, kSessionsAt = 71, kPayloadCrcAt = 83,
                      kHeaderCrcAt = 87, kHeaderBytes = 91;

/// A fresh directory, removed with everything in it at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string name = (fs::temp_directory_path() / "scl_database_file_XXXXXX").string();
    path_ = ::mkdtemp(&name[0]);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

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
  put(bytes, kPayloadCrcAt, crc32(bytes->data() + kHeaderBytes, bytes->size() - kHeaderBytes));
  put(bytes, kHeaderCrcAt, crc32(bytes->data(), kHeaderCrcAt));
}

KeyframeInfo at(double stamp, double x, std::int64_t tag = -1) {
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
    ASSERT_TRUE(detector->process(viewOf(test::streetScene(300 + i)), at(100.0 + i, 10.0 * i, i)).accepted);
  }
  detector->startSession();
  for (int i = 0; i < 6; ++i) {
    KeyframeInfo info = at(1.0 + i, 5.0 * i, 100 + i);
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
    ASSERT_TRUE(detector->process(viewOf(test::streetScene(21 + i)), at(1.0 + i, 30.0 * i)).accepted);
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
          test::rotateTranslate(test::streetScene(310), -2.0),
          test::rotateTranslate(test::streetScene(402), 3.1, 1.0),
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
  // The loaded descriptors stayed in the arena they were decoded into (one per file, not the heap).
  const std::pmr::memory_resource* memory = b.keyframe(0).descriptor.unit_columns.get_allocator().resource();
  EXPECT_NE(memory, std::pmr::get_default_resource());
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
    const Detection x = original.process(viewOf(cloud), at(stamp, 0.0));
    const Detection y = loaded.process(viewOf(cloud), at(stamp, 0.0));
    SCOPED_TRACE(stamp);
    expectSameDetection(x, y);
    EXPECT_EQ(x.query.eligible, saved) << "all saved keyframes are candidates, the new ones are recent";
    matched += x.query.matched;
  }
  EXPECT_EQ(matched, 3) << "the three revisits match, the new street does not";
}

TEST(DatabaseFile, LoadedSessionsFollowTheRunningOnesAndANewSessionBegins) {
  TempDir dir;
  LoopDetector saved(descriptorConfig());
  drive(&saved);
  std::string error;
  ASSERT_TRUE(saveDatabase(saved, dir.file("db.scl"), SaveOptions(), &error)) << error;

  LoopDetector running(descriptorConfig());
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(running.process(viewOf(test::streetScene(500 + i)), at(50.0 + i, i)).accepted);
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
  const Detection next = running.process(viewOf(test::streetScene(303)), at(0.0, 0.0));
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
  const KeyframeInfo back = at(0.5, 0.0);
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

TEST(DatabaseFile, APipelineForgetsItsOdometryOnLoad) {
  TempDir dir;
  LoopDetector saved(descriptorConfig());
  drive(&saved);
  std::string error;
  ASSERT_TRUE(saveDatabase(saved, dir.file("db.scl"), SaveOptions(), &error)) << error;
  Config c = descriptorConfig();
  c.keyframe_min_distance = 5.0;
  KeyframePipeline pipeline(c);
  ASSERT_TRUE(pipeline.process(viewOf(test::streetScene(1)), at(1.0, 0.0)).accepted);
  EXPECT_FALSE(pipeline.process(viewOf(test::streetScene(1)), at(2.0, 0.0)).selected) << "has not moved";
  ASSERT_TRUE(loadDatabase(dir.file("db.scl"), &pipeline, &error)) << error;
  const Detection d = pipeline.process(viewOf(test::streetScene(1)), at(3.0, 0.0));
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
    for (int i = 0; i < 3; ++i) detector->process(viewOf(test::streetScene(21 + i)), at(1.0 + i, 30.0 * i));
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
    const Detection a = tried->process(viewOf(query), at(10.0, 0.0));
    const Detection b = twin->process(viewOf(query), at(10.0, 0.0));
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
  put(&bytes, kVersionAt, std::uint32_t(2));
  expectRefused(bytes, {"format version 2", "reads version 1"});
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

TEST_F(DamagedFile, ValuesThatAreNotFinite) {
  // The first keyframe's record begins with its stamp; with a pose (12 doubles), its descriptor's first
  // unit-column value follows 8 + 4 + 8 + 8 + 1 + 96 + 4 bytes in.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::uint8_t> stamp = plain_;
  put(&stamp, kHeaderBytes, nan);
  rewriteChecksums(&stamp);
  expectRefused(stamp, {"keyframe 0", "stamp is not finite"});
  std::vector<std::uint8_t> column = plain_;
  put(&column, kHeaderBytes + 8 + 4 + 8 + 8 + 1 + 96 + 4, std::numeric_limits<float>::infinity());
  rewriteChecksums(&column);
  expectRefused(column, {"keyframe 0", "not finite"});
  std::vector<std::uint8_t> pose = plain_;
  put(&pose, kHeaderBytes + 8 + 4 + 8 + 8 + 1 + 8, nan);
  rewriteChecksums(&pose);
  expectRefused(pose, {"keyframe 0", "pose is not finite"});
}

TEST_F(DamagedFile, BadRegistrationData) {
  // Four keyframe records with poses (29 + 96 bytes and the 20 x 60 descriptor's 5,184), then the first
  // keyframe's registration data: its gravity alignment (9 f32), the flag, the voxel count, the compressed size.
  const std::size_t clouds = kHeaderBytes + 4 * (29 + 96 + 5184), flag = clouds + 36;
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
            fs::perms::owner_read | fs::perms::owner_write) << "the replaced file's mode is kept";
  // A third save: the backup is now the second save's file.
  const std::vector<std::uint8_t> second = readBytes(dir.file("db.scl"));
  ASSERT_TRUE(saveDatabase(empty, dir.file("db.scl"), save, &error)) << error;
  EXPECT_EQ(readBytes(dir.file("db.scl.bak")), second);
  EXPECT_EQ(readBytes(dir.file("db.scl")), first);
}

}  // namespace
}  // namespace scan_context_loop
