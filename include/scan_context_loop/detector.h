// Online loop detection: describe a keyframe, query the database, then add the keyframe.
#pragma once

#include <string>

#include <memory>
#include <vector>

#include "scan_context_loop/database.h"
#include "scan_context_loop/descriptor.h"
#include "scan_context_loop/verification.h"

namespace scan_context_loop {

/// A candidate that went through geometric verification.
struct VerifiedCandidate {
  std::size_t index = 0;  ///< candidate keyframe number
  Alignment alignment;    ///< its descriptor alignment (distance, yaw prior)
  VerificationResult result;
};

struct Detection {
  bool accepted = false;     ///< false: the keyframe was rejected (see error) and nothing changed
  std::string error;
  std::size_t index = 0;     ///< keyframe number given to the new keyframe
  QueryResult query;         ///< candidates among the earlier keyframes
  std::size_t points_used = 0;
  std::size_t points_skipped = 0;
  double descriptor_seconds = 0.0;  ///< making the descriptor
  double query_seconds = 0.0;       ///< querying the database and adding the keyframe

  /// With Config::verify: the candidates verified, in order; the last one is the accepted loop when
  /// `verified` is set.
  std::vector<VerifiedCandidate> verifications;
  bool verified = false;
  double verify_seconds = 0.0;

  /// The loop decision: a verified candidate with Config::verify, else the descriptor match.
  bool loop() const { return verified || (!verifications_enabled && query.matched); }
  bool verifications_enabled = false;
};

/// Not thread-safe (one owner thread), like Database.
class LoopDetector {
 public:
  explicit LoopDetector(const Config& config)
      : database_(config), store_(static_cast<std::size_t>(config.verify_max_bytes)),
        verification_(verificationConfig(config)) {}

  Detection process(const PointView& points, const KeyframeInfo& info);

  template <typename PointT>
  Detection process(const pcl::PointCloud<PointT>& cloud, const KeyframeInfo& info) {
    return process(viewOf(cloud), info);
  }

  const Database& database() const { return database_; }
  const Config& config() const { return database_.config(); }
  const CloudStore& cloudStore() const { return store_; }

 private:
  void verifyCandidates(const PointView& points, Detection* detection);

  Database database_;
  CloudStore store_;
  VerificationConfig verification_;
};

}  // namespace scan_context_loop
