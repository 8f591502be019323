#include "scan_context_loop/core/block_arena.h"

#include <algorithm>
#include <cstdint>
#include <new>

#include <sys/mman.h>

namespace scan_context_loop {

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;

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

std::size_t BlockArena::mappedBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t total = 0;
  for (const Block& b : blocks_) total += b.size;
  return total;
}

void BlockArena::do_deallocate(void*, std::size_t, std::size_t) { unref(); }

}  // namespace scan_context_loop
