#include "correction_graph.h"

#include "scan_context_loop/core/keyframes.h"

namespace scan_context_loop {
namespace eval {

Matrix6d floorCovariance(const Config& config) {
  const double t = config.verification.min_translation_variance, r = config.verification.min_rotation_variance;
  Eigen::Matrix<double, 6, 1> floor;
  floor << t, t, t, r, r, r;
  return floor.asDiagonal();
}

CorrectionGraph::CorrectionGraph(const Sequence& s, const Evaluation& e, const PoseGraphConfig& config)
    : graph(config), s_(s), e_(e), prior_count_(e.prior_keyframes.frames.size()) {
  for (const auto& pose : e.prior_keyframes.odometry) ok_ &= graph.addFixedKeyframe(pose) >= 0;
  for (const auto& pose : s.odometry) ok_ &= graph.addKeyframe(pose) >= 0;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    if (s.frames[k] < 0) continue;
    const std::size_t frame = static_cast<std::size_t>(s.frames[k]);
    if (frame >= keyframe_of_frame_.size()) keyframe_of_frame_.resize(frame + 1, -1);
    keyframe_of_frame_[frame] = static_cast<long>(k);
  }
}

long CorrectionGraph::nodeOfIndex(std::size_t index) const {
  if (index < prior_count_) return static_cast<long>(index);
  const long k = index < e_.keyframe_of.size() ? e_.keyframe_of[index] : -1;
  return k < 0 ? -1 : static_cast<long>(nodeOfKeyframe(static_cast<std::size_t>(k)));
}

long CorrectionGraph::nodeOfFrame(int frame) const {
  if (frame < 0 || static_cast<std::size_t>(frame) >= keyframe_of_frame_.size()) return -1;
  const long k = keyframe_of_frame_[static_cast<std::size_t>(frame)];
  return k < 0 ? -1 : static_cast<long>(nodeOfKeyframe(static_cast<std::size_t>(k)));
}

const Eigen::Isometry3d& CorrectionGraph::truth(std::size_t node) const {
  return inPrior(node) ? e_.prior_keyframes.truth[node] : s_.truth[node - prior_count_];
}

std::size_t CorrectionGraph::addReportedLoops(const Config& config, LoopPose pose, LoopCovariance covariance,
                                              double covariance_scale, std::size_t* prior_loops) {
  std::size_t added = 0;
  for (const Loop& loop : e_.loops) {
    if (e_.verification && !loop.verified) continue;
    const long q = nodeOfIndex(loop.query), m = nodeOfIndex(loop.match);
    if (q < 0 || m < 0) continue;
    const Eigen::Isometry3d relative = pose == LoopPose::kTrue ? truth(q).inverse() * truth(m) : loop.relative();
    const Matrix6d weight =
        covariance_scale * (covariance == LoopCovariance::kFloor ? floorCovariance(config) : loopCovariance(loop, config));
    if (!graph.addLoop(q, m, relative, weight)) continue;
    ++added;
    if (prior_loops != nullptr && (inPrior(q) || inPrior(m))) ++*prior_loops;
  }
  return added;
}

std::size_t CorrectionGraph::addOracleLoops(const Matrix6d& covariance) {
  std::size_t added = 0;
  for (const QueryOutcome& o : e_.outcomes) {
    if (o.revisit_index < 0) continue;
    const long q = nodeOfFrame(o.query), m = nodeOfIndex(static_cast<std::size_t>(o.revisit_index));
    if (q < 0 || m < 0) continue;
    added += graph.addLoop(q, m, truth(q).inverse() * truth(m), covariance);
  }
  return added;
}

double CorrectionGraph::addFalseLoop(const Matrix6d& covariance) {
  const std::size_t q = s_.truth.size() * 3 / 4;
  for (std::size_t k = 0; k < q; ++k) {
    const double gap = (s_.truth[k].translation() - s_.truth[q].translation()).norm();
    if (gap < 40.0 || gap > 100.0) continue;
    return graph.addLoop(nodeOfKeyframe(q), nodeOfKeyframe(k), Eigen::Isometry3d::Identity(), covariance) ? gap : -1.0;
  }
  return -1.0;
}

std::vector<Eigen::Isometry3d> CorrectionGraph::sequencePoses() const {
  std::vector<Eigen::Isometry3d> all = graph.poses();
  return std::vector<Eigen::Isometry3d>(all.begin() + static_cast<long>(prior_count_), all.end());
}

std::vector<PoseGraphFactor> CorrectionGraph::sequenceFactors() const {
  std::vector<PoseGraphFactor> factors;
  for (PoseGraphFactor f : graph.factors()) {
    if (inPrior(f.a) || inPrior(f.b)) continue;
    f.a -= prior_count_;
    f.b -= prior_count_;
    factors.push_back(f);
  }
  return factors;
}

}  // namespace eval
}  // namespace scan_context_loop
