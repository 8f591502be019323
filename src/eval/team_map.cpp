// The team's map with the reference pose-graph backend (graph/pose_graph.h, Ceres); a build without the
// backend uses team_map_unavailable.cpp.
#include "scan_context_loop/eval/team_map.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {
namespace eval {

namespace {

/// What the graph takes, in the world's clock order: a keyframe, or a loop between two earlier ones.
struct Event {
  double clock;
  bool loop;             // else a keyframe
  std::size_t robot, k;  // the keyframe; the loop's query
  std::size_t match_robot = 0, match = 0;
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity();
  bool own = false;  // a loop within one robot
};

/// Every keyframe of the team, each robot's own loops (the verified ones with verification) and the
/// loops between robots, each loop at the clock of the later of its keyframes (it cannot be known before),
/// after the keyframes of that moment.
std::vector<Event> events(const TeamSequence& team, const TeamEvaluation& e, const Config& config) {
  std::vector<Event> out;
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const TeamRobot& robot = team.robots[r];
    for (std::size_t k = 0; k < robot.sequence.frames.size(); ++k) out.push_back({robot.clock(k), false, r, k});
    const Evaluation& own = e.robots[r].evaluation;
    for (const Loop& loop : own.loops) {
      if (own.verification && !loop.verified) continue;
      const long q = loop.query < own.keyframe_of.size() ? own.keyframe_of[loop.query] : -1;
      const long m = loop.match < own.keyframe_of.size() ? own.keyframe_of[loop.match] : -1;
      if (q < 0 || m < 0) continue;
      Event x{std::max(robot.clock(q), robot.clock(m)), true, r, static_cast<std::size_t>(q)};
      x.match_robot = r;
      x.match = static_cast<std::size_t>(m);
      x.relative = loop.relative();
      x.covariance = loopCovariance(loop, config);
      x.own = true;
      out.push_back(x);
    }
  }
  for (const InterRobotLoop& loop : e.loops) {
    Event x{loop.clock, true, loop.query_robot, loop.query};
    x.match_robot = loop.match_robot;
    x.match = loop.match;
    x.relative = loop.relative;
    x.covariance = loop.covariance;
    out.push_back(x);
  }
  std::stable_sort(out.begin(), out.end(), [](const Event& a, const Event& b) {
    return std::tie(a.clock, a.loop) < std::tie(b.clock, b.loop);
  });
  return out;
}

}  // namespace

TeamMap mergeTeamMap(const TeamSequence& team, const TeamEvaluation& e, const Config& config) {
  TeamMap map;
  if (team.robots.empty() || e.robots.size() != team.robots.size()) {
    map.note = "no robot";
    return map;
  }
  map.robots.resize(team.robots.size());
  // As the pose_graph node takes them: keyframes and loops as they come, a solve after each loop, so
  // each loop meets the estimate the earlier ones left (not the raw drift a robust loss would discount).
  PoseGraph graph;
  std::vector<std::vector<std::size_t>> node(team.robots.size());
  for (const Event& x : events(team, e, config)) {
    if (!x.loop) {
      const long added = graph.addKeyframe(team.robots[x.robot].sequence.odometry[x.k], x.robot);
      if (added < 0) {
        map.note = team.robots[x.robot].id + ": a keyframe pose is not finite or its rotation is not one";
        return map;
      }
      node[x.robot].push_back(static_cast<std::size_t>(added));
      continue;
    }
    if (x.k >= node[x.robot].size() || x.match >= node[x.match_robot].size() ||
        !graph.addLoop(node[x.robot][x.k], node[x.match_robot][x.match], x.relative, x.covariance)) {
      ++map.loops_rejected;
      continue;
    }
    ++(x.own ? map.robots[x.robot].own_loops : map.robots[x.robot].team_loops);
    graph.optimize();
  }
  if (graph.size() < 3) {
    map.note = "fewer than 3 keyframes";
    return map;
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
      corrected.push_back(graph.pose(node[r][k]));
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
