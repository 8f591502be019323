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
  if (detection.accepted && database_.config().verify) verifyCandidates(points, &detection);
  return detection;
}

void LoopDetector::verifyCandidates(const PointView& points, Detection* detection) {
  const auto start = std::chrono::steady_clock::now();
  const Config& config = database_.config();
  detection->verifications_enabled = true;
  VerificationCloud cloud = prepareCloud(points, verification_);
  int tried = 0;
  for (const Candidate& c : detection->query.candidates) {
    if (tried >= config.verify_max_candidates || !(c.alignment.distance < config.verify_threshold)) break;
    ++tried;
    VerifiedCandidate v;
    v.index = c.index;
    v.alignment = c.alignment;
    const VerificationCloud* stored = store_.get(c.index);
    if (stored == nullptr) {
      v.result.reason = "unverifiable: the candidate's cloud was dropped to stay within verify_max_bytes";
    } else {
      v.result = verifyWithYaw(cloud, *stored, c.alignment.yaw, verification_);
    }
    detection->verifications.push_back(v);
    if (v.result.accepted) {
      detection->verified = true;
      break;
    }
  }
  store_.add(detection->index, std::move(cloud));
  detection->verify_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace scan_context_loop
