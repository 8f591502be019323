#include "evaluate_team.h"

#include <cstdio>

#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/team_evaluation.h"
#include "scan_context_loop/eval/team_map.h"
#include "scan_context_loop/eval/team_sequence.h"
#include "cli.h"

namespace scan_context_loop {
namespace tools {

namespace {

int fail(const std::string& error) {
  std::fprintf(stderr, "scan_context_evaluate: %s\n", error.c_str());
  return 1;
}

}  // namespace

int evaluateTeam(const std::string& team_dir, const std::string& out_dir, const Config& config,
                 const eval::SequenceOptions& options, double radius) {
  std::string error;
  eval::TeamSequence team;
  if (!eval::loadTeam(team_dir, options, &team, &error)) return fail(error);
  const eval::TeamEvaluation result = eval::evaluateTeam(team, config, radius);
  const eval::TeamMap map = eval::mergeTeamMap(team, result, config);
  if (!cli::makeDirectories(out_dir, &error) ||
      !eval::writeTeamJson(out_dir + "/team.json", team, result, map, &error) ||
      !eval::writeInterRobotLoopsCsv(out_dir + "/inter_robot_loops.csv", team, result, &error)) {
    return fail(error);
  }
  std::printf("team %s: %zu robots, %s anchors the map\n", team_dir.c_str(), team.robots.size(),
              team.robots.front().id.c_str());
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const eval::TeamRobot& robot = team.robots[r];
    const eval::Evaluation& own = result.robots[r].evaluation;
    const std::string dir = out_dir + "/" + robot.id;
    if (!cli::makeDirectories(dir, &error) || !eval::writeResultsCsv(dir + "/results.csv", own, &error) ||
        !eval::writeMetricsJson(dir + "/metrics.json", own, robot.sequence, config, radius, &error) ||
        !eval::writeTrajectoryCsv(dir + "/trajectory.csv", robot.sequence, &error) ||
        (own.verification && !eval::writeVerificationsCsv(dir + "/verifications.csv", own, &error))) {
      return fail(error);
    }
    for (std::size_t i = 0; i < own.errors.size() && i < 5; ++i) {
      std::fprintf(stderr, "scan_context_evaluate: %s: skipped %s\n", robot.id.c_str(), own.errors[i].c_str());
    }
    // Its own loops, as a single run scores them.
    std::printf("%s: %zu keyframes from %.1f s, %zu queries, %zu true revisits of its own", robot.id.c_str(),
                robot.sequence.frames.size(), robot.start_seconds, own.metrics.queries, own.metrics.revisits);
    if (own.verification) {
      std::printf("; verified loops: precision %.3f, recall %.3f (%zu TP, %zu FP)\n", own.verified.precision,
                  own.verified.recall, own.verified.true_positives, own.verified.false_positives);
    } else {
      std::printf("; at threshold %.3f: precision %.3f, recall %.3f (%zu TP, %zu FP)\n", own.metrics.threshold,
                  own.metrics.precision, own.metrics.recall, own.metrics.true_positives, own.metrics.false_positives);
    }
  }
  for (const std::string& line : eval::teamSummary(team, result)) std::printf("%s\n", line.c_str());
  for (const std::string& line : eval::teamMapSummary(team, map)) std::printf("%s\n", line.c_str());
  // scripts/evaluate plots each robot's results with its sequence.
  for (const eval::TeamRobot& robot : team.robots) {
    std::printf("robot output: %s/%s %s\n", out_dir.c_str(), robot.id.c_str(), robot.sequence.dir.c_str());
  }
  std::printf("output: %s\n", out_dir.c_str());
  return 0;
}

}  // namespace tools
}  // namespace scan_context_loop
