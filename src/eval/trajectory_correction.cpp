// The trajectory correction with the reference pose-graph backend (graph/pose_graph.h, Ceres); a build
// without the backend uses trajectory_correction_unavailable.cpp.
#include "scan_context_loop/eval/trajectory_correction.h"

#include <algorithm>
#include <map>

#include "correction_graph.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/verification.h"
#include "scan_context_loop/eval/graph_study.h"

namespace scan_context_loop {
namespace eval {

namespace {

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
  c.loops = corrected.addReportedLoops(config, LoopPose::kMeasured, LoopCovariance::kReported, 1.0, &c.prior_loops);
  corrected.graph.optimize();
  c.corrected_poses = corrected.sequencePoses();
  c.corrected_factors = corrected.sequenceFactors();
  c.corrected = absoluteTrajectoryError(c.corrected_poses, s.truth);
  const std::vector<bool> revisited = revisitedKeyframes(s, e);
  c.corrected_revisited = partError(c.corrected_poses, s.truth, c.corrected.alignment, revisited, true);
  c.corrected_rest = partError(c.corrected_poses, s.truth, c.corrected.alignment, revisited, false);
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
  c.false_loop_gap = with_false.addFalseLoop(floorCovariance(config));
  with_false.graph.optimize();
  c.with_false_loop = absoluteTrajectoryError(with_false.sequencePoses(), s.truth);

  // What the loops could do: the same pairs at their true relative poses (the loops' own error), and
  // every revisit at its true relative pose with a verified loop's covariance at its floors (the pairs
  // the detector missed as well): the oracle.
  CorrectionGraph reported_true(s, e, graph_config);
  reported_true.addReportedLoops(config, LoopPose::kTrue);
  reported_true.graph.optimize();
  c.reported_true = absoluteTrajectoryError(reported_true.sequencePoses(), s.truth);
  CorrectionGraph oracle(s, e, graph_config);
  c.oracle_loops = oracle.addOracleLoops(floorCovariance(config));
  oracle.graph.optimize();
  c.oracle = absoluteTrajectoryError(oracle.sequencePoses(), s.truth);
  c.computed = true;
  return c;
}

}  // namespace eval
}  // namespace scan_context_loop
