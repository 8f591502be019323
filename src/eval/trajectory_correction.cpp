// The trajectory correction with the reference pose-graph backend (graph/pose_graph.h, Ceres); a build
// without the backend uses trajectory_correction_unavailable.cpp.
#include "scan_context_loop/eval/trajectory_correction.h"

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {
namespace eval {

namespace {

/// A graph of the sequence's odometry keyframe poses.
void addOdometry(const Sequence& sequence, PoseGraph* graph) {
  for (const auto& pose : sequence.odometry) graph->addKeyframe(pose);
}

/// The sequence keyframe of a database index, or -1.
long keyframeOf(const Evaluation& e, std::size_t index) {
  return index < e.keyframe_of.size() ? e.keyframe_of[index] : -1;
}

std::size_t addReportedLoops(const Evaluation& e, const Config& config, PoseGraph* graph) {
  std::size_t added = 0;
  for (const Loop& loop : e.loops) {
    if (e.verification && !loop.verified) continue;
    const long q = keyframeOf(e, loop.query), m = keyframeOf(e, loop.match);
    if (q < 0 || m < 0) continue;
    added += graph->addLoop(static_cast<std::size_t>(q), static_cast<std::size_t>(m), loop.relative(),
                            loopCovariance(loop, config));
  }
  return added;
}

/// Where each sequence frame number is among the keyframes.
std::vector<long> keyframeOfFrame(const Sequence& s) {
  std::vector<long> of;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    if (s.frames[k] >= static_cast<int>(of.size())) of.resize(s.frames[k] + 1, -1);
    of[s.frames[k]] = static_cast<long>(k);
  }
  return of;
}

}  // namespace

TrajectoryCorrection correctTrajectory(const Sequence& s, const Evaluation& e, const Config& config,
                                       const PoseGraphConfig& graph_config) {
  TrajectoryCorrection c;
  if (!s.odometry_from_file) {
    c.note = "the sequence has no odom_poses.txt: its odometry is the truth";
    return c;
  }
  if (e.has_prior) {
    c.note = "not computed in a prior map";
    return c;
  }
  if (s.odometry.size() < 3) {
    c.note = "fewer than 3 keyframes";
    return c;
  }
  c.odometry = absoluteTrajectoryError(s.odometry, s.truth);

  PoseGraph corrected(graph_config);
  addOdometry(s, &corrected);
  c.loops = addReportedLoops(e, config, &corrected);
  corrected.optimize();
  c.corrected_poses = corrected.poses();
  c.corrected_factors = corrected.factors();
  c.corrected = absoluteTrajectoryError(c.corrected_poses, s.truth);

  // Plain Scan Context: the descriptor's best candidate under the threshold, yaw prior only.
  PoseGraph plain(graph_config);
  addOdometry(s, &plain);
  const std::vector<long> of_frame = keyframeOfFrame(s);
  for (const QueryOutcome& o : e.outcomes) {
    if (o.match < 0 || o.match_in_prior || !(o.distance < config.distance_threshold)) continue;
    const long q = of_frame[o.query], m = o.match < static_cast<int>(of_frame.size()) ? of_frame[o.match] : -1;
    if (q < 0 || m < 0) continue;
    Loop loop;
    loop.alignment.yaw = o.yaw;
    if (plain.addLoop(q, m, priorPose(o.yaw), loopCovariance(loop, config))) {
      ++c.plain_loops;
      c.plain_false_loops += !o.correct;
    }
  }
  plain.optimize();
  c.plain = absoluteTrajectoryError(plain.poses(), s.truth);

  // One false loop, claimed as sure as a verified one: from the keyframe three quarters of the way to
  // the first earlier keyframe 40-100 m away from it.
  PoseGraph with_false(graph_config);
  addOdometry(s, &with_false);
  addReportedLoops(e, config, &with_false);
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
    if (with_false.addLoop(q, static_cast<std::size_t>(m), Eigen::Isometry3d::Identity(), floor.asDiagonal())) {
      c.false_loop_gap = (s.truth[m].translation() - s.truth[q].translation()).norm();
    }
  }
  with_false.optimize();
  c.with_false_loop = absoluteTrajectoryError(with_false.poses(), s.truth);
  c.computed = true;
  return c;
}

}  // namespace eval
}  // namespace scan_context_loop
