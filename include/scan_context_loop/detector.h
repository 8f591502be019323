// Online loop detection: describe a keyframe, query the database, then add the keyframe.
#pragma once

#include <string>

#include "scan_context_loop/database.h"
#include "scan_context_loop/descriptor.h"

namespace scan_context_loop {

struct Detection {
  bool accepted = false;     ///< false: the keyframe was rejected (see error) and nothing changed
  std::string error;
  std::size_t index = 0;     ///< keyframe number given to the new keyframe
  QueryResult query;         ///< candidates among the earlier keyframes
  std::size_t points_used = 0;
  std::size_t points_skipped = 0;
  double descriptor_seconds = 0.0;  ///< making the descriptor
  double query_seconds = 0.0;       ///< querying the database and adding the keyframe
};

/// Not thread-safe (one owner thread), like Database.
class LoopDetector {
 public:
  explicit LoopDetector(const Config& config) : database_(config) {}

  Detection process(const PointView& points, const KeyframeInfo& info);

  template <typename PointT>
  Detection process(const pcl::PointCloud<PointT>& cloud, const KeyframeInfo& info) {
    return process(viewOf(cloud), info);
  }

  const Database& database() const { return database_; }
  const Config& config() const { return database_.config(); }

 private:
  Database database_;
};

}  // namespace scan_context_loop
