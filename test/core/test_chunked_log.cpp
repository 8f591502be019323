// ChunkedLog: items that never move, views that share chunks and never see an item change.
#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

#include <Eigen/Core>

#include "scan_context_loop/core/chunked_log.h"

namespace scan_context_loop {
namespace {

using Log = ChunkedLog<std::uint64_t>;
constexpr std::size_t kChunk = Log::kChunkItems;

TEST(ChunkedLog, ItemsStayWhereTheyWereAcrossChunks) {
  Log log;
  const std::size_t n = 2 * kChunk + 5;
  for (std::size_t i = 0; i < n; ++i) log.push_back(3 * i);
  ASSERT_EQ(log.size(), n);
  const std::uint64_t* first = &log[0];
  const std::uint64_t* last_of_first_chunk = &log[kChunk - 1];
  for (std::size_t i = 0; i < kChunk; ++i) log.push_back(7);
  EXPECT_EQ(&log[0], first) << "appending moved an item";
  EXPECT_EQ(&log[kChunk - 1], last_of_first_chunk);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(log[i], 3 * i) << i;
  EXPECT_EQ(log.back(), 7u);
  EXPECT_EQ(log.mappedBytes(), 4 * Log::kChunkBytes);

  log.resize(kChunk + 1);
  EXPECT_EQ(log.size(), kChunk + 1);
  EXPECT_EQ(log.mappedBytes(), 2 * Log::kChunkBytes) << "chunks past the end are kept";
  log.resize(kChunk + 3, 9);
  EXPECT_EQ(log[kChunk], 3 * kChunk);
  EXPECT_EQ(log[kChunk + 1], 9u);
  EXPECT_EQ(log[kChunk + 2], 9u);
}

TEST(ChunkedLog, AViewKeepsItsItemsAsTakenWhileTheLogGoesOn) {
  Log log;
  for (std::size_t i = 0; i < kChunk + 10; ++i) log.push_back(i);
  const Log::View view = log.view(kChunk - 2, kChunk + 4);
  ASSERT_EQ(view.size(), 6u);
  EXPECT_EQ(view[0], kChunk - 2);
  EXPECT_EQ(view[5], kChunk + 3);

  log.set(kChunk - 1, 1000);  // in a chunk the view shares: copied first
  log.set(kChunk + 1, 2000);
  for (std::size_t i = 0; i < kChunk; ++i) log.push_back(5);
  EXPECT_EQ(log[kChunk - 1], 1000u);
  EXPECT_EQ(log[kChunk + 1], 2000u);
  for (std::size_t i = 0; i < view.size(); ++i) EXPECT_EQ(view[i], kChunk - 2 + i) << i;
  EXPECT_EQ(view.toVector(),
            std::vector<std::uint64_t>({kChunk - 2, kChunk - 1, kChunk, kChunk + 1, kChunk + 2, kChunk + 3}));

  // Clamped to the log; empty when it starts past the end.
  EXPECT_EQ(log.view(0, 10 * kChunk).size(), log.size());
  EXPECT_EQ(log.view(10 * kChunk, 20 * kChunk).size(), 0u);
  EXPECT_EQ(Log::View().size(), 0u);
}

TEST(ChunkedLog, AViewIsReadOnAnotherThreadWhileTheOwnerAppendsAndChanges) {
  ChunkedLog<Eigen::Matrix3f> log;
  for (int i = 0; i < 1000; ++i) log.push_back(Eigen::Matrix3f::Constant(static_cast<float>(i)));
  const ChunkedLog<Eigen::Matrix3f>::View view = log.view(0, log.size());
  bool same = true;
  std::thread reader([&] {
    for (int pass = 0; pass < 20; ++pass) {
      for (std::size_t i = 0; i < view.size(); ++i) same = same && view[i](2, 2) == static_cast<float>(i);
    }
  });
  for (int i = 0; i < 20000; ++i) log.push_back(Eigen::Matrix3f::Identity());
  for (std::size_t i = 0; i < 1000; i += 7) log.set(i, Eigen::Matrix3f::Zero());
  reader.join();
  EXPECT_TRUE(same);
  EXPECT_EQ(log[7](0, 0), 0.0f);
  EXPECT_EQ(log[8](0, 0), 8.0f);
}

}  // namespace
}  // namespace scan_context_loop
