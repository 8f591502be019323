// Loop tracking: once a revisit is established by a confirmed loop, the odometry says where each
// following keyframe stands in the revisited place's frame, so the keyframe nearest to that spot is a
// candidate with a pose guess, whatever its descriptor distance. On a changed street (cars parked
// elsewhere, other foliage, another lane) the descriptor misses some keyframes of a revisit that
// registration from a good guess still verifies.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>

#include <Eigen/Geometry>

#include "scan_context_loop/core/consistency.h"
#include "scan_context_loop/core/database.h"

namespace scan_context_loop {

/// A keyframe where the last confirmed loop and the odometry put a new one.
struct TrackedCandidate {
  std::size_t index = 0;  ///< the stored keyframe nearest to the predicted position
  /// T_query<-match (sensor frames) that the anchor loop and the odometry predict.
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  double gap = 0.0;  ///< distance from the predicted position to the keyframe's [m]
};

/// Keeps the latest confirmed loop that passed verification in full (the anchor) and predicts from it.
/// Not thread-safe (one owner, like Database).
class LoopTracker {
 public:
  /// The farthest a predicted position may be from the keyframe chosen for it [m]: the reach of the
  /// verification's coarse search (+-6 m) less a margin for the prediction's own error.
  static constexpr double kReach = 5.0;

  /// Makes `loop` the anchor when it is verified in full (not one that needed support) and newer (a
  /// later query) than the current anchor.
  void anchor(const Loop& loop);
  const std::optional<Loop>& current() const { return anchor_; }
  void clear() { anchor_.reset(); }

  /// For keyframe `query`, already in `database`: the keyframe of the anchor's match session nearest to
  /// where the anchor and the odometry put the query, among the first `eligible` keyframes (the ones
  /// the query may match) near the anchor's match along that session (nearAnchorMatch) and, when
  /// `usable` is given, for which it holds (the keyframes whose registration data are kept), within kReach. Nothing
  /// when Config::track_distance is 0, the anchor's query is of another session or more than track_distance of odometry
  /// path back, or a pose is missing.
  std::optional<TrackedCandidate> predict(const Database& database, std::size_t query, std::size_t eligible,
                                          const std::function<bool(std::size_t)>& usable = {}) const;

  /// Whether a loop (tracked or not) lands where the anchor and the odometry put it: its query is one
  /// predict() would serve, its match is near the anchor's (nearAnchorMatch) and it agrees with the anchor
  /// (loopsAgree), `strict` (without the drift allowance) for a loop that needs support.
  bool agrees(const Loop& loop, const Database& database, bool strict) const;

 private:
  /// Keyframe `query` follows the anchor's query in its session, within Config::track_distance of path,
  /// and the poses predict() needs are there.
  bool reaches(const Database& database, std::size_t query) const;
  /// Keyframe `index` is of the anchor's match session and its odometry path from the anchor's match is
  /// at most the query's from the anchor's query, plus kReach: the odometry that relates the two is as
  /// short on the match's side as on the query's. (A place the match session passed twice has a
  /// keyframe from each pass; the other pass is related only through all the drift in between.)
  bool nearAnchorMatch(const Database& database, std::size_t query, std::size_t index) const;

  std::optional<Loop> anchor_;
};

}  // namespace scan_context_loop
