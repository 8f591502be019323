// The team's map with the reference pose-graph backend (graph/pose_graph.h, Ceres); a build without the
// backend uses team_map_unavailable.cpp.
#include "scan_context_loop/eval/team_map.h"

#include <cmath>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {
namespace eval {

TeamMap mergeTeamMap(const TeamSequence& team, const TeamEvaluation& e, const Config& config) {
  TeamMap map;
  map.robots.resize(team.robots.size());
  PoseGraph graph;
  // Node of robot r's keyframe k: first[r] + k.
  std::vector<std::size_t> first;
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    first.push_back(graph.size());
    for (const Eigen::Isometry3d& pose : team.robots[r].sequence.odometry) {
      if (graph.addKeyframe(pose, r) < 0) {
        map.note = team.robots[r].id + ": a keyframe pose is not finite or its rotation is not one";
        return map;
      }
    }
  }
  if (graph.size() < 3) {
    map.note = "fewer than 3 keyframes";
    return map;
  }
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const Evaluation& own = e.robots[r].evaluation;
    for (const Loop& loop : own.loops) {
      if (own.verification && !loop.verified) continue;
      const long q = loop.query < own.keyframe_of.size() ? own.keyframe_of[loop.query] : -1;
      const long m = loop.match < own.keyframe_of.size() ? own.keyframe_of[loop.match] : -1;
      if (q < 0 || m < 0) continue;
      if (graph.addLoop(first[r] + q, first[r] + m, loop.relative(), loopCovariance(loop, config))) {
        ++map.robots[r].own_loops;
      } else {
        ++map.loops_rejected;
      }
    }
  }
  for (const InterRobotLoop& loop : e.loops) {
    if (graph.addLoop(first[loop.query_robot] + loop.query, first[loop.match_robot] + loop.match, loop.relative,
                      loop.covariance)) {
      ++map.robots[loop.query_robot].team_loops;
    } else {
      ++map.loops_rejected;
    }
  }
  graph.optimize();

  const Eigen::Isometry3d anchor_inverse = team.robots.front().world_from_start.inverse();
  std::vector<Eigen::Isometry3d> all_odometry, all_corrected, all_truth;
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const TeamRobot& robot = team.robots[r];
    TeamMapRobot& out = map.robots[r];
    out.joined = graph.joined(r);
    out.frame = graph.frame(r);
    out.true_frame = anchor_inverse * robot.world_from_start;
    out.frame_translation_error = (out.frame.translation() - out.true_frame.translation()).norm();
    out.frame_rotation_error =
        Eigen::AngleAxisd(out.true_frame.linear().transpose() * out.frame.linear()).angle() * 180.0 / M_PI;
    std::vector<Eigen::Isometry3d> odometry, corrected, truth;
    for (std::size_t k = 0; k < robot.sequence.frames.size(); ++k) {
      truth.push_back(out.true_frame * robot.sequence.truth[k]);
      odometry.push_back(out.true_frame * robot.sequence.odometry[k]);
      corrected.push_back(graph.pose(first[r] + k));
    }
    out.odometry = positionError(odometry, truth);
    if (!out.joined) continue;
    out.corrected = positionError(corrected, truth);
    all_odometry.insert(all_odometry.end(), odometry.begin(), odometry.end());
    all_corrected.insert(all_corrected.end(), corrected.begin(), corrected.end());
    all_truth.insert(all_truth.end(), truth.begin(), truth.end());
  }
  map.odometry = positionError(all_odometry, all_truth);
  map.corrected = positionError(all_corrected, all_truth);
  map.computed = true;
  return map;
}

}  // namespace eval
}  // namespace scan_context_loop
