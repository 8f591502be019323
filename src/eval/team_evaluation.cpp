#include "scan_context_loop/eval/team_evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>
#include <tuple>

#include "scan_context_loop/eval/metrics.h"
#include "scan_context_loop/eval/sequence_scorer.h"
#include "scan_context_loop/eval/team_session.h"

namespace scan_context_loop {
namespace eval {

namespace {

/// A stored keyframe of the team: its robot, its sequence index and true position in the world.
struct Stored {
  std::size_t robot, k;
  Eigen::Vector3d position;
};

/// The team's keyframes in the world's clock order: (robot, sequence index).
std::vector<std::pair<std::size_t, std::size_t>> clockOrder(const TeamSequence& team) {
  std::vector<std::tuple<double, std::size_t, std::size_t>> all;
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    for (std::size_t k = 0; k < team.robots[r].sequence.frames.size(); ++k) {
      all.emplace_back(team.robots[r].clock(k), r, k);
    }
  }
  std::stable_sort(all.begin(), all.end());
  std::vector<std::pair<std::size_t, std::size_t>> order;
  for (const auto& [clock, r, k] : all) order.emplace_back(r, k);
  return order;
}

/// Scores the team's loops and counts its exchange, keyframe by keyframe.
class TeamScorer {
 public:
  TeamScorer(const TeamSequence& team, TeamEvaluation* e) : team_(team), e_(*e) {}

  /// Robot r's keyframe k was stored (its keyframe number `index`) and went through the exchange.
  void score(std::size_t r, std::size_t k, std::size_t index, const TeamStep& step) {
    const TeamRobot& robot = team_.robots[r];
    TeamRobotEvaluation& mine = e_.robots[r];
    ++mine.keyframes;
    mine.record_bytes += step.record_bytes;
    mine.fetched += step.fetched;
    mine.fetched_bytes += step.fetched_bytes;
    mine.fetch_failures += step.fetch_failures;
    e_.record_bytes_max = std::max(e_.record_bytes_max, step.record_bytes);
    for (std::size_t other = 0; other < e_.robots.size(); ++other) {
      if (other != r) e_.robots[other].received_bytes += step.record_bytes;
    }
    e_.robots[r].records_refused += step.records_refused;
    const Eigen::Vector3d here = robot.worldPose(k).translation();
    bool revisit = false;
    if (step.held > 0) {
      ++mine.queries;
      // The others' keyframes stored so far: the records this robot held when it matched this one.
      for (const Stored& s : stored_) revisit |= s.robot != r && (s.position - here).norm() < e_.revisit_radius;
      mine.revisits += revisit;
    }
    ownKeyframe(r, index, k);
    for (const TeamLoop& loop : step.loops) scoreLoop(loop, revisit);
    stored_.push_back({r, k, here});
  }

  /// Robot r's keyframe number `index` is its sequence's keyframe k.
  void ownKeyframe(std::size_t r, std::size_t index, std::size_t k) {
    std::vector<long>& of = sequence_of_[r];
    if (of.size() <= index) of.resize(index + 1, -1);
    of[index] = static_cast<long>(k);
  }

 private:
  /// `revisit`: whether the keyframe that released the loop had another robot's keyframe within the
  /// revisit radius (a loop confirmed later counts for the keyframe that confirmed it).
  void scoreLoop(const TeamLoop& found, bool revisit) {
    const std::size_t r = found.query_robot;
    const std::vector<long>& of = sequence_of_[found.match_robot];
    const std::vector<long>& mine_of = sequence_of_[r];
    if (found.match >= of.size() || of[found.match] < 0) return;  // cannot be: every stored keyframe is known
    if (found.query >= mine_of.size() || mine_of[found.query] < 0) return;
    const std::size_t k = static_cast<std::size_t>(mine_of[found.query]);
    InterRobotLoop loop;
    loop.query_robot = r;
    loop.query = k;
    loop.match_robot = found.match_robot;
    loop.match = static_cast<std::size_t>(of[found.match]);
    loop.relative = found.relative;
    loop.covariance = found.covariance;
    loop.clock = team_.robots[r].clock(k);
    const Eigen::Isometry3d truth =
        team_.robots[r].worldPose(k).inverse() * team_.robots[loop.match_robot].worldPose(loop.match);
    loop.gap = truth.translation().norm();
    constraintError(loop.relative, truth, &loop.translation_error, &loop.rotation_error);
    loop.correct = correctConstraint(loop.translation_error, loop.rotation_error);
    TeamRobotEvaluation& mine = e_.robots[r];
    ++(loop.correct ? mine.true_positives : mine.false_positives);
    mine.revisits_found += revisit && loop.correct;
    const auto a = std::make_pair(r, k), b = std::make_pair(loop.match_robot, loop.match);
    if (!pairs_.insert(std::minmax(a, b)).second) ++e_.repeated_pairs;
    e_.loops.push_back(loop);
  }

