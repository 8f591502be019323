// Feeding one sequence's keyframes through a KeyframePipeline and scoring each query against the truth:
// what evaluate() does for a sequence (with its prior map first) and the team evaluation for each robot,
// keyframe by keyframe in the world's clock order, with the pipeline the team session holds.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/eval/evaluation.h"

namespace scan_context_loop {
namespace eval {

struct DatabasePrior;  // prior_map.h

/// A relative pose is a correct constraint within 1 m and 2 deg of the truth (verified loops, loops into
/// a prior map, loops between robots are all scored so).
constexpr double kConstraintMetres = 1.0, kConstraintDegrees = 2.0;
/// Its translation error [m] and rotation error [rad] against the true relative pose.
void constraintError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth, double* translation,
                     double* rotation);
bool correctConstraint(double translation_error, double rotation_error);

/// Yaw of a pose's x axis [rad].
double yawOf(const Eigen::Isometry3d& t);

/// Feeds keyframes through `pipeline` (not owned) and scores the query sequence's into `evaluation`. A
/// prior map (when given) comes first, as session 0: a prior sequence's keyframes fed through the
/// pipeline, or a saved database's joining it; it is not scored.
class SequenceScorer {
 public:
  SequenceScorer(KeyframePipeline* pipeline, double revisit_radius, Evaluation* evaluation)
      : pipeline_(*pipeline), radius_(revisit_radius), e_(*evaluation) {}

  /// The prior's keyframes, then a new session.
  void buildPriorMap(const Sequence& prior);
  /// The database's keyframes, as saved (the next keyframe begins a new session).
  bool loadPriorMap(DatabasePrior* prior, std::string* error);

  /// Every keyframe of `s` in order: begin(s), then step(s, k) for each.
  void score(const Sequence& s);
  /// Before the first step of `s` (which must outlive the scorer).
  void begin(const Sequence& s);
  /// Reads, processes and scores keyframe k of `s`; `described` (when given) receives the points of a
  /// keyframe that entered the database as they were described (KeyframePipeline::process).
  Detection step(const Sequence& s, std::size_t k, pcl::PointCloud<pcl::PointXYZ>* described = nullptr);

  std::size_t priorKeyframes() const { return prior_count_; }
  const KeyframePipeline& pipeline() const { return pipeline_; }

 private:
  struct Keyframe {
    const Sequence* sequence;
    std::size_t k;
    const Eigen::Isometry3d& truth() const { return sequence->truth[k]; }
    int frame() const { return sequence->frames[k]; }
  };

  /// Reads and processes keyframe k; a cloud that cannot be read, or that the detector refuses, counts
  /// as rejected (Detection::accepted false).
  Detection feed(const Sequence& s, std::size_t k, pcl::PointCloud<pcl::PointXYZ>* described);
  void priorMapBuilt();
  bool inPrior(std::size_t index) const { return index < prior_count_; }
  PriorOutcome priorOutcome(const Sequence& s, std::size_t k) const;
  void scoreLoops(const Sequence& s, std::size_t k, const Detection& d);

  KeyframePipeline& pipeline_;
  double radius_;
  bool has_prior_ = false;
  Evaluation& e_;
  std::vector<Eigen::Vector3d> positions_;           // true positions of the accepted keyframes
  std::vector<Keyframe> keyframes_;                  // detector index -> sequence and keyframe
  std::vector<float> scan_buffer_;                   // the scan being fed, its memory kept from scan to scan
  std::size_t prior_count_ = 0;                      // keyframes of the prior map
  std::vector<long> outcome_of_, prior_outcome_of_;  // detector index -> outcome, -1 for none
  std::vector<double> metres_;                       // true distance along the query sequence to each keyframe
};

/// After the last step: the metrics of the outcomes (Evaluation::metrics, verified, relocalization).
void finishEvaluation(const Config& config, Evaluation* evaluation);

}  // namespace eval
}  // namespace scan_context_loop
