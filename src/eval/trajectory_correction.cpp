// The trajectory correction with the reference pose-graph backend (graph/pose_graph.h, Ceres); a build
// without the backend uses trajectory_correction_unavailable.cpp.
#include "scan_context_loop/eval/trajectory_correction.h"

#include <algorithm>
#include <map>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {
namespace eval {

namespace {

/// A pose graph of the prior map's keyframes, each held at its stored pose (nodes 0 .. P-1, its database
/// indices), and the sequence's odometry keyframe poses as a chain (node P + k for sequence keyframe k).
class CorrectionGraph {
 public:
  CorrectionGraph(const Sequence& s, const Evaluation& e, const PoseGraphConfig& config)
      : graph(config), e_(e), prior_count_(e.prior_keyframes.frames.size()) {
    for (const auto& pose : e.prior_keyframes.odometry) ok_ &= graph.addFixedKeyframe(pose) >= 0;
    for (const auto& pose : s.odometry) ok_ &= graph.addKeyframe(pose) >= 0;
  }

  /// Every pose went in (a pose that is not finite, or no rotation, does not).
  bool ok() const { return ok_; }
  std::size_t priorCount() const { return prior_count_; }
  std::size_t nodeOfKeyframe(std::size_t k) const { return prior_count_ + k; }
  /// The node of a database index, or -1.
  long nodeOfIndex(std::size_t index) const {
    if (index < prior_count_) return static_cast<long>(index);
    const long k = index < e_.keyframe_of.size() ? e_.keyframe_of[index] : -1;
    return k < 0 ? -1 : static_cast<long>(nodeOfKeyframe(k));
  }
  bool inPrior(std::size_t node) const { return node < prior_count_; }

  /// Adds the loops the detector reported (the verified ones when verification is on); counts those
  /// into the prior in `prior_loops` when given.
  std::size_t addReportedLoops(const Config& config, std::size_t* prior_loops = nullptr) {
    std::size_t added = 0;
    for (const Loop& loop : e_.loops) {
      if (e_.verification && !loop.verified) continue;
      const long q = nodeOfIndex(loop.query), m = nodeOfIndex(loop.match);
      if (q < 0 || m < 0) continue;
      if (!graph.addLoop(q, m, loop.relative(), loopCovariance(loop, config))) continue;
      ++added;
      if (prior_loops != nullptr && (inPrior(q) || inPrior(m))) ++*prior_loops;
    }
    return added;
  }

  /// The sequence's keyframes' corrected poses.
  std::vector<Eigen::Isometry3d> sequencePoses() const {
    std::vector<Eigen::Isometry3d> all = graph.poses();
    return std::vector<Eigen::Isometry3d>(all.begin() + static_cast<long>(prior_count_), all.end());
  }

  /// The graph's factors among the sequence's keyframes, numbered as sequence keyframes (those that
  /// touch a prior keyframe are left out): the graph --save-map writes.
  std::vector<PoseGraphFactor> sequenceFactors() const {
    std::vector<PoseGraphFactor> factors;
    for (PoseGraphFactor f : graph.factors()) {
      if (inPrior(f.a) || inPrior(f.b)) continue;
      f.a -= prior_count_;
      f.b -= prior_count_;
      factors.push_back(f);
    }
    return factors;
  }

  PoseGraph graph;

 private:
  const Evaluation& e_;
  std::size_t prior_count_;
  bool ok_ = true;
};

/// Where each frame number is among `frames` (a sequence's keyframes), -1 for none.
std::vector<long> indexOfFrame(const std::vector<int>& frames) {
  std::vector<long> of;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (frames[k] >= static_cast<int>(of.size())) of.resize(frames[k] + 1, -1);
    of[frames[k]] = static_cast<long>(k);
  }
  return of;
}

long lookUp(const std::vector<long>& of, int frame) {
  return frame >= 0 && frame < static_cast<int>(of.size()) ? of[frame] : -1;
}

}  // namespace

