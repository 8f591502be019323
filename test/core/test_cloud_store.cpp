// The cloud store: the registration data of every keyframe within a byte budget, halving its density
// when the budget is reached, and what it holds in memory.
#include <algorithm>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "scan_context_loop/core/cloud_store.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/verification.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

VoxelCloud cloudOf(std::size_t voxels) {
  VoxelCloud c;
  c.means.assign(voxels, Eigen::Vector3f::Zero());
  c.normals.assign(voxels, {0, 0, 127, VoxelCloud::kPlanar});
  return c;
}

TEST(CloudStore, HalvesItsDensityToStayWithinItsBudget) {
  const std::size_t per_cloud = cloudOf(100).bytes();
  CloudStore store(10 * per_cloud);
  for (std::size_t i = 0; i < 10; ++i) store.add(i, cloudOf(100));
  EXPECT_EQ(store.stored(), 10u);
  EXPECT_EQ(store.dropped(), 0u);
  store.add(10, cloudOf(100));  // one too many: only even keyframes are kept from now on
  EXPECT_LE(store.bytes(), 10 * per_cloud);
  EXPECT_EQ(store.dropped(), 5u);
  EXPECT_NE(store.get(0), nullptr);
  EXPECT_EQ(store.get(1), nullptr);
  EXPECT_NE(store.get(2), nullptr);
  EXPECT_EQ(store.get(3), nullptr);
  EXPECT_NE(store.get(10), nullptr);
  store.add(11, cloudOf(100));
  EXPECT_EQ(store.get(11), nullptr);
  for (std::size_t i = 11; i < 200; ++i) store.add(i, cloudOf(100));
  EXPECT_LE(store.bytes(), 10 * per_cloud);
  // Still spread over the whole drive, not only its end.
  std::size_t early = 0;
  for (std::size_t i = 0; i < 100; ++i) early += store.get(i) != nullptr;
  EXPECT_GE(early, 2u);
}

TEST(CloudStore, AHalvingIsReportedWithWhatItLost) {
  const std::size_t per_cloud = cloudOf(100).bytes();
  CloudStore store(10 * per_cloud);
  for (std::size_t i = 0; i < 10; ++i) store.add(i, cloudOf(100));
  EXPECT_EQ(store.stride(), 1u);
  EXPECT_EQ(cloudStoreHalvingWarning(1, store, 10), "");
  store.add(10, cloudOf(100));
  ASSERT_EQ(store.stride(), 2u);
  const std::string warning = cloudStoreHalvingWarning(1, store, 11);
  EXPECT_NE(warning.find("verify_max_bytes"), std::string::npos) << warning;
  EXPECT_NE(warning.find("one keyframe in 2"), std::string::npos) << warning;
  // Keyframes 0, 2, ..., 10 keep their data: 5 of the 11 have none.
  EXPECT_NE(warning.find("5 of 11 keyframes have none"), std::string::npos) << warning;
  EXPECT_EQ(cloudStoreHalvingWarning(2, store, 11), "") << "reported twice";
}

TEST(CloudStore, HalvingFreesTheDroppedCloudsAFewAtATime) {
  // 1,000 clouds fill the budget; the next one halves the density: 500 leave the store at once, but
  // their memory is freed at most kReleasedPerAdd per later add, not all by the keyframe that halved it.
  const std::size_t per_cloud = cloudOf(10).bytes();
  CloudStore store(1000 * per_cloud);
  for (std::size_t i = 0; i < 1000; ++i) store.add(i, cloudOf(10));
  EXPECT_EQ(store.releasing(), 0u);
  store.add(1000, cloudOf(10));
  EXPECT_EQ(store.dropped(), 500u);
  EXPECT_EQ(store.releasing(), 500u);
  EXPECT_EQ(store.stored(), 501u);
  EXPECT_LE(store.bytes(), 1000 * per_cloud);
  EXPECT_EQ(store.get(1), nullptr);  // dropped: never served again, even before it is freed
  std::size_t adds = 0;
  for (std::size_t i = 1001; store.releasing() > 0; ++i, ++adds) {
    const std::size_t before = store.releasing();
    store.add(i, cloudOf(10));
    EXPECT_EQ(before - store.releasing(), std::min(before, CloudStore::kReleasedPerAdd));
  }
  EXPECT_EQ(adds, (500 + CloudStore::kReleasedPerAdd - 1) / CloudStore::kReleasedPerAdd);
}

