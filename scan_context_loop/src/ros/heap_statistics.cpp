#include "scan_context_loop/ros/heap_statistics.h"

#include <chrono>

#if defined(__GLIBC__)
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