  const TeamSequence& team_;
  TeamEvaluation& e_;
  std::vector<Stored> stored_;
  std::vector<std::vector<long>> sequence_of_ = std::vector<std::vector<long>>(team_.robots.size());
  std::set<std::pair<std::pair<std::size_t, std::size_t>, std::pair<std::size_t, std::size_t>>> pairs_;
};

/// The team's sums over its robots, and the loops' error statistics.
void summarize(TeamEvaluation* e) {
  std::vector<double> translation, rotation;
  for (const InterRobotLoop& loop : e->loops) {
    if (!loop.correct) continue;
    translation.push_back(loop.translation_error);
    rotation.push_back(loop.rotation_error * 180.0 / M_PI);
  }
  e->translation_error_median = percentile(translation, 0.5);
  e->translation_error_p90 = percentile(translation, 0.9);
  e->rotation_error_median = percentile(rotation, 0.5);
  e->rotation_error_p90 = percentile(rotation, 0.9);
  for (const TeamRobotEvaluation& r : e->robots) {
    e->queries += r.queries;
    e->revisits += r.revisits;
    e->true_positives += r.true_positives;
    e->false_positives += r.false_positives;
    e->revisits_found += r.revisits_found;
    e->keyframes += r.keyframes;
    e->record_bytes += r.record_bytes;
    e->fetched += r.fetched;
    e->fetched_bytes += r.fetched_bytes;
  }
  e->records = e->keyframes;
  const std::size_t loops = e->true_positives + e->false_positives;
  e->precision = loops > 0 ? double(e->true_positives) / loops : 1.0;
  e->recall = e->revisits > 0 ? double(e->revisits_found) / e->revisits : 0.0;
  e->record_bytes_mean = e->records > 0 ? double(e->record_bytes) / e->records : 0.0;
  e->fetched_bytes_mean = e->fetched > 0 ? double(e->fetched_bytes) / e->fetched : 0.0;
  e->sent_bytes_per_keyframe = e->keyframes > 0 ? double(e->record_bytes + e->fetched_bytes) / e->keyframes : 0.0;
}

}  // namespace

TeamEvaluation evaluateTeam(const TeamSequence& team, const Config& config, double revisit_radius) {
  TeamEvaluation e;
  e.revisit_radius = revisit_radius;
  e.robots.resize(team.robots.size());
  std::vector<std::string> ids;
  for (const TeamRobot& robot : team.robots) ids.push_back(robot.id);
  TeamSession session(config, ids);
  std::vector<std::unique_ptr<SequenceScorer>> scorers;
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    scorers.push_back(std::make_unique<SequenceScorer>(&session.pipeline(r), revisit_radius, &e.robots[r].evaluation));
    scorers.back()->begin(team.robots[r].sequence);
  }
  TeamScorer scorer(team, &e);
  for (const auto& [r, k] : clockOrder(team)) {
    pcl::PointCloud<pcl::PointXYZ> described;
    const Detection d = scorers[r]->step(team.robots[r].sequence, k, &described);
    if (!d.accepted) continue;
    const TeamStep step = session.share(r, d, described);
    scorer.score(r, k, d.index, step);
  }
  for (TeamRobotEvaluation& r : e.robots) finishEvaluation(config, &r.evaluation);
  summarize(&e);
  return e;
}

bool writeInterRobotLoopsCsv(const std::string& path, const TeamSequence& team, const TeamEvaluation& e,
                             std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot create " + path;
    return false;
  }
  out << "clock_s,query_robot,query_frame,match_robot,match_frame,gap_m,correct,trans_err_m,rot_err_deg,x,y,z,yaw_"
         "deg\n";
  out.precision(6);
  for (const InterRobotLoop& l : e.loops) {
    const Eigen::Vector3d t = l.relative.translation();
    out << l.clock << ',' << team.robots[l.query_robot].id << ',' << team.robots[l.query_robot].sequence.frames[l.query]
        << ',' << team.robots[l.match_robot].id << ',' << team.robots[l.match_robot].sequence.frames[l.match] << ','
        << l.gap << ',' << int(l.correct) << ',' << l.translation_error << ',' << l.rotation_error * 180.0 / M_PI << ','
        << t.x() << ',' << t.y() << ',' << t.z() << ',' << yawOf(l.relative) * 180.0 / M_PI << '\n';
  }
  return out.good();
}

std::vector<std::string> teamSummary(const TeamSequence& team, const TeamEvaluation& e) {
  std::vector<std::string> lines;
  char line[512];
  std::snprintf(line, sizeof line,
                "loops between robots: %zu (%zu true, %zu false; precision %.3f), recall %.3f: %zu of %zu keyframes "
                "within %.1f m of another robot's earlier keyframe; %zu pairs reported twice",
                e.loops.size(), e.true_positives, e.false_positives, e.precision, e.recall, e.revisits_found,
                e.revisits, e.revisit_radius, e.repeated_pairs);
  lines.push_back(line);
  std::snprintf(
      line, sizeof line,
      "pose error of the true ones: translation %.3f m median / %.3f p90, rotation %.2f deg median / %.2f p90",
      e.translation_error_median, e.translation_error_p90, e.rotation_error_median, e.rotation_error_p90);
  lines.push_back(line);
  for (std::size_t r = 0; r < team.robots.size(); ++r) {
    const TeamRobotEvaluation& x = e.robots[r];
    std::snprintf(line, sizeof line,
                  "  %s: %zu keyframes shared (%zu bytes), %zu received (%zu bytes); %zu loops into the others' "
                  "(%zu true), %zu of %zu revisits; %zu registration data fetched (%zu bytes)",
                  team.robots[r].id.c_str(), x.keyframes, x.record_bytes, e.keyframes - x.keyframes, x.received_bytes,
                  x.true_positives + x.false_positives, x.true_positives, x.revisits_found, x.revisits, x.fetched,
                  x.fetched_bytes);
    lines.push_back(line);
  }
  std::snprintf(line, sizeof line,
                "exchange: %zu records, %.0f bytes per keyframe shared (max %zu; %.1f kB sent, each to %zu robots); "
                "%zu registration data fetched, %.0f bytes each (%.1f kB); %.0f bytes sent per keyframe in all",
                e.records, e.record_bytes_mean, e.record_bytes_max, e.record_bytes / 1e3,
                team.robots.empty() ? 0 : team.robots.size() - 1, e.fetched, e.fetched_bytes_mean,
                e.fetched_bytes / 1e3, e.sent_bytes_per_keyframe);
  lines.push_back(line);
  return lines;
}

}  // namespace eval
}  // namespace scan_context_loop
