#include "scan_context_loop/graph/pose_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include <Eigen/Cholesky>

#include "ceres_compat.h"
#include "relative_pose_error.h"
#include "scan_context_loop/graph/pose_graph_settings.h"

namespace scan_context_loop {

namespace {

bool isRotation(const Eigen::Matrix3d& r) {
  return r.allFinite() && (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-3 &&
         r.determinant() > 0.0;
}

/// S with S^T S = covariance^-1, or false if the covariance is not symmetric positive definite.
bool sqrtInformation(const Matrix6d& covariance, Matrix6d* out) {
  if (!covariance.allFinite() || !covariance.isApprox(covariance.transpose(), 1e-9)) return false;
  const Eigen::LLT<Matrix6d> llt(covariance);
  if (llt.info() != Eigen::Success) return false;
  const Matrix6d information = llt.solve(Matrix6d::Identity());
  const Eigen::LLT<Matrix6d> info_llt(0.5 * (information + information.transpose()));
  if (info_llt.info() != Eigen::Success) return false;
  *out = info_llt.matrixU();  // U^T U = information
  return out->allFinite();
}

}  // namespace

std::vector<std::string> PoseGraphConfig::validate() const { return checkSettings(poseGraphSettings(), *this); }

Matrix6d odometryCovariance(const Eigen::Isometry3d& step, const PoseGraphConfig& config) {
  const double length = step.translation().norm();
  const double t = config.odometry_translation_floor + config.odometry_translation_per_metre * length;
  const double turned = Eigen::AngleAxisd(step.linear()).angle();
  const double r = config.odometry_rotation_floor + config.odometry_rotation_per_metre * length +
                   config.odometry_rotation_per_radian * turned;
  Eigen::Matrix<double, 6, 1> diagonal;
  diagonal << t * t, t * t, t * t, r * r, r * r, r * r;
  return diagonal.asDiagonal();
}

struct PoseGraph::Impl {
  /// The group of the fixed keyframes (chains' groups are numbered by their lowest chain).
  static constexpr std::size_t kFixedGroup = static_cast<std::size_t>(-1);
  struct Chain {
    long first = -1;        ///< its first keyframe, -1: none yet
    long last = -1;         ///< its newest keyframe, which the chain's next keyframe is tied to
    std::size_t group = 0;  ///< the lowest chain of its group, or kFixedGroup
  };

  Impl() {
    ceres::Problem::Options options;
    ceres_compat::keepQuaternionOwnership(&options);
    options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(options);
  }
  // deques: blocks never move once Ceres holds their addresses.
  std::deque<Eigen::Vector3d> positions;
  std::deque<Eigen::Quaterniond> rotations;
  std::vector<ceres::ResidualBlockId> loop_blocks;
  std::vector<long> chain_of;  ///< per keyframe: its chain, -1 for a fixed one (addFixedKeyframe)
  std::vector<Chain> chains;   ///< by chain number
  /// By group (its lowest chain): the keyframe held as its gauge, -1 once the group joined the fixed
  /// keyframes (they hold it then).
  std::vector<long> gauge;
  ceres_compat::EigenQuaternion quaternion_parameterization;
  /// The loops' loss: switched between none (least squares) and the Cauchy loss by optimize().
  std::unique_ptr<ceres::LossFunctionWrapper> loop_loss =
      std::make_unique<ceres::LossFunctionWrapper>(nullptr, ceres::TAKE_OWNERSHIP);
  std::unique_ptr<ceres::Problem> problem;

