// What the loops do to the map: the sequence's odometry keyframe poses and the evaluation's loops go
// into the reference pose graph (graph/pose_graph.h), and the corrected trajectory is scored against
// the truth (absolute trajectory error), next to the odometry's own. Every sequence gets one: without
// odometry of its own the truth is the odometry (what the loops' registration errors do to a perfect
// trajectory); in a prior map the prior's keyframes are held at their stored poses and the sequence's
// loops into them go in with its own.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/graph/pose_graph.h"
#include "scan_context_loop/eval/trajectory_error.h"

namespace scan_context_loop {
namespace eval {

struct TrajectoryCorrection {
  bool computed = false;
  /// Why nothing was computed, when so; when computed, what the numbers mean for this kind of sequence
  /// (the truth as the odometry, a prior map), empty for a sequence with its own odometry.
  std::string note;
  /// The sequence has odometry of its own (odom_poses.txt, fed to the detector); false: the truth is the
  /// odometry, whose error is then 0.
  bool own_odometry = true;
  TrajectoryError odometry;  ///< the odometry's keyframe poses as they are
  /// The loops the detector reported (verified ones when verification is on), each with the covariance
  /// the node publishes.
  TrajectoryError corrected;
  std::size_t loops = 0;
  std::size_t prior_loops = 0;  ///< of `loops`, those into the prior map's keyframes (the rest: the sequence's own)
  /// In a prior map: its keyframes, each held at the pose the pipeline stored; that stored trajectory's
  /// own error against the prior's truth; and how far the solver moved any of them (0: they stayed fixed).
  bool in_prior = false;
  std::string prior_source;
  std::size_t prior_keyframes = 0;
  TrajectoryError prior_odometry;
  double prior_moved = 0.0;  ///< [m]
  /// Plain Scan Context: every query whose best descriptor candidate is under the threshold, as a loop
  /// with the descriptor's yaw prior and the prior covariance (what the node publishes without verify).
  TrajectoryError plain;
  std::size_t plain_loops = 0, plain_false_loops = 0;
  /// The reported loops plus one false loop (two keyframes 40-100 m apart claimed to be at the same
  /// place, with a verified loop's covariance at its floors): what the robust loss holds off.
  TrajectoryError with_false_loop;
  double false_loop_gap = -1.0;  ///< the false loop's true length [m]; -1 when no pair was that far apart
  /// Where the corrected error lies, with its alignment: on the revisited keyframes (revisits and their
  /// nearest earlier keyframes, graph_study.h) and on the rest, which only the odometry holds.
  PartError corrected_revisited, corrected_rest;
  /// The reported loops' pairs and covariances at their true relative poses: what the loops' own
  /// registration error costs (corrected minus this).
  TrajectoryError reported_true;
  /// The oracle: every revisit (as the scoring defines it: an eligible keyframe within the revisit
  /// radius, the nearest) at its true relative pose, with a verified loop's covariance at its floors:
  /// what the graph makes of every loop there is to find, exact. Against reported_true: the pairs missed.
  TrajectoryError oracle;
  std::size_t oracle_loops = 0;
  std::vector<Eigen::Isometry3d> corrected_poses;  ///< per sequence keyframe, from the reported loops
  std::vector<PoseGraphFactor> corrected_factors;  ///< that graph's factors (odometry and loops)
};

/// Builds and solves the graphs: the sequence's odometry chain (the truth when it has no odometry
/// of its own) and, in a prior map, the prior's keyframes fixed at their stored poses, with the loops
/// (the plain ones, the false one, the true-pose and the oracle ones likewise). computed = false, the reason in `note`, with fewer than 3
/// keyframes or in a build without the backend.
TrajectoryCorrection correctTrajectory(const Sequence& sequence, const Evaluation& evaluation, const Config& config,
                                       const PoseGraphConfig& graph_config = PoseGraphConfig());

/// trajectory_error.json: the trajectory errors (RMSE, mean, max) and the loop counts, what the
/// odometry was, the prior map's part and the note; or computed false and the note.
bool writeTrajectoryErrorJson(const std::string& path, const TrajectoryCorrection& correction, std::string* error);
/// The summary line scan_context_evaluate prints: the odometry's and the corrected ATE (RMSE / max) and
/// which loops went in, or why there is none.
std::string trajectoryErrorLine(const TrajectoryCorrection& correction);
/// trajectory_corrected.csv: per keyframe, its frame and the odometry's and the corrected positions and headings
/// (yaw of the x axis, radians), each in the truth's frame by its own alignment.
bool writeCorrectedTrajectoryCsv(const std::string& path, const Sequence& sequence,
                                 const TrajectoryCorrection& correction, std::string* error);

/// --save-map: the corrected map as the pose_graph node's ~save_map writes it (graph/map_files.h), into
/// `directory`: the sequence's keyframe scans at the corrected poses through a KeyframeMap with the
/// node's map defaults, the corrected and the odometry trajectories (stamps from times.txt) and the
/// graph. False with the reason (nothing computed, a scan unreadable, a file not written); `summary`
/// gets the files, sizes, points and voxel.
bool saveCorrectedMap(const std::string& directory, const Sequence& sequence, const TrajectoryCorrection& correction,
                      std::string* summary, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
