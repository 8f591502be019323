#include "scan_context_loop/detector.h"

#include <chrono>

namespace scan_context_loop {

Detection LoopDetector::process(const PointView& points, const KeyframeInfo& info) {
  Detection detection;
  using Clock = std::chrono::steady_clock;
  if (!database_.acceptable(info, &detection.error)) return detection;
  const auto t0 = Clock::now();
  const HeightGrid grid = makeHeightGrid(points, database_.config());
  detection.points_used = grid.points_used;
  detection.points_skipped = grid.points_skipped;
  Descriptor descriptor = makeDescriptor(grid, database_.config());
  const auto t1 = Clock::now();
  // Query before adding, so the keyframe never finds itself.
  detection.query = database_.query(descriptor, info);
  detection.index = database_.size();
  detection.accepted = database_.add(info, std::move(descriptor), &detection.error);
  detection.descriptor_seconds = std::chrono::duration<double>(t1 - t0).count();
  detection.query_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return detection;
}

}  // namespace scan_context_loop
