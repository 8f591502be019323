#include "scan_context_loop/core/block_arena.h"

#include <algorithm>
#include <cstdint>
#include <new>

#include <sys/mman.h>

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23  // Linux 5.14; older kernels refuse it, and PageWarmer then does nothing
#endif

namespace scan_context_loop {

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;
constexpr std::size_t kPage = std::size_t(4) << 10;

std::size_t roundUp(std::size_t n, std::size_t to) { return (n + to - 1) / to * to; }

/// `size` bytes of fresh memory at a 2 MB boundary (so that all of it can be on huge pages), or null;
/// marked for huge pages when `huge`, for ordinary ones otherwise.
char* mapHugeAligned(std::size_t size, bool huge) {
  const std::size_t padded = size + kHugePage;
  void* p = ::mmap(nullptr, padded, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return nullptr;
  char* raw = static_cast<char*>(p);
  char* begin = reinterpret_cast<char*>(roundUp(reinterpret_cast<std::uintptr_t>(raw), kHugePage));
  if (begin > raw) ::munmap(raw, static_cast<std::size_t>(begin - raw));
  if (char* end = begin + size; end < raw + padded) ::munmap(end, static_cast<std::size_t>(raw + padded - end));
  // Only a hint: where transparent huge pages are off the memory works the same on 4 KB pages.
  ::madvise(begin, size, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
  return begin;
}

}  // namespace

BlockArena::Handle BlockArena::create(std::size_t block_bytes, Pages pages) {
  return Handle(new BlockArena(roundUp(std::max<std::size_t>(block_bytes, 1), kHugePage), pages));
}

BlockArena::~BlockArena() {
  for (const Block& b : blocks_) ::munmap(b.begin, b.size);
}

void BlockArena::unref() {
  if (references_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
}

void* BlockArena::do_allocate(std::size_t bytes, std::size_t alignment) {
  // Aligned as malloc aligns, so that arrays here read as fast as those on the heap.
  alignment = std::max(alignment, alignof(std::max_align_t));
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t offset = blocks_.empty() ? 0 : roundUp(used_, alignment);
  if (blocks_.empty() || offset + bytes > blocks_.back().size) {
    const std::size_t size = std::max(block_bytes_, roundUp(bytes, kHugePage));
    char* begin = mapHugeAligned(size, pages_ == Pages::kHuge);
    if (begin == nullptr) throw std::bad_alloc();
    blocks_.push_back({begin, size});
    offset = 0;
  }
  used_ = offset + bytes;
  references_.fetch_add(1, std::memory_order_relaxed);
  return blocks_.back().begin + offset;
}

BlockArena::Range BlockArena::reserve(std::size_t bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t offset = blocks_.empty() ? 0 : roundUp(used_, alignof(std::max_align_t));
  if (!blocks_.empty() && offset + bytes <= blocks_.back().size) return {blocks_.back().begin + offset, bytes};
  const std::size_t size = std::max(block_bytes_, roundUp(std::max<std::size_t>(bytes, 1), kHugePage));
  char* begin = mapHugeAligned(size, pages_ == Pages::kHuge);
  if (begin == nullptr) throw std::bad_alloc();
  blocks_.push_back({begin, size});
  used_ = 0;
  return {begin, bytes};
}

std::size_t BlockArena::mappedBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t total = 0;
  for (const Block& b : blocks_) total += b.size;
  return total;
}

void BlockArena::do_deallocate(void*, std::size_t, std::size_t) { unref(); }

PageWarmer::PageWarmer(std::vector<BlockArena::Range> ranges) : ranges_(std::move(ranges)) {
  // Whole pages only: madvise takes a page-aligned start.
  for (BlockArena::Range& r : ranges_) {
    char* begin = reinterpret_cast<char*>(roundUp(reinterpret_cast<std::uintptr_t>(r.begin), kPage));
    r.size = begin < r.begin + r.size ? static_cast<std::size_t>(r.begin + r.size - begin) / kPage * kPage : 0;
    r.begin = begin;
  }
  // A thread only for memory worth one (a keyframe or a few, as a robot of a team shares them, are not).
  constexpr std::size_t kWorthAThread = std::size_t(16) << 20;
  std::size_t total = 0;
  for (const BlockArena::Range& r : ranges_) total += r.size;
  if (total >= kWorthAThread) thread_ = std::thread([this] { run(); });
}

PageWarmer::~PageWarmer() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void PageWarmer::run() {
  std::size_t total = 0;
  for (const BlockArena::Range& r : ranges_) total += r.size;
  if (total == 0) return;
  // From the far end back, in steps of about 8 MB in all, each range's share in proportion to its size
  // (whole pages): the caller, filling from the front, and this thread meet somewhere in between, each
  // having set up its own part, whichever is faster the larger one.
  constexpr std::size_t kStep = std::size_t(8) << 20;
  const std::size_t steps = (total + kStep - 1) / kStep;
  std::vector<std::size_t> left(ranges_.size());  // the start of what is set up, per range
  for (std::size_t i = 0; i < ranges_.size(); ++i) left[i] = ranges_[i].size;
  for (std::size_t step = steps; step-- > 0 && !stop_;) {
    for (std::size_t i = 0; i < ranges_.size(); ++i) {
      const BlockArena::Range& r = ranges_[i];
      const std::size_t from = r.size / steps * step / kPage * kPage;
      if (from >= left[i]) continue;
      if (::madvise(r.begin + from, left[i] - from, MADV_POPULATE_WRITE) != 0) return;  // not supported
      left[i] = from;
    }
  }
}

void adviseHugePages(void* begin, std::size_t size) {
  const auto from = roundUp(reinterpret_cast<std::uintptr_t>(begin), kHugePage);
  const auto to = (reinterpret_cast<std::uintptr_t>(begin) + size) / kHugePage * kHugePage;
  if (to > from) ::madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);
}

}  // namespace scan_context_loop