TrajectoryCorrection correctTrajectory(const Sequence& s, const Evaluation& e, const Config& config,
                                       const PoseGraphConfig& graph_config) {
  TrajectoryCorrection c;
  if (s.odometry.size() < 3) {
    c.note = "fewer than 3 keyframes";
    return c;
  }
  c.own_odometry = s.odometry_from_file;
  c.in_prior = e.has_prior;
  if (!c.own_odometry) {
    c.note =
        "no odometry of its own (no odom_poses.txt, or --truth-odometry): the truth is the odometry (error 0), "
        "and the corrected error is what the loops' registration errors do to a perfect trajectory";
  }
  if (c.in_prior) {
    c.prior_source = e.prior_source;
    c.prior_keyframes = e.prior_keyframes.frames.size();
    c.prior_odometry = absoluteTrajectoryError(e.prior_keyframes.odometry, e.prior_keyframes.truth);
    c.note += std::string(c.note.empty() ? "" : "; ") +
              "in a prior map: its keyframes held at their stored poses, the sequence's loops into them and its "
              "own corrected its trajectory, scored against the sequence's truth";
  }
  c.odometry = absoluteTrajectoryError(s.odometry, s.truth);

  CorrectionGraph corrected(s, e, graph_config);
  if (!corrected.ok()) {
    c.note = "a keyframe pose is not finite or its rotation is not one";
    return c;
  }
  c.loops = corrected.addReportedLoops(config, &c.prior_loops);
  corrected.graph.optimize();
  c.corrected_poses = corrected.sequencePoses();
  c.corrected_factors = corrected.sequenceFactors();
  c.corrected = absoluteTrajectoryError(c.corrected_poses, s.truth);
  for (std::size_t i = 0; i < corrected.priorCount(); ++i) {
    const double moved = (corrected.graph.pose(i).translation() - e.prior_keyframes.odometry[i].translation()).norm();
    c.prior_moved = std::max(c.prior_moved, moved);
  }

  // Plain Scan Context: the descriptor's best candidate under the threshold, yaw prior only.
  CorrectionGraph plain(s, e, graph_config);
  const std::vector<long> of_frame = indexOfFrame(s.frames), of_prior_frame = indexOfFrame(e.prior_keyframes.frames);
  for (const QueryOutcome& o : e.outcomes) {
    if (o.match < 0 || !(o.distance < config.distance_threshold)) continue;
    const long q = lookUp(of_frame, o.query);
    const long m = o.match_in_prior ? lookUp(of_prior_frame, o.match) : lookUp(of_frame, o.match);
    if (q < 0 || m < 0) continue;
    Loop loop;
    loop.alignment.yaw = o.yaw;
    const std::size_t match_node = o.match_in_prior ? static_cast<std::size_t>(m) : plain.nodeOfKeyframe(m);
    if (plain.graph.addLoop(plain.nodeOfKeyframe(q), match_node, priorPose(o.yaw), loopCovariance(loop, config))) {
      ++c.plain_loops;
      c.plain_false_loops += !o.correct;
    }
  }
  plain.graph.optimize();
  c.plain = absoluteTrajectoryError(plain.sequencePoses(), s.truth);

  // One false loop, claimed as sure as a verified one: from the keyframe three quarters of the way to
  // the first earlier keyframe 40-100 m away from it.
  CorrectionGraph with_false(s, e, graph_config);
  with_false.addReportedLoops(config);
  const std::size_t q = s.truth.size() * 3 / 4;
  long m = -1;
  for (std::size_t k = 0; k < q && m < 0; ++k) {
    const double gap = (s.truth[k].translation() - s.truth[q].translation()).norm();
    if (gap >= 40.0 && gap <= 100.0) m = static_cast<long>(k);
  }
  if (m >= 0) {
    Eigen::Matrix<double, 6, 1> floor;
    floor << config.verification.min_translation_variance, config.verification.min_translation_variance,
        config.verification.min_translation_variance, config.verification.min_rotation_variance,
        config.verification.min_rotation_variance, config.verification.min_rotation_variance;
    if (with_false.graph.addLoop(with_false.nodeOfKeyframe(q), with_false.nodeOfKeyframe(m),
                                 Eigen::Isometry3d::Identity(), floor.asDiagonal())) {
      c.false_loop_gap = (s.truth[m].translation() - s.truth[q].translation()).norm();
    }
  }
  with_false.graph.optimize();
  c.with_false_loop = absoluteTrajectoryError(with_false.sequencePoses(), s.truth);
  c.computed = true;
  return c;
}

}  // namespace eval
}  // namespace scan_context_loop
