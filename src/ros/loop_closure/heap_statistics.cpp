#include "loop_closure/heap_statistics.h"

#include <chrono>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define SCL_SANITIZED_MALLOC 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SCL_SANITIZED_MALLOC 1
#endif

// Under ASan or TSan the sanitizer's allocator serves malloc and glibc's mallinfo2 reports zeros: no
// statistics rather than wrong ones.
#if defined(__GLIBC__) && !defined(SCL_SANITIZED_MALLOC)
#include <malloc.h>
#define SCL_HAVE_MALLINFO2 (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
#else
#define SCL_HAVE_MALLINFO2 0
#endif

namespace scan_context_loop {

bool HeapStatistics::available() { return SCL_HAVE_MALLINFO2; }

bool HeapStatistics::afterKeyframe(bool queue_empty) {
  if (interval_ <= 0 || !available()) return false;
  if (since_ < interval_) ++since_;
  if (since_ < interval_ || !queue_empty) return false;
  const auto start = std::chrono::steady_clock::now();
#if SCL_HAVE_MALLINFO2
  const struct mallinfo2 heap = mallinfo2();
  allocated_ = static_cast<long long>(heap.uordblks + heap.hblkhd);
  free_ = static_cast<long long>(heap.fordblks);
#endif
  last_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++reads_;
  since_ = 0;
  return true;
}

}  // namespace scan_context_loop
