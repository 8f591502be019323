// Why the corrected trajectory stays where it is: the evaluator's pose graph solved again with other
// loops (the reported ones at their true poses, the oracle's), other loop weights and other graph
// settings, each scored several ways (after the best rigid motion, after the best similarity, without
// any alignment, on the revisited keyframes and on the rest). `scan_context_evaluate --graph-study FILE`
// reads the variants from FILE and writes OUT_DIR/graph_study.csv (doc/pose_graph.md#what-limits-the-corrected-trajectory).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/trajectory_error.h"
#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {
namespace eval {

/// One graph to solve. A line of the study file: a name, then KEY=VALUE words:
///   loops=reported|reported_true|oracle|none  which loops (none: the odometry alone)
///   covariance=reported|floor                 a reported loop's covariance (the oracle's is the floor)
///   covariance_scale=X                        every loop's covariance times X (> 0)
///   false_loop=0|1                            add the one false loop the trajectory correction adds
///   any key of the pose graph's table (poseGraphSettings: odometry noise, robust loss, iterations).
/// Keys left out keep the defaults the evaluator corrects with.
struct GraphVariant {
  enum class Loops { kReported, kReportedTrue, kOracle, kNone };
  std::string name;
  std::string text;  ///< the KEY=VALUE words as given
  Loops loops = Loops::kReported;
  bool floor_covariance = false;
  double covariance_scale = 1.0;
  bool false_loop = false;
  PoseGraphConfig graph;
};

/// Parses one line ("" or a # comment: false without an error). False with `error` on an unknown key or
/// a value out of range.
bool parseGraphVariant(const std::string& line, GraphVariant* variant, std::string* error);
/// Every variant of the file (one a line, # comments).
bool readGraphVariants(const std::string& path, std::vector<GraphVariant>* variants, std::string* error);

/// Per sequence keyframe: it is a revisit (a query with an eligible keyframe within the revisit
/// radius) or the nearest such keyframe of one: the part of the drive the loops can reach.
std::vector<bool> revisitedKeyframes(const Sequence& sequence, const Evaluation& evaluation);

struct GraphStudyRow {
  std::string name, text;
  std::size_t loops = 0;
  bool solved = false;
  int iterations = 0;
  double seconds = 0.0;
  TrajectoryError aligned;   ///< after the best rigid motion (what trajectory_error.json reports)
  TrajectoryError anchored;  ///< without alignment (the graph's frame is the odometry's first pose)
  double similarity_rmse = 0.0, similarity_scale = 1.0;  ///< after the best similarity (rigid + scale)
  PartError revisited, rest;  ///< aligned as `aligned`, on the revisited keyframes and on the others
};

/// Solves each variant's graph over the sequence's odometry (and a prior map's fixed keyframes) and
/// scores it; the odometry's own row ("odometry", loops=none) comes first.
std::vector<GraphStudyRow> runGraphStudy(const Sequence& sequence, const Evaluation& evaluation, const Config& config,
                                         const std::vector<GraphVariant>& variants);
bool writeGraphStudyCsv(const std::string& path, const std::vector<GraphStudyRow>& rows, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
