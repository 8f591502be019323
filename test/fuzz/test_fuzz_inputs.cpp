// The fuzz targets' kept inputs (scripts/dev/fuzz): the inputs that once crashed a target and the reduced
// corpus, replayed through the same target functions; the in-memory database parser the targets reach.
// No ROS master needed.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "fuzz_input.h"
#include "scan_context_loop/core/database_file.h"

namespace scan_context_loop {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> readBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

/// The inputs of a packed corpus file (records of a 4-byte little-endian length and the bytes;
/// scripts/dev/fuzz_corpus.py). Fails the test if the file is missing or malformed.
std::vector<std::vector<std::uint8_t>> readPacked(const fs::path& path) {
  const std::vector<std::uint8_t> blob = readBytes(path);
  std::vector<std::vector<std::uint8_t>> inputs;
  std::size_t at = 0;
  while (at < blob.size()) {
    if (at + 4 > blob.size()) {
      ADD_FAILURE() << path << ": truncated record header at byte " << at;
      break;
    }
    const std::size_t size = blob[at] | blob[at + 1] << 8 | blob[at + 2] << 16 | std::size_t(blob[at + 3]) << 24;
    at += 4;
    if (at + size > blob.size()) {
      ADD_FAILURE() << path << ": record " << inputs.size() << " runs past the end";
      break;
    }
    inputs.emplace_back(blob.begin() + at, blob.begin() + at + size);
    at += size;
  }
  return inputs;
}

TEST(FuzzRegressions, EveryKeptInputRunsThroughItsTarget) {
  // Two kinds of kept input per target: test/fuzz_regressions/<target>/ (inputs that once crashed it,
  // one file each) and test/fuzz_corpus/<target>.corpus (the fuzzing runs' corpus reduced to a set
  // with the same coverage). Under `scripts/dev/test --sanitize` and scripts/dev/fuzz they run under ASan/UBSan.
  const std::pair<const char*, int (*)(const std::uint8_t*, std::size_t)> targets[] = {
      {"cloudInput", fuzz::cloudInput}, {"odometryInput", fuzz::odometryInput}, {"databaseFile", fuzz::databaseFile}};
  const fs::path root = fs::path(SCL_PACKAGE_DIR) / "test";
  for (const auto& [name, run] : targets) {
    SCOPED_TRACE(name);
    const auto corpus = readPacked(root / "fuzz_corpus" / (std::string(name) + ".corpus"));
    EXPECT_GE(corpus.size(), 50u) << "the kept corpus is missing or nearly empty";
    for (std::size_t i = 0; i < corpus.size(); ++i) {
      SCOPED_TRACE("corpus input " + std::to_string(i));
      EXPECT_EQ(run(corpus[i].data(), corpus[i].size()), 0);
    }
    if (!fs::is_directory(root / "fuzz_regressions" / name)) continue;
    for (const auto& entry : fs::directory_iterator(root / "fuzz_regressions" / name)) {
      SCOPED_TRACE(entry.path().string());
      const std::vector<std::uint8_t> bytes = readBytes(entry.path());
      EXPECT_EQ(run(bytes.data(), bytes.size()), 0);
    }
  }
}

/// A database file of three keyframes of the fixed cloud, with registration data, as bytes.
std::vector<std::uint8_t> savedDatabase(const Config& config) {
  LoopDetector detector(config);
  for (int i = 0; i < 3; ++i) {
    KeyframeInfo info;
    info.stamp = i;
    info.pose = Eigen::Isometry3d(Eigen::Translation3d(0.2 * i, 0.0, 0.0));
    detector.process(fuzz::fixedCloud(), info);
  }
  const std::string path = (fs::temp_directory_path() / "scl_test_fuzz_inputs.db").string();
  SaveOptions options;
  options.include_clouds = true;
  std::string error;
  EXPECT_TRUE(saveDatabase(detector, path, options, &error)) << error;
  std::vector<std::uint8_t> bytes = readBytes(path);
  fs::remove(path);
  return bytes;
}

TEST(DatabaseBytes, AFileInMemoryIsReadWholeAndItsDamageRefusedWithTheName) {
  const Config config = fuzz::smallConfig(fuzz::kDatabaseChoice);
  std::vector<std::uint8_t> bytes = savedDatabase(config);
  std::string error;
  PriorSessions from_memory;
  MemoryReader reader(bytes.data(), bytes.size());
  ASSERT_TRUE(readDatabase(&reader, "memory", config, &from_memory, &error)) << error;
  EXPECT_EQ(from_memory.keyframes.size(), 3u);
  ASSERT_EQ(from_memory.clouds.size(), 3u);
  EXPECT_TRUE(from_memory.clouds[2] != nullptr);

  bytes.back() ^= 1;  // the payload's last byte
  MemoryReader damaged(bytes.data(), bytes.size());
  PriorSessions ignored;
  EXPECT_FALSE(readDatabase(&damaged, "memory", config, &ignored, &error));
  EXPECT_EQ(error, "memory: payload checksum mismatch: the file is corrupt");
  MemoryReader truncated(bytes.data(), 40);
  EXPECT_FALSE(readDatabase(&truncated, "memory", config, &ignored, &error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
}

TEST(DatabaseBytes, LoadedVoxelMeansFarOutsideTheGridAreIgnoredByVerification) {
  // The loader asks only that a file's voxel means be finite: means far outside the registration grid
  // (out of int's range once divided by the voxel size) must neither break verification nor match.
  const Config config = fuzz::smallConfig(fuzz::kDatabaseChoice);
  const std::vector<std::uint8_t> bytes = savedDatabase(config);
  MemoryReader reader(bytes.data(), bytes.size());
  PriorSessions sessions;
  std::string error;
  ASSERT_TRUE(readDatabase(&reader, "memory", config, &sessions, &error)) << error;
  for (auto& cloud : sessions.clouds) {
    ASSERT_TRUE(cloud != nullptr);
    for (auto& mean : cloud->means) mean = Eigen::Vector3f(1e30f, -1e30f, 1e30f);
  }
  LoopDetector loaded(config);
  ASSERT_TRUE(loaded.appendSessions(std::move(sessions), &error)) << error;
  const Detection found = loaded.locate(fuzz::fixedCloud());
  EXPECT_FALSE(found.verifications.empty());  // the candidates were registered against the far voxels
  EXPECT_FALSE(found.verified);
}

TEST(FuzzInputs, TheFixedCloudReachesTheRegistration) {
  // The fuzz targets' clouds must get past the structure floor, or no fuzz input ever exercises the
  // registration and its acceptance tests.
  LoopDetector detector(fuzz::smallConfig(fuzz::kDatabaseChoice));
  bool registered = false;
  for (int i = 0; i < 4; ++i) {
    KeyframeInfo info;
    info.stamp = i;
    info.pose = Eigen::Isometry3d(Eigen::Translation3d(0.2 * i, 0.0, 0.0));
    const Detection d = detector.process(fuzz::fixedCloud(), info);
    for (const auto& v : d.verifications) {
      registered |= v.result.rejected_by != "unverifiable" && v.result.rejected_by != "structure";
    }
  }
  EXPECT_TRUE(registered) << "no candidate of the fixed cloud got past the structure test";
}

}  // namespace
}  // namespace scan_context_loop
