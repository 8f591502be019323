// One map of a team: every robot's odometry as a chain of the reference pose graph (graph/pose_graph.h;
// the first robot's chain anchors it), its own loops and the loops between robots; each robot's frame
// in the anchor's frame and its merged corrected trajectory scored against the truth, next to its
// odometry alone placed by its true start.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/eval/team_evaluation.h"
#include "scan_context_loop/eval/team_sequence.h"
#include "scan_context_loop/eval/trajectory_error.h"

namespace scan_context_loop {
namespace eval {

struct TeamMapRobot {
  /// Its chain was joined to the anchor's by loops between robots: the frame and the corrected
  /// trajectory are estimates in the anchor's frame (the anchor itself: always).
  bool joined = false;
  /// T_anchor_start<-robot_start, estimated (PoseGraph::frame) and true
  /// (T_world<-anchor_start^-1 x T_world<-robot_start), and how far apart they are.
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity(), true_frame = Eigen::Isometry3d::Identity();
  double frame_translation_error = 0.0;  ///< [m]
  double frame_rotation_error = 0.0;     ///< [deg]
  /// In the anchor's frame, no alignment: the odometry alone placed by the true start pose, and the
  /// merged corrected trajectory (computed when joined).
  TrajectoryError odometry, corrected;
  std::size_t own_loops = 0, team_loops = 0;  ///< loop factors its keyframes are the query of
};

struct TeamMap {
  bool computed = false;
  std::string note;  ///< why nothing was computed (fewer than 3 keyframes, no backend in this build)
  std::vector<TeamMapRobot> robots;
  /// Every joined robot's keyframes together, in the anchor's frame: odometry alone and corrected.
  TrajectoryError odometry, corrected;
  std::size_t loops_rejected = 0;  ///< loops the graph did not take (addLoop false)
};

/// Builds the graph (one chain per robot, its odometry; its verified own loops, or every loop without
/// verification; the loops between robots, in the order found), solves it and scores it. computed =
/// false, the reason in `note`, in a build without the backend.
TeamMap mergeTeamMap(const TeamSequence& team, const TeamEvaluation& evaluation, const Config& config);

/// The lines scan_context_evaluate --team prints about the frames and the merged map.
std::vector<std::string> teamMapSummary(const TeamSequence& team, const TeamMap& map);

/// team.json: the loops between robots, the exchange, and per robot its keyframes, own loops, bytes,
/// frame and trajectory errors.
bool writeTeamJson(const std::string& path, const TeamSequence& team, const TeamEvaluation& evaluation,
                   const TeamMap& map, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
