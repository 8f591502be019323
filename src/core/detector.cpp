#include "scan_context_loop/detector.h"

namespace scan_context_loop {

Detection LoopDetector::process(const PointView& points, const KeyframeInfo& info) {
  Detection detection;
  if (!database_.acceptable(info, &detection.error)) return detection;
  const HeightGrid grid = makeHeightGrid(points, database_.config());
  detection.points_used = grid.points_used;
  detection.points_skipped = grid.points_skipped;
  Descriptor descriptor = makeDescriptor(grid, database_.config());
  // Query before adding, so the keyframe never finds itself.
  detection.query = database_.query(descriptor, info);
  detection.index = database_.size();
  detection.accepted = database_.add(info, std::move(descriptor), &detection.error);
  return detection;
}

}  // namespace scan_context_loop