/// The process's resident memory [bytes], from /proc/self/statm.
long residentBytes() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * 4096;
}

TEST(CloudStore, LevelsAreTheHalvingsThatKeepAKeyframe) {
  EXPECT_EQ(CloudStore::levelOf(1), 0);
  EXPECT_EQ(CloudStore::levelOf(7), 0);
  EXPECT_EQ(CloudStore::levelOf(2), 1);
  EXPECT_EQ(CloudStore::levelOf(12), 2);
  EXPECT_EQ(CloudStore::levelOf(1024), 10);
  EXPECT_GT(CloudStore::levelOf(0), 60);  // kept at every density
}

TEST(CloudStore, AHalvingGivesTheDroppedLevelsMemoryBackToTheSystem) {
  // 4,096 clouds of 16 KB fill a 64 MB budget; the next one halves the density and drops the odd
  // keyframes, 32 MB. Freed in place on the heap, they left a hole between every two kept clouds and
  // the process stayed as large; in an arena of their own the memory goes back once they are freed.
  const std::size_t per_cloud = cloudOf(1000).bytes();
  CloudStore store(4096 * per_cloud);
  for (std::size_t i = 0; i < 4096; ++i) store.add(i, cloudOf(1000));
  // What the arenas hold: the voxels, plus at most one part-filled 2 MB block for each of the 13 levels.
  EXPECT_GE(store.memoryBytes(), store.bytes());
  EXPECT_LE(store.memoryBytes(), store.bytes() + 13 * CloudStore::kLevelBlockBytes);
  const long full = residentBytes();
  std::size_t next = 4096;
  store.add(next++, cloudOf(1000));
  ASSERT_EQ(store.dropped(), 2048u);
  while (store.releasing() > 0) store.add(next++, cloudOf(1000));
  EXPECT_LE(store.memoryBytes(), store.bytes() + 13 * CloudStore::kLevelBlockBytes);
  const long after = residentBytes();
  EXPECT_GE(full - after, 24L << 20) << "resident " << full << " bytes before the halving, " << after << " after";
  // The kept ones are intact.
  for (std::size_t i = 0; i < next; i += 2) {
    ASSERT_NE(store.get(i), nullptr) << i;
    EXPECT_EQ(store.get(i)->size(), 1000u);
    EXPECT_EQ(store.get(i)->normals.back()[2], 127);
  }
}

TEST(CloudStore, HoldsNoMoreMemoryThanItsBudgetCounts) {
  // A keyframe's registration data: only voxels with enough points are kept, and the arrays hold
  // exactly those (a downsampled scan leaves most 1 m voxels with one or two points).
  pcl::PointCloud<pcl::PointXYZI> sparse;
  for (int i = 0; i < 4000; ++i) {
    pcl::PointXYZI p;
    p.x = static_cast<float>(-30.0 + 1.7 * (i % 37));
    p.y = static_cast<float>(-30.0 + 1.3 * ((i / 37) % 41));
    p.z = static_cast<float>(0.2 * (i % 5));
    sparse.push_back(p);
  }
  for (const auto& scan : {test::kittiScan("00", 198), sparse}) {
    const VoxelCloud cloud = prepareCloud(viewOf(scan), VerificationConfig());
    ASSERT_FALSE(cloud.empty());
    EXPECT_EQ(cloud.means.capacity(), cloud.size());
    EXPECT_EQ(cloud.normals.capacity(), cloud.size());
  }
  // Whatever it is handed, the store keeps arrays no larger than the voxels it counts.
  VoxelCloud slack = cloudOf(100);
  slack.means.reserve(1000);
  slack.normals.reserve(1000);
  CloudStore store(1 << 20);
  store.add(0, std::move(slack));
  ASSERT_NE(store.get(0), nullptr);
  EXPECT_EQ(store.get(0)->means.capacity(), 100u);
  EXPECT_EQ(store.get(0)->normals.capacity(), 100u);
  EXPECT_EQ(store.bytes(), cloudOf(100).bytes());
}

}  // namespace
}  // namespace scan_context_loop
