// The worker's reading of malloc's statistics: when it reads, and what. No ROS master.
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

#include "loop_closure/heap_statistics.h"

namespace scan_context_loop {
namespace {

TEST(HeapStatistics, ReadsEveryIntervalKeyframesOnlyWhenTheQueueIsEmpty) {
  if (!HeapStatistics::available()) GTEST_SKIP() << "no mallinfo2 on this platform";
  HeapStatistics heap(3);
  EXPECT_EQ(heap.allocatedBytes(), -1);
  EXPECT_FALSE(heap.afterKeyframe(true));
  EXPECT_FALSE(heap.afterKeyframe(true));
  EXPECT_TRUE(heap.afterKeyframe(true));
  EXPECT_EQ(heap.reads(), 1u);
  // Keyframes waiting: the read waits for an empty queue, then comes at once.
  for (int k = 0; k < 5; ++k) EXPECT_FALSE(heap.afterKeyframe(false));
  EXPECT_TRUE(heap.afterKeyframe(true));
  EXPECT_EQ(heap.reads(), 2u);
  EXPECT_GE(heap.lastMs(), 0.0);
}

TEST(HeapStatistics, IntervalZeroNeverReads) {
  HeapStatistics heap(0);
  for (int k = 0; k < 100; ++k) EXPECT_FALSE(heap.afterKeyframe(true));
  EXPECT_EQ(heap.reads(), 0u);
  EXPECT_EQ(heap.allocatedBytes(), -1);
}

TEST(HeapStatistics, AllocatedGrowsByWhatWasAllocated) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // The sanitizer's allocator replaces glibc's malloc, whose statistics would read 0: none are read.
  EXPECT_FALSE(HeapStatistics::available());
  HeapStatistics sanitized(1);
  EXPECT_FALSE(sanitized.afterKeyframe(true));
  EXPECT_EQ(sanitized.allocatedBytes(), -1);
  return;
#endif
  if (!HeapStatistics::available()) GTEST_SKIP() << "no mallinfo2 on this platform";
  HeapStatistics heap(1);
  ASSERT_TRUE(heap.afterKeyframe(true));
  const long long before = heap.allocatedBytes();
  EXPECT_GT(before, 0);
  EXPECT_GE(heap.freeBytes(), 0);
  // 1,000 blocks of 4 KB held: 4 MB more allocated (plus malloc's few bytes a block).
  constexpr int kBlocks = 1000;
  constexpr std::size_t kSize = 4096;
  char* blocks[kBlocks];
  for (char*& b : blocks) {
    b = static_cast<char*>(std::malloc(kSize));
    ASSERT_NE(b, nullptr);
    std::memset(b, 1, kSize);
  }
  ASSERT_TRUE(heap.afterKeyframe(true));
  const long long grown = heap.allocatedBytes() - before;
  for (char* b : blocks) std::free(b);
  EXPECT_GE(grown, static_cast<long long>(kBlocks * kSize));
  EXPECT_LT(grown, static_cast<long long>(kBlocks * (kSize + 64)));
}

}  // namespace
}  // namespace scan_context_loop