  /// A keyframe's parameter blocks (position, rotation) starting at `estimate`.
  void addBlocks(const Eigen::Isometry3d& estimate, long chain) {
    positions.push_back(estimate.translation());
    rotations.push_back(Eigen::Quaterniond(estimate.linear()).normalized());
    problem->AddParameterBlock(positions.back().data(), 3);
    problem->AddParameterBlock(rotations.back().coeffs().data(), 4, &quaternion_parameterization);
    chain_of.push_back(chain);
  }
  void setHeld(std::size_t i, bool held) {
    if (held) {
      problem->SetParameterBlockConstant(positions[i].data());
      problem->SetParameterBlockConstant(rotations[i].coeffs().data());
    } else {
      problem->SetParameterBlockVariable(positions[i].data());
      problem->SetParameterBlockVariable(rotations[i].coeffs().data());
    }
  }
  std::size_t groupOf(std::size_t i) const {
    return chain_of[i] < 0 ? kFixedGroup : chains[static_cast<std::size_t>(chain_of[i])].group;
  }
  Eigen::Isometry3d pose(std::size_t i) const {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = rotations[i].normalized().toRotationMatrix();
    t.translation() = positions[i];
    return t;
  }
  /// Before the first loop between the groups of `query` and `match`: moves one group rigidly so that
  /// T_query<-match holds, frees its gauge and merges it into the other (see the header).
  void join(std::size_t query, std::size_t match, const Eigen::Isometry3d& query_from_match) {
    const std::size_t gq = groupOf(query), gm = groupOf(match);
    // kFixedGroup is the largest number: the fixed keyframes' group stays, else the lower chain's.
    const bool query_stays = gq == kFixedGroup || (gm != kFixedGroup && gq < gm);
    const std::size_t stays = query_stays ? gq : gm, moves = query_stays ? gm : gq;
    const std::size_t moved = query_stays ? match : query;
    const Eigen::Isometry3d target =
        query_stays ? pose(query) * query_from_match : pose(match) * query_from_match.inverse();
    const Eigen::Isometry3d move = target * pose(moved).inverse();
    for (std::size_t i = 0; i < positions.size(); ++i) {
      if (groupOf(i) != moves) continue;
      const Eigen::Isometry3d now = move * pose(i);
      positions[i] = now.translation();
      rotations[i] = Eigen::Quaterniond(now.linear()).normalized();
    }
    if (gauge[moves] >= 0) setHeld(static_cast<std::size_t>(gauge[moves]), false);
    gauge[moves] = -1;
    for (Chain& c : chains) {
      if (c.group == moves) c.group = stays;
    }
  }
};

PoseGraph::PoseGraph(const PoseGraphConfig& config) : config_(config), impl_(std::make_unique<Impl>()) {}

PoseGraph::~PoseGraph() = default;

namespace {

/// Whether `pose` can be a keyframe's: finite, within kMaxCoordinate, its rotation one.
bool usablePose(const Eigen::Isometry3d& pose) {
  return pose.translation().allFinite() && pose.translation().cwiseAbs().maxCoeff() <= PoseGraph::kMaxCoordinate &&
         isRotation(pose.linear());
}

}  // namespace

long PoseGraph::addKeyframe(const Eigen::Isometry3d& odometry_pose, std::size_t chain) {
  if (!usablePose(odometry_pose) || chain >= kMaxChains) return -1;
  Impl& g = *impl_;
  const Impl::Chain previous = chain < g.chains.size() ? g.chains[chain] : Impl::Chain();
  Eigen::Isometry3d estimate = odometry_pose, step = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity(), sqrt_information = Matrix6d::Identity();
  if (previous.last >= 0) {
    step = odometry_[previous.last].inverse() * odometry_pose;
    estimate = pose(previous.last) * step;
    covariance = odometryCovariance(step, config_);
    // Checked before anything is added: a factor must never carry an unset weight.
    if (!usablePose(estimate) || !sqrtInformation(covariance, &sqrt_information)) return -1;
  }
  while (g.chains.size() <= chain) {
    Impl::Chain c;
    c.group = g.chains.size();
    g.chains.push_back(c);
    g.gauge.push_back(-1);
  }
  Impl::Chain& c = g.chains[chain];
  const long index = static_cast<long>(odometry_.size());
  g.addBlocks(estimate, static_cast<long>(chain));
  if (c.last < 0) {
    g.setHeld(index, true);  // the gauge of its own group (no loop can have joined it yet)
    c.first = index;
    g.gauge[chain] = index;
  } else {
    const std::size_t a = static_cast<std::size_t>(c.last);
    g.problem->AddResidualBlock(new RelativePoseCost(step, sqrt_information), nullptr, g.positions[a].data(),
                                g.rotations[a].coeffs().data(), g.positions.back().data(),
                                g.rotations.back().coeffs().data());
    factors_.push_back({a, static_cast<std::size_t>(index), step, covariance, false});
  }
  c.last = index;
  odometry_.push_back(odometry_pose);
  return index;
}

long PoseGraph::addFixedKeyframe(const Eigen::Isometry3d& stored_pose) {
  if (!usablePose(stored_pose)) return -1;
  const long index = static_cast<long>(odometry_.size());
  impl_->addBlocks(stored_pose, -1);
  impl_->setHeld(index, true);
  odometry_.push_back(stored_pose);
  return index;
}

bool PoseGraph::fixed(std::size_t i) const { return i < impl_->chain_of.size() && impl_->chain_of[i] < 0; }

bool PoseGraph::addLoop(std::size_t query, std::size_t match, const Eigen::Isometry3d& query_from_match,
                        const Matrix6d& covariance, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (query >= size() || match >= size()) return fail("unknown keyframe");
  if (query == match) return fail("a loop from a keyframe to itself");
  if (!query_from_match.translation().allFinite() || !isRotation(query_from_match.linear())) {
    return fail("the relative pose is not finite or not a rotation");
  }
  if (fixed(query) && fixed(match)) return fail("a loop between two fixed keyframes");
  Matrix6d sqrt_information;
  if (!sqrtInformation(covariance, &sqrt_information)) {
    return fail("the covariance is not symmetric positive definite");
  }
  Impl& g = *impl_;
  if (g.groupOf(query) != g.groupOf(match)) g.join(query, match, query_from_match);
  const ceres::ResidualBlockId id = g.problem->AddResidualBlock(
      new RelativePoseCost(query_from_match, sqrt_information), g.loop_loss.get(), g.positions[query].data(),
      g.rotations[query].coeffs().data(), g.positions[match].data(), g.rotations[match].coeffs().data());
  g.loop_blocks.push_back(id);
  factors_.push_back({query, match, query_from_match, covariance, true});
  ++loop_count_;
  return true;
}

PoseGraphResult PoseGraph::optimize() {
  PoseGraphResult result;
  if (size() < 2 || factors_.empty()) {
    result.solved = true;
    result.message = "nothing to solve";
    return result;
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = config_.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  // Two passes. Least squares first: from drifted estimates every loop, true or not, starts many
  // standard deviations off, where a robust loss would give the true ones no pull either. Then the
  // Cauchy loss from there: a loop that the others and the odometry disagree with stays far off and
  // loses its weight; the true ones, now close, keep theirs.
  const auto start = std::chrono::steady_clock::now();
  ceres::Solver::Summary summary;
  impl_->loop_loss->Reset(nullptr, ceres::TAKE_OWNERSHIP);
  ceres::Solve(options, impl_->problem.get(), &summary);
  result.initial_cost = summary.initial_cost;
  result.iterations = static_cast<int>(summary.iterations.size());
  if (config_.loop_robust_scale > 0.0 && loop_count_ > 0 && summary.IsSolutionUsable()) {
    impl_->loop_loss->Reset(new ceres::CauchyLoss(config_.loop_robust_scale), ceres::TAKE_OWNERSHIP);
    ceres::Solve(options, impl_->problem.get(), &summary);
    result.iterations += static_cast<int>(summary.iterations.size());
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.solved = summary.IsSolutionUsable();
  result.final_cost = summary.final_cost;
  result.message = summary.BriefReport();
  for (std::size_t i = 0; i < size(); ++i) {
    if (!fixed(i)) impl_->rotations[i].normalize();  // fixed ones stay exactly as given
  }
  return result;
}

Eigen::Isometry3d PoseGraph::pose(std::size_t i) const { return impl_->pose(i); }

std::vector<Eigen::Isometry3d> PoseGraph::poses() const {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(size());
  for (std::size_t i = 0; i < size(); ++i) out.push_back(pose(i));
  return out;
}

Eigen::Isometry3d PoseGraph::correction(std::size_t chain) const {
  const long last = chain < impl_->chains.size() ? impl_->chains[chain].last : -1;
  if (last < 0) return Eigen::Isometry3d::Identity();
  return pose(last) * odometry_[last].inverse();
}

std::size_t PoseGraph::chains() const { return impl_->chains.size(); }

long PoseGraph::chainOf(std::size_t i) const { return i < impl_->chain_of.size() ? impl_->chain_of[i] : -1; }

std::vector<std::size_t> PoseGraph::chainKeyframes(std::size_t chain) const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < size(); ++i) {
    if (impl_->chain_of[i] == static_cast<long>(chain)) out.push_back(i);
  }
  return out;
}

Eigen::Isometry3d PoseGraph::frame(std::size_t chain) const {
  const long first = chain < impl_->chains.size() ? impl_->chains[chain].first : -1;
  if (first < 0) return Eigen::Isometry3d::Identity();
  return pose(first) * odometry_[first].inverse();
}

bool PoseGraph::joined(std::size_t chain) const {
  const auto& chains = impl_->chains;
  if (chain >= chains.size() || chains[chain].first < 0) return false;
  return chains[chain].group == chains[0].group;
}

std::vector<std::size_t> PoseGraph::held() const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < size(); ++i) {
    if (fixed(i)) out.push_back(i);
  }
  for (const long g : impl_->gauge) {
    if (g >= 0) out.push_back(static_cast<std::size_t>(g));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace scan_context_loop
