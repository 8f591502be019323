// Memory for many arrays made at once and kept about as long as each other (the descriptors of a loaded
// database), taken from a few large blocks on transparent huge pages.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <memory_resource>
#include <mutex>
#include <thread>
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

  /// Maps, now, a block that the next `bytes` of pieces will be taken from (when the current block has
  /// less room left), and returns the memory those pieces will occupy: [begin, begin + size). A caller
  /// that knows how much it is about to allocate passes it to a PageWarmer.
  struct Range {
    char* begin = nullptr;
    std::size_t size = 0;
  };
  Range reserve(std::size_t bytes);

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

/// Has the kernel set up (and zero) fresh memory on a thread of its own, from the far end back, while the
/// caller fills it from the front: on a virtual machine the first touch of new memory costs far more
/// than writing it (1.4-2.3 s a gigabyte against 0.06 s, doc/database_file.md), and the two threads
/// share that work, meeting wherever the slower one has got to. Several ranges (filled in step, as a
/// vector of records and the arena of their arrays are) advance in proportion to their sizes. Uses
/// madvise(MADV_POPULATE_WRITE), which changes no byte, so the caller may write anywhere meanwhile;
/// where the kernel lacks it (before Linux 5.14) nothing happens and the caller's writes fault the
/// pages in as before. Below 16 MB in all it does nothing (not worth a thread). Stops and joins in its
/// destructor.
class PageWarmer {
 public:
  explicit PageWarmer(std::vector<BlockArena::Range> ranges);
  ~PageWarmer();
  PageWarmer(const PageWarmer&) = delete;
  PageWarmer& operator=(const PageWarmer&) = delete;

 private:
  void run();
  std::vector<BlockArena::Range> ranges_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// Asks for transparent huge pages on the part of [begin, begin + size) that whole huge pages cover
/// (memory from the heap, a std::vector's after reserve()): 2 MB a page fault instead of 4 KB.
void adviseHugePages(void* begin, std::size_t size);

}  // namespace scan_context_loop
