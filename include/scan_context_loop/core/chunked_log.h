// An array that only grows at its end, kept in fixed chunks that never move, so that a snapshot of its
// first n items shares the chunks instead of copying the items (DatabaseSnapshot: a save of a million
// keyframes taken between two keyframes).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include "scan_context_loop/core/block_arena.h"

namespace scan_context_loop {

/// Items in chunks of 2 MB, each on a huge page where the kernel gives one: appending never moves an
/// item, and growing past a million items takes a fresh chunk instead of copying every item into new
/// memory (which, on a virtual machine, costs tens of milliseconds in page faults at that size).
///
/// A View shares the chunks holding a range of items as they are when it is taken. The owner may go on
/// appending (into slots no view reads) on its own thread while views are read on others; set() on an
/// item of a shared chunk copies the chunk first, so a view never sees an item change. Not safe for two
/// threads changing one log at once.
template <typename T>
class ChunkedLog {
  // Items are dropped without their destructor and a chunk is copied as bytes: plain values (pointers,
  // fixed-size Eigen matrices of float).
  static_assert(std::is_trivially_destructible_v<T>, "items are dropped without their destructor");
  struct Chunk;

 public:
  static constexpr std::size_t kChunkBytes = std::size_t(2) << 20;
  static constexpr std::size_t kChunkItems = kChunkBytes / sizeof(T);

  /// The items [begin, end) of a log as they were when the view was taken.
  class View {
   public:
    View() = default;
    std::size_t size() const { return end_ - begin_; }
    const T& operator[](std::size_t i) const {
      const std::size_t k = begin_ + i;
      return chunks_[k / kChunkItems - first_chunk_]->items[k % kChunkItems];
    }
    /// The items in a vector of their own.
    std::vector<T> toVector() const {
      std::vector<T> out;
      out.reserve(size());
      for (std::size_t i = 0; i < size(); ++i) out.push_back((*this)[i]);
      return out;
    }

   private:
    friend class ChunkedLog;
    std::vector<std::shared_ptr<const Chunk>> chunks_;
    std::size_t first_chunk_ = 0, begin_ = 0, end_ = 0;
  };

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const T& operator[](std::size_t i) const { return chunks_[i / kChunkItems]->items[i % kChunkItems]; }
  const T& back() const { return (*this)[size_ - 1]; }

  void push_back(const T& item) {
    if (size_ == chunks_.size() * kChunkItems) chunks_.push_back(std::make_shared<Chunk>());
    new (&chunks_[size_ / kChunkItems]->items[size_ % kChunkItems]) T(item);
    ++size_;
  }
  /// Maps the chunks for `n` items now, so that appending up to `n` cannot fail.
  void reserve(std::size_t n) {
    while (chunks_.size() * kChunkItems < n) chunks_.push_back(std::make_shared<Chunk>());
  }
  /// Grows to `n` items, the new ones `item`, or drops the items from `n` on (chunks no view shares are
  /// freed).
  void resize(std::size_t n, const T& item = T()) {
    while (size_ < n) push_back(item);
    size_ = std::min(size_, n);
    chunks_.resize((size_ + kChunkItems - 1) / kChunkItems);
  }
  /// Replaces item `i`; a chunk a view shares is copied first.
  void set(std::size_t i, const T& item) {
    std::shared_ptr<Chunk>& chunk = chunks_[i / kChunkItems];
    if (chunk.use_count() > 1) chunk = std::make_shared<Chunk>(*chunk);
    new (&chunk->items[i % kChunkItems]) T(item);
  }
  /// A view of the items [begin, end), clamped to the log.
  View view(std::size_t begin, std::size_t end) const {
    View v;
    v.end_ = std::min(end, size_);
    v.begin_ = std::min(begin, v.end_);
    if (v.begin_ == v.end_) return v;
    v.first_chunk_ = v.begin_ / kChunkItems;
    v.chunks_.assign(chunks_.begin() + static_cast<long>(v.first_chunk_),
                     chunks_.begin() + static_cast<long>((v.end_ - 1) / kChunkItems + 1));
    return v;
  }
  /// Bytes of the chunks mapped (whole chunks: the last one's unused end too).
  std::size_t mappedBytes() const { return chunks_.size() * kChunkBytes; }

 private:
  struct Chunk {
    Chunk() : items(static_cast<T*>(std::aligned_alloc(kChunkBytes, kChunkBytes))) {
      if (items == nullptr) throw std::bad_alloc();
      adviseHugePages(items, kChunkBytes);
    }
    Chunk(const Chunk& other) : Chunk() {
      std::memcpy(static_cast<void*>(items), static_cast<const void*>(other.items), kChunkItems * sizeof(T));
    }
    Chunk& operator=(const Chunk&) = delete;
    ~Chunk() { std::free(items); }
    T* items;
  };
  std::vector<std::shared_ptr<Chunk>> chunks_;
  std::size_t size_ = 0;
};

}  // namespace scan_context_loop
