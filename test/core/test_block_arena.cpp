// BlockArena hands out aligned, separate pieces and lives as long as the containers that use it.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory_resource>
#include <vector>

#include "scan_context_loop/core/block_arena.h"

namespace scan_context_loop {
namespace {

TEST(BlockArena, PiecesAreAlignedAndApartAndOutliveTheHandle) {
  std::vector<std::pmr::vector<float>> arrays;
  {
    const BlockArena::Handle arena = BlockArena::create(std::size_t(1) << 20);
    for (int i = 0; i < 1000; ++i) {
      arrays.emplace_back(std::size_t(7 + i % 5), static_cast<float>(i), arena.get());
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(arrays.back().data()) % alignof(std::max_align_t), 0u);
    }
    EXPECT_EQ(arrays.front().get_allocator().resource(), arena.get());
  }
  // The handle is gone; the arrays still hold what was written, each its own.
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(arrays[i].size(), std::size_t(7 + i % 5));
    for (float v : arrays[i]) ASSERT_EQ(v, static_cast<float>(i)) << i;
  }
  // Growing after the handle is gone takes a further block, larger than the first.
  arrays.front().resize(3'000'000, 1.0f);
  EXPECT_EQ(arrays.front()[2'999'999], 1.0f);
  EXPECT_EQ(arrays.front()[0], 0.0f);
}

TEST(BlockArena, ARequestLargerThanABlockGetsABlockOfItsOwn) {
  const BlockArena::Handle arena = BlockArena::create(4096);
  std::pmr::vector<std::uint8_t> small(100, 1, arena.get());
  std::pmr::vector<std::uint8_t> large(std::size_t(5) << 20, 2, arena.get());
  std::pmr::vector<std::uint8_t> after(100, 3, arena.get());
  EXPECT_EQ(small.back(), 1);
  EXPECT_EQ(large.front(), 2);
  EXPECT_EQ(large.back(), 2);
  EXPECT_EQ(after.front(), 3);
}

TEST(BlockArena, CopiesOfItsContainersAreOnTheDefaultResource) {
  const BlockArena::Handle arena = BlockArena::create(4096);
  std::pmr::vector<float> in_arena(10, 1.0f, arena.get());
  const std::pmr::vector<float> copy = in_arena;
  EXPECT_EQ(copy.get_allocator().resource(), std::pmr::get_default_resource());
  const std::pmr::vector<float> moved = std::move(in_arena);
  EXPECT_EQ(moved.get_allocator().resource(), arena.get());
}

TEST(BlockArena, ReservedRoomHoldsTheNextPiecesAndAWarmerChangesNoByte) {
  const BlockArena::Handle arena = BlockArena::create(std::size_t(2) << 20);
  std::pmr::vector<std::uint8_t> first(100, 1, arena.get());
  // 40 MB: more than the block holds, so a block of its own, which the next pieces are taken from.
  const std::size_t bytes = std::size_t(40) << 20;
  const BlockArena::Range room = arena->reserve(bytes);
  ASSERT_NE(room.begin, nullptr);
  EXPECT_EQ(room.size, bytes);
  std::pmr::vector<std::uint8_t> filled(bytes / 2, 0, arena.get());
  EXPECT_EQ(reinterpret_cast<char*>(filled.data()), room.begin);
  for (std::size_t i = 0; i < filled.size(); i += 4096) filled[i] = static_cast<std::uint8_t>(i / 4096);
  std::vector<std::uint8_t> heap(bytes / 2, 7);
  {
    // While the warmer runs (on a kernel without MADV_POPULATE_WRITE it does nothing), the memory keeps
    // what was written and what is written meanwhile.
    const PageWarmer warmer({room, {reinterpret_cast<char*>(heap.data()), heap.size()}});
    for (std::size_t i = 1; i < filled.size(); i += 4096) filled[i] = 9;
  }
  for (std::size_t i = 0; i < filled.size(); i += 4096) {
    ASSERT_EQ(filled[i], static_cast<std::uint8_t>(i / 4096)) << i;
    ASSERT_EQ(filled[i + 1], 9) << i;
    ASSERT_EQ(filled[i + 2], 0) << i;
  }
  for (std::size_t i = 0; i < heap.size(); i += 4096) ASSERT_EQ(heap[i], 7) << i;
  EXPECT_EQ(first[99], 1);
}

}  // namespace
}  // namespace scan_context_loop
