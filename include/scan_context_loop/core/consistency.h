// Pairwise consistency of loop closures, in the spirit of PCM (pairwise consistent measurement sets):
// a loop is trusted only once other loops agree with it through the odometry.
#pragma once

#include <cstddef>
#include <deque>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {

class Database;

/// A loop-closure constraint between keyframe `query` and the earlier keyframe `match`.
struct Loop {
  std::size_t query = 0, match = 0;
  /// The virtual viewpoint (query frame, metres) the match was found from; zero for the real one.
  Eigen::Vector2d viewpoint = Eigen::Vector2d::Zero();
  Alignment alignment;
  /// Geometric verification accepted it; `verification` then holds the registered pose.
  bool verified = false;
  VerificationResult verification;
  /// Other loops that agreed with it (consistency check), when it was reported.
  int support = 0;
  /// Found by loop tracking (loop_tracking.h): the match is where the last confirmed loop and the
  /// odometry put the query, registered from that guess, not a descriptor candidate.
  bool tracked = false;

  /// T_query<-match: the registered pose when verified, else the descriptor prior
  /// (priorPose(alignment.yaw, viewpoint)).
  Eigen::Isometry3d relative() const;
  /// Verified and accepted, with no rejection (a check confirmed it).
  void markConfirmed();
};

/// Two loops a = (i <- j) and b = (k <- l) agree when the cycle
/// T_i<-k (odometry) * T_k<-l (loop b) * T_l<-j (odometry) * T_j<-i (loop a, inverted)
/// is the identity within Config::consistency_translation + consistency_drift * (odometry path i..k +
/// path j..l) metres and consistency_rotation degrees. Keyframes without an odometry pose never agree.
/// `translation_error` / `rotation_error` (metres, radians) receive the cycle's residual when given.
/// `strict`: without the drift allowance (how a loop that needs support is checked: it must land where
/// the confirmed loop and the odometry put it, within the translation a constraint may be off by).
bool loopsAgree(const Loop& a, const Loop& b, const Database& database, double* translation_error = nullptr,
                double* rotation_error = nullptr, bool strict = false);

/// Online pairwise consistency check. Each verified loop waits, for up to Config::consistency_window
/// keyframes, until Config::consistency_min_support other loops (earlier or later ones, whose queries
/// lie within the window) agree with it; it is then confirmed and reported, possibly a few keyframes
/// after its query. One that finds no support in time is dropped. A single wrong loop, which nothing
/// else confirms, is never reported; a revisit, which gives a run of loops, is reported from its second
/// loop on, together with the first. A loop that needs support (its registration passed every test but
/// the overlap or the free-space bound in full; VerificationResult::needs_support) is confirmed only by a
/// confirmed loop that passed in full and agrees with it strictly (loopsAgree's `strict`); it supports
/// nothing itself. A loop the odometry contradicted (VerificationResult::odometry_contradicted: every
/// geometric test passed, but its rotation disagrees with the odometry's beyond what odometry_trust.h
/// allows) needs one support more, and it supports only loops like it.
/// Not thread-safe (one owner, like Database).
class ConsistencyFilter {
 public:
  explicit ConsistencyFilter(const Config& config) : config_(config) {}

  /// Offers the loop of a new keyframe (queries in increasing order). Loops confirmed by it, earlier
  /// waiting ones first and then possibly itself, are appended to `confirmed`.
  void offer(const Loop& loop, const Database& database, std::vector<Loop>* confirmed);

  /// Takes a loop the caller has confirmed and reported already (one that agrees with the last confirmed
  /// loop of a revisit, LoopTracker): like a confirmed loop it supports the waiting ones (unless it
  /// needed support itself); those it confirms are appended to `confirmed`.
  void add(const Loop& loop, const Database& database, std::vector<Loop>* confirmed);

  /// Ends the wait of the loops too old for keyframe `query` to support; the unconfirmed ones are
  /// appended to `dropped`, not verified, with the acceptance rule's verdict (unsupportedVerdict: the
  /// support they had and needed). Call once per keyframe, before offer().
  void advance(std::size_t query, std::vector<Loop>* dropped);

  /// Loops still waiting for support.
  std::size_t waiting() const;

  /// Takes new values of the live settings (Setting::live): the tolerances apply from the next offer.
  void reconfigure(const Config& config) { config_ = config; }

 private:
  struct Entry {
    Loop loop;
    bool confirmed = false;
  };
  /// The support `loop` needs to be confirmed (the acceptance rule's requiredSupport).
  int supportNeeded(const Loop& loop) const;
  /// A loop the odometry contradicted is not confirmed while a loop within the window that the odometry
  /// contradicts less (VerificationResult::odometry_excess; a confirmed one, or one that passed in full)
  /// disagrees with it: a registration 180 degrees off in a street that looks the same both ways round
  /// gives a run of loops as consistent with each other as the true ones.
  bool outranked(const Entry& entry, const Database& database) const;
  /// Whether agreeing `giver` counts as support for `taker`.
  static bool supports(const Loop& giver, const Loop& taker);
  /// Their queries lie within consistency_window keyframes of each other.
  bool near(const Entry& a, const Entry& b) const;
  /// Reports `entry` as confirmed; a loop that passed verification in full then confirms the waiting
  /// loops that need support (VerificationResult::needs_support) and agree with it.
  void confirm(Entry* entry, const Database& database, std::vector<Loop>* confirmed);
  /// The waiting loops that need support and agree strictly with `entry`, a confirmed loop that passed
  /// in full, are confirmed.
  void confirmWeak(const Entry& entry, const Database& database, std::vector<Loop>* confirmed);
  Config config_;
  std::deque<Entry> recent_;  // loops whose query is within the window, oldest first
};

}  // namespace scan_context_loop
