// How far the odometry is trusted between two keyframes, learned from the loops already confirmed.
//
// The odometry checks (the candidate gate, Config::gate_odometry_distance, and the rotation check,
// VerificationConfig::odometry_rotation) compare a loop with what the odometry says of the two keyframes,
// allowing for drift over the odometry path between them; the checks of a registered loop, their limits
// and verdicts, are the acceptance rule's (acceptance_rule.h). Real odometry can drift far beyond any
// fixed rate or break down (a heading that keeps turning away, a jump); fixed allowances then refuse
// exactly the loops that would repair it. Two things keep the checks useful:
// - Anchors: each confirmed loop relates its two keyframes exactly, so the odometry is relied on only
//   from the query to the nearest confirmed loop and from that loop's match to the candidate. The
//   prediction with the least odometry path is used (the direct one when no loop is nearer).
// - Measured drift: each confirmed loop also says how far off the direct odometry between its keyframes
//   placed them. Beyond the gate's fixed part (gate_odometry_distance), that error over the path is a
//   drift rate; the gate's radius grows to kMeasuredDriftMargin times the worst rate measured so far,
//   so an odometry that proved bad is trusted less. An odometry whose errors stay within the fixed part
//   measures nothing and keeps the configured rate. The rotation allowance does not grow: once the
//   odometry's heading is 90 degrees or more off, a registration 180 degrees off (a street that looks
//   the same both ways round) would agree with it as well as the true one; a registration the
//   odometry contradicts is left to the consistency check instead (ConsistencyFilter).
// Not thread-safe (one owner, like Database).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {

struct Config;
struct Keyframe;

/// What the odometry predicts of T_query<-candidate, and the odometry path [m] the prediction relies on.
struct OdometryPrediction {
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  double path = 0.0;
  bool anchored = false;  ///< through a confirmed loop rather than the direct odometry
};

class OdometryTrust {
 public:
  /// Allowances are at least this many times the worst measured drift rate.
  static constexpr double kMeasuredDriftMargin = 1.5;
  /// A loop measures a drift rate only over at least this much odometry path [m].
  static constexpr double kMinMeasuredPath = 100.0;

  /// A confirmed loop, T_query<-match = `relative`, between keyframes of one session each (both poses
  /// known); `config` gives the fixed parts of the allowances. Loops across sessions, or without poses,
  /// are ignored.
  void add(const Keyframe& query, const Keyframe& match, const Eigen::Isometry3d& relative, const Config& config);

  /// The odometry's T_query<-candidate for a query at `pose` with odometry path `path` in session
  /// `session`: directly, or through the confirmed loop that leaves the least odometry path (the first
  /// confirmed of equals). The candidate must have a pose and be in the query's session. Looks at the
  /// loops nearest in either keyframe's path first and stops once no other can leave less: a long run
  /// confirms tens of thousands of loops, and a scan over all of them cost milliseconds a call.
  OdometryPrediction predict(const Eigen::Isometry3d& pose, double path, std::uint32_t session,
                             const Keyframe& candidate) const;

  /// Worst translation drift rate measured by confirmed loops beyond the gate's fixed part [m/m].
  double translationRate() const { return translation_rate_; }
  std::size_t anchors() const { return anchors_.size(); }

 private:
  struct Anchor {
    Eigen::Isometry3d query_pose, match_pose, relative;
    double query_path = 0.0, match_path = 0.0;
    std::uint32_t query_session = 0, match_session = 0;
  };
  /// An anchor's place in the order of one of its paths.
  struct Entry {
    double path;
    std::uint32_t anchor;
  };
  /// The anchors of one pair of sessions, ordered by their query's path and by their match's path.
  struct Orders {
    std::vector<Entry> by_query, by_match;
  };
  std::vector<Anchor> anchors_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, Orders> orders_;  ///< by (query session, match session)
  double translation_rate_ = 0.0;
};

/// The translation drift per metre of odometry path the odometry is allowed [m/m]: the larger of
/// gate_odometry_drift and the measured rate with its margin. The candidate gate and the odometry
/// translation check (anchoredTranslationAllowance, acceptance_rule.h) both grow with it.
double allowedDriftRate(const Config& config, const OdometryTrust& trust);
/// The candidate gate's radius over `path` metres of odometry [m]: gate_odometry_distance plus the
/// larger of gate_odometry_drift and the measured rate (with its margin) per metre.
double gateRadius(const Config& config, const OdometryTrust& trust, double path);

}  // namespace scan_context_loop
