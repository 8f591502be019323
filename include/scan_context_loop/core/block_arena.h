// Memory for many arrays made at once and kept about as long as each other (the descriptors of a loaded
// database), taken from a few large blocks on transparent huge pages.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <memory_resource>
#include <mutex>
#include <vector>

namespace scan_context_loop {

/// A memory resource that hands out pieces of large blocks, each block mapped on its own and (by default)
/// marked for transparent huge pages (madvise MADV_HUGEPAGE). A process touching hundreds of megabytes for the
/// first time then takes a page fault per 2 MB instead of one per 4 KB, which on a virtual machine is
/// most of what loading a large database costs. A piece given back is not reused: the blocks are
/// unmapped when every piece has come back.
///
/// The arena frees itself once its handle is gone and every piece has come back, so containers using it
/// (std::pmr) may outlive the handle: keyframes decoded into it can move into a database and live as
/// long as the database does. Allocation and deallocation may happen on any thread. The one thing not
/// to do: once the handle is gone, let a container that holds none of the arena's memory (empty or
/// moved from) allocate again after every other piece came back, when the arena is gone.
class BlockArena final : public std::pmr::memory_resource {
 public:
  struct Release {
    void operator()(BlockArena* arena) const { arena->unref(); }
  };
  using Handle = std::unique_ptr<BlockArena, Release>;

  /// Whether the blocks are marked for transparent huge pages. Worth it for memory touched all at once
  /// (a database loaded), not for memory filled a little at a time: where the kernel compacts memory
  /// to find a huge page, the first touch of each 2 MB can stall for milliseconds (doc/testing.md, the
  /// soak), so such blocks ask for ordinary pages.
  enum class Pages { kHuge, kOrdinary };

  /// A new arena whose blocks hold at least `block_bytes` (rounded up to 2 MB); a request larger than
  /// that gets a block of its own.
  static Handle create(std::size_t block_bytes, Pages pages = Pages::kHuge);

  /// Bytes of the blocks it has mapped so far.
  std::size_t mappedBytes() const;

 private:
  BlockArena(std::size_t block_bytes, Pages pages) : block_bytes_(block_bytes), pages_(pages) {}
  ~BlockArena() override;
  void unref();

  void* do_allocate(std::size_t bytes, std::size_t alignment) override;
  void do_deallocate(void* p, std::size_t bytes, std::size_t alignment) override;
  bool do_is_equal(const std::pmr::memory_resource& other) const noexcept override { return this == &other; }

  struct Block {
    char* begin;
    std::size_t size;
  };
  const std::size_t block_bytes_;
  const Pages pages_;
  mutable std::mutex mutex_;  // guards blocks_ and used_
  std::vector<Block> blocks_;
  std::size_t used_ = 0;  // bytes handed out of blocks_.back()
  /// The handle plus the pieces not given back.
  std::atomic<std::size_t> references_{1};
};

}  // namespace scan_context_loop
