// Scoring a team offline with the node's code (scan_context_evaluate --team): every robot's keyframes in
// the world's clock order through its own KeyframePipeline, scored as a single run (SequenceScorer), and
// through the team exchange (TeamSession): the loops between robots against the truth in the world frame,
// and the bytes the exchange takes.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/team_sequence.h"

namespace scan_context_loop {
namespace eval {

/// A verified loop between two robots, scored against the truth.
struct InterRobotLoop {
  std::size_t query_robot = 0, match_robot = 0;                ///< indices in TeamSequence::robots
  std::size_t query = 0, match = 0;                            ///< keyframes of their sequences (Sequence index)
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  ///< registered T_query<-match
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
  double gap = 0.0;                ///< true distance between the two keyframes [m]
  double translation_error = 0.0;  ///< of the registered pose against the truth [m]
  double rotation_error = 0.0;     ///< [rad]
  bool correct = false;            ///< within 1 m and 2 deg of the truth
  double clock = 0.0;              ///< the world's clock when it was found (the query keyframe's)
};

struct TeamRobotEvaluation {
  /// Its own keyframes and loops, as a single run (keyframe_of maps its keyframe numbers to its sequence).
  Evaluation evaluation;
  std::size_t keyframes = 0;                   ///< stored, so shared
  std::size_t record_bytes = 0;                ///< its records, sent once each
  std::size_t received_bytes = 0;              ///< the other robots' records it received
  std::size_t fetched = 0, fetched_bytes = 0;  ///< registration data it fetched
  std::size_t fetch_failures = 0, records_refused = 0;
  /// Its keyframes matched against the others' records (with at least one held), those within the
  /// revisit radius of one of those records (true revisits between robots), its loops into them.
  std::size_t queries = 0, revisits = 0, true_positives = 0, false_positives = 0, revisits_found = 0;
};

struct TeamEvaluation {
  std::vector<TeamRobotEvaluation> robots;  ///< in TeamSequence::robots' order
  std::vector<InterRobotLoop> loops;        ///< every loop between robots, in the order found
  double revisit_radius = 5.0;
  /// Over the team. precision = TP / (TP + FP) (1 without loops); recall = revisits with a correct loop /
  /// revisits.
  std::size_t queries = 0, revisits = 0, true_positives = 0, false_positives = 0, revisits_found = 0;
  double precision = 1.0, recall = 0.0;
  /// Loops that join two keyframes already joined by an earlier loop (either way round): 0 when every
  /// pair is looked at once.
  std::size_t repeated_pairs = 0;
  double translation_error_median = 0.0, translation_error_p90 = 0.0;  ///< over the correct loops [m]
  double rotation_error_median = 0.0, rotation_error_p90 = 0.0;        ///< [deg]
  /// The exchange: records (one per stored keyframe, sent once; each other robot receives it) and
  /// registration data fetched; per keyframe = over every stored keyframe of the team.
  std::size_t keyframes = 0, records = 0, record_bytes = 0, fetched = 0, fetched_bytes = 0;
  double record_bytes_mean = 0.0, fetched_bytes_mean = 0.0;
  double sent_bytes_per_keyframe = 0.0;  ///< (record bytes + fetched bytes) / keyframes
  std::size_t record_bytes_max = 0;
};

/// Runs the team (TeamSession) over `team`'s keyframes in the world's clock order (start_seconds +
/// times; ties in team.txt's order) and scores it with the revisit radius.
TeamEvaluation evaluateTeam(const TeamSequence& team, const Config& config, double revisit_radius);

/// inter_robot_loops.csv: one row per loop between robots.
bool writeInterRobotLoopsCsv(const std::string& path, const TeamSequence& team, const TeamEvaluation& evaluation,
                             std::string* error);
/// The summary lines scan_context_evaluate --team prints about the loops between robots and the exchange.
std::vector<std::string> teamSummary(const TeamSequence& team, const TeamEvaluation& evaluation);

}  // namespace eval
}  // namespace scan_context_loop
