// The evaluator's pose graph over a sequence (a private header of the eval library, built with the
// backend): the prior map's keyframes held at their stored poses, the sequence's odometry chain, and
// the loops the trajectory correction and the graph study put in: the reported ones (as measured, or
// at their true relative pose), the oracle's (every revisit at its true relative pose) and one false
// loop.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {
namespace eval {

/// Which relative pose a reported loop goes in with.
enum class LoopPose {
  kMeasured,  ///< the registration's (what the node publishes)
  kTrue,      ///< the truth's, for the same pair and covariance: what the loops' own error costs
};

/// Which covariance a loop goes in with.
enum class LoopCovariance {
  kReported,  ///< the one the node publishes (loopCovariance)
  kFloor,     ///< the verification's floors (min_translation_variance, min_rotation_variance), diagonal
};

/// A verified loop's covariance at the verification's floors: as sure as the node ever claims to be.
Matrix6d floorCovariance(const Config& config);

/// Graph nodes: the prior map's keyframes 0 .. P-1 (its database indices), held fixed at their stored
/// poses, then the sequence's keyframes as one chain (node P + k for sequence keyframe k).
class CorrectionGraph {
 public:
  CorrectionGraph(const Sequence& s, const Evaluation& e, const PoseGraphConfig& config);

  /// Every pose went in (a pose that is not finite, or no rotation, does not).
  bool ok() const { return ok_; }
  std::size_t priorCount() const { return prior_count_; }
  std::size_t nodeOfKeyframe(std::size_t k) const { return prior_count_ + k; }
  /// The node of a database index, or -1.
  long nodeOfIndex(std::size_t index) const;
  /// The node of a sequence frame number, or -1.
  long nodeOfFrame(int frame) const;
  bool inPrior(std::size_t node) const { return node < prior_count_; }
  /// The true pose of a node (the prior's truth or the sequence's).
  const Eigen::Isometry3d& truth(std::size_t node) const;

  /// Adds the loops the detector reported (the verified ones when verification is on), with `pose` and
  /// `covariance` x `covariance_scale`; counts those into the prior in `prior_loops` when given.
  std::size_t addReportedLoops(const Config& config, LoopPose pose = LoopPose::kMeasured,
                               LoopCovariance covariance = LoopCovariance::kReported, double covariance_scale = 1.0,
                               std::size_t* prior_loops = nullptr);
  /// The oracle: every revisit (each query with an eligible keyframe within the revisit radius, joined to
  /// the nearest one, QueryOutcome::revisit_index) at its true relative pose, with `covariance` (a
  /// verified loop's). Returns how many went in.
  std::size_t addOracleLoops(const Matrix6d& covariance);
  /// One false loop, claimed with `covariance`: from the keyframe three quarters of the way to the first
  /// earlier keyframe 40-100 m away from it, at the identity. Returns its true length [m], -1 when no
  /// pair was that far apart.
  double addFalseLoop(const Matrix6d& covariance);

  /// The sequence's keyframes' corrected poses.
  std::vector<Eigen::Isometry3d> sequencePoses() const;
  /// The graph's factors among the sequence's keyframes, numbered as sequence keyframes (those that
  /// touch a prior keyframe are left out): the graph --save-map writes.
  std::vector<PoseGraphFactor> sequenceFactors() const;

  PoseGraph graph;

 private:
  const Sequence& s_;
  const Evaluation& e_;
  std::size_t prior_count_;
  std::vector<long> keyframe_of_frame_;  ///< sequence keyframe of each frame number, -1: none
  bool ok_ = true;
};

}  // namespace eval
}  // namespace scan_context_loop
