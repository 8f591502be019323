#include "scan_context_loop/core/verification.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "scan_context_loop/core/pcl_refinement.h"

namespace scan_context_loop {

VoxelOptions voxelOptions(const VerificationConfig& config) {
  VoxelOptions o;
  o.resolution = static_cast<float>(config.voxel_leaf);
  o.max_range = static_cast<float>(config.max_range);
  return o;
}

VoxelCloud prepareCloud(const PointView& points, const VerificationConfig& config,
                        const Eigen::Matrix3f& gravity_alignment) {
  return makeVoxelCloud(points, voxelOptions(config), gravity_alignment);
}

namespace {

using Clock = std::chrono::steady_clock;

std::size_t structureCount(const VoxelCloud& c) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < c.size(); ++i) n += c.vertical(i);
  return n;
}

/// Angle between the rotation's z axis and the vertical [deg].
double tiltDegrees(const Eigen::Isometry3d& pose) {
  return std::acos(std::min(1.0, std::max(-1.0, pose.linear()(2, 2)))) * 180.0 / M_PI;
}

bool close(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double metres, double radians) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().norm() < metres && Eigen::AngleAxisd(d.linear()).angle() < radians;
}

/// How many of `from`'s structure voxels inside `to`'s crop (after moving them by T_to<-from) have a
/// voxel of `to` near them on the same plane. With `information`, also accumulates the point-to-plane
/// information of the agreeing pairs in `to`'s frame, (rx, ry, rz, tx, ty, tz), and their squared
/// residuals.
struct Agreement {
  std::size_t covered = 0, agreeing = 0;
  double residual2 = 0.0;
};

/// One keyframe's voxels moved into another's frame (T_to<-from), and what of them the other covers.
struct MovedInto {
  MovedInto(const VoxelIndex& to, const Eigen::Isometry3d& to_from, const VerificationConfig& config)
      : R(to_from.linear().cast<float>()),
        t(to_from.translation().cast<float>()),
        plane(static_cast<float>(config.inlier_plane_distance)) {
    const float reach = to.cloud()->max_range - static_cast<float>(config.inlier_distance);
    reach2 = reach * reach;
  }
  Eigen::Vector3f operator()(const Eigen::Vector3f& p) const { return R * p + t; }
  bool covered(const Eigen::Vector3f& moved) const { return moved.head<2>().squaredNorm() <= reach2; }

  Eigen::Matrix3f R;
  Eigen::Vector3f t;
  float plane, reach2 = 0.0f;
};

Agreement agreement(const VoxelCloud& from, const VoxelIndex& to, const Eigen::Isometry3d& to_from,
                    const VerificationConfig& config, bool structure_only, int stride,
                    Eigen::Matrix<double, 6, 6>* information) {
  Agreement a;
  const VoxelCloud& target = *to.cloud();
  const MovedInto move(to, to_from, config);
  const float plane = move.plane;
  for (std::size_t i = 0; i < from.size(); i += stride) {
    if (structure_only ? !from.vertical(i) : !from.ground(i)) continue;
    const Eigen::Vector3f p = move(from.means[i]);
    if (!move.covered(p)) continue;
    ++a.covered;
    const int j = to.nearest(p, static_cast<float>(config.inlier_distance));
    if (j < 0 || !target.registrable(j)) continue;
    const Eigen::Vector3f n = target.normal(j);
    const float d = n.dot(p - target.means[j]);
    if (std::fabs(d) > plane) continue;
    ++a.agreeing;
    a.residual2 += static_cast<double>(d) * d;
    if (information != nullptr) {
      Eigen::Matrix<double, 1, 6> row;
      row.head<3>() = (p.cast<double>().cross(n.cast<double>())).transpose();
      row.tail<3>() = n.cast<double>().transpose();
      *information += row.transpose() * row;
    }
  }
  return a;
}

/// Fractions like agreement()'s, but a structure voxel agrees with any voxel of `to` on its vertical
/// plane within a column around it (VoxelIndex::onPlane). Over at most kColumnSamples of the covered
/// voxels, evenly spread; once the share can no longer reach `floor`, it stops and returns the most it
/// could still have been (below `floor`).
constexpr std::size_t kColumnSamples = 400;

double columnAgreement(const VoxelCloud& from, const VoxelIndex& to, const Eigen::Isometry3d& to_from,
                       const VerificationConfig& config, double floor) {
  const MovedInto move(to, to_from, config);
  const float plane = move.plane;
  const float along = static_cast<float>(config.inlier_distance);
  std::vector<std::pair<std::uint32_t, Eigen::Vector3f>> covered;
  covered.reserve(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (!from.vertical(i)) continue;
    const Eigen::Vector3f p = move(from.means[i]);
    if (move.covered(p)) covered.emplace_back(static_cast<std::uint32_t>(i), p);
  }
  if (covered.empty()) return 0.0;
  const std::size_t stride = (covered.size() + kColumnSamples - 1) / kColumnSamples;
  const std::size_t samples = (covered.size() + stride - 1) / stride;
  const auto allowed_misses = static_cast<std::size_t>((1.0 - floor) * static_cast<double>(samples));
  std::size_t misses = 0;
  for (std::size_t k = 0; k < covered.size(); k += stride) {
    const std::size_t i = covered[k].first;
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    if (from.shape(i) == VoxelCloud::kPlanar) {
      n = move.R * from.normal(i);
      n.z() = 0.0f;
      n.normalize();
    }
    if (to.onPlane(covered[k].second, n, n.isZero() ? 2.0f * plane : plane, along, 2.0f)) continue;
    if (++misses > allowed_misses) break;
  }
  return static_cast<double>(samples - std::min(misses, samples)) / static_cast<double>(samples);
}

}  // namespace

void Verifier::setQuery(const VoxelCloud& query) {
  query_ = &query;
  query_index_.build(query);
  query_map_ = structureMap(query, static_cast<float>(config_.search_cell));
  query_free_ = freeSpace(query);
  query_structure_ = structureCount(query);
}

VerificationResult Verifier::verify(const VoxelCloud& match, const std::vector<Eigen::Isometry3d>& hypotheses) {
  const auto start = Clock::now();
  const auto timed = [&](VerificationResult result) {
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  };
  const auto finish = [&](VerificationResult result, const Verdict& verdict) {
    result.record(verdict);
    return timed(std::move(result));
  };
  VerificationResult r;
  if (query_ == nullptr) return finish(r, registrationFailure("no query set"));
  r.query_points = query_structure_;
  r.match_points = structureCount(match);
  if (const Verdict structure = judgeStructure(r.query_points, r.match_points, config_); !structure.accepted()) {
    return finish(r, structure);
  }
  std::vector<Eigen::Isometry3d> guesses;
  for (const auto& h : hypotheses) {
    if (h.matrix().allFinite()) guesses.push_back(h);
  }
  if (guesses.empty()) return finish(r, registrationFailure("initial guess is not finite"));
  r.relative = guesses.front();

  const std::vector<CoarseHit> hits = coarseSearch(query_map_, structureColumns(match, query_map_.cell), guesses,
                                                   config_.search_radius, 3.0 * M_PI / 180.0);
  match_index_.build(match);
  match_free_ = freeSpace(match);

  // Of the rejected hypotheses the one with the largest overlap is reported ("no hypothesis" until one
  // was registered).
  VerificationResult best_rejected = r;
  best_rejected.record(registrationFailure("no hypothesis"));
  bool registered_any = false;
  // A hypothesis that passes only with support is kept while the others may still pass in full.
  VerificationResult best_supportable;
  std::vector<Eigen::Isometry3d> tried;
  for (const CoarseHit& hit : hits) {
    if (static_cast<int>(tried.size()) >= config_.max_hypotheses) break;
    if (!tried.empty() && hit.score < config_.hypothesis_ratio * hits.front().score) break;
    if (std::any_of(tried.begin(), tried.end(),
                    [&](const Eigen::Isometry3d& t) { return close(t, hit.pose, 1.5, 0.05); }))
      continue;
    tried.push_back(hit.pose);
    VerificationResult candidate = r;
    candidate.coarse_score = hit.score;
    candidate.hypotheses = static_cast<int>(tried.size());
    const Verdict verdict = refineAndJudge(match, hit.pose, &candidate);
    if (verdict.accepted()) return finish(candidate, verdict);
    candidate.record(verdict);
    if (candidate.needs_support) {
      if (!best_supportable.needs_support || candidate.inlier_ratio > best_supportable.inlier_ratio) {
        best_supportable = candidate;
      }
      continue;
    }
    if (!registered_any || candidate.inlier_ratio > best_rejected.inlier_ratio) {
      best_rejected = candidate;
      registered_any = true;
    }
  }
  VerificationResult& best = best_supportable.needs_support ? best_supportable : best_rejected;
  best.hypotheses = static_cast<int>(tried.size());
  return timed(std::move(best));
}

Verdict Verifier::refineAndJudge(const VoxelCloud& match, const Eigen::Isometry3d& initial, VerificationResult* r) {
  Eigen::Isometry3d pose = initial;
  if (const std::string failure = refine(match, &pose, r); !failure.empty()) return registrationFailure(failure);
  r->relative = pose;
  estimateCovariance(measure(match, r), r);
  return judgeRegistration(*r, config_);
}

std::string Verifier::refine(const VoxelCloud& match, Eigen::Isometry3d* pose, VerificationResult* r) {
  // One voxel GICP stage from `pose` at a correspondence distance; false when it found too few pairs. A
  // rough stage stops at ten times the step the last stage stops at: the fine stage starts from it and
  // moves the pose by more than that anyway (a quarter of the coarse stage's iterations, the same
  // verified loops on city3-changed_hdl64, their poses within 1.1 cm).
  const auto stage = [&](double distance, int iterations, bool fix_tilt, bool rough) {
    GicpOptions options;
    options.max_iterations = iterations;
    if (rough) {
      options.translation_epsilon *= 10.0;
      options.rotation_epsilon *= 10.0;
    }
    options.max_source_voxels = config_.max_source_voxels;
    options.max_correspondence = static_cast<float>(distance);
    options.fix_tilt = fix_tilt;
    const GicpResult g = alignVoxels(match, query_index_, *pose, options);
    if (g.correspondences < 6) return false;
    *pose = g.transform;
    return true;
  };
  if (config_.method == RegistrationMethod::kVgicp) {
    for (double distance : {config_.coarse_correspondence, config_.fine_correspondence}) {
      const bool rough = distance != config_.fine_correspondence;
      if (!stage(distance, config_.max_iterations, false, rough)) return "registration found no correspondences";
    }
  } else if (!refineWithPcl(*query_, match, config_, pose)) {
    return "registration did not converge";
  }
  if (!pose->matrix().allFinite()) return "registration diverged";
  r->tilt_deg = tiltDegrees(*pose);
  if (!trustsRegisteredTilt(r->tilt_deg, config_)) {
    // Roll and pitch from the gravity alignment: drop the registered tilt, then yaw and translation again.
    pose->linear() = Eigen::AngleAxisd(std::atan2(pose->linear()(1, 0), pose->linear()(0, 0)), Eigen::Vector3d::UnitZ())
                         .toRotationMatrix();
    // From the full registration's yaw and translation, which the tilt hardly moves: a few iterations.
    if (!stage(config_.fine_correspondence, std::min(config_.max_iterations, 5), true, false)) {
      return "registration found no correspondences";
    }
    if (!pose->matrix().allFinite()) return "registration diverged";
    r->tilt_from_alignment = true;
  }
  return "";
}

Eigen::Matrix<double, 6, 6> Verifier::measure(const VoxelCloud& match, VerificationResult* r) {
  const Eigen::Isometry3d pose = r->relative;
  // Agreement both ways, over the region both sensors cover: a changed world moves cars and trees, not
  // facades, so the structure that is still there must be where the pose puts it, from either side.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  const Agreement forward = agreement(match, query_index_, pose, config_, true, 1, &information);
  const Agreement backward = agreement(*query_, match_index_, pose.inverse(), config_, true, 1, nullptr);
  agreement(match, query_index_, pose, config_, false, 2, &information);  // ground: z, roll, pitch
  r->overlap_match = forward.covered > 0 ? static_cast<double>(forward.agreeing) / forward.covered : 0.0;
  r->overlap_query = backward.covered > 0 ? static_cast<double>(backward.agreeing) / backward.covered : 0.0;
  r->inlier_ratio = std::min(r->overlap_match, r->overlap_query);
  // The column overlap only where it can decide, and the second direction only when the first reaches
  // the support floor.
  if (columnOverlapCanDecide(r->inlier_ratio, config_)) {
    const double floor = columnOverlapFloor(config_);
    r->column_overlap = r->column_overlap_match = columnAgreement(match, query_index_, pose, config_, floor);
    if (r->column_overlap_match >= floor) {
      r->column_overlap_query = columnAgreement(*query_, match_index_, pose.inverse(), config_, floor);
      r->column_overlap = std::min(r->column_overlap_match, r->column_overlap_query);
    }
  }
  r->violation_match = checkFreeSpace(match, query_free_, pose).ratio();
  r->violation_query = checkFreeSpace(*query_, match_free_, pose.inverse()).ratio();
  r->violation = std::max(r->violation_match, r->violation_query);
  r->fitness = forward.agreeing > 0 ? forward.residual2 / forward.agreeing : std::numeric_limits<double>::infinity();
  return information;
}

void Verifier::estimateCovariance(const Eigen::Matrix<double, 6, 6>& information, VerificationResult* r) const {
  // Covariance in the query frame from the point-to-plane information, reordered to (x, y, z, roll,
  // pitch, yaw), scaled by the residual variance (never below 5 cm squared: voxel means are not points).
  const double sigma2 = std::max(r->fitness, 0.0025);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(information);
  const Eigen::Matrix<double, 6, 1> values = eig.eigenvalues().cwiseMax(1e-9);
  const Eigen::Matrix<double, 6, 6> cov_rt =
      sigma2 * eig.eigenvectors() * values.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  Eigen::Matrix<int, 6, 1> order;
  order << 3, 4, 5, 0, 1, 2;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) r->covariance(i, j) = cov_rt(order[i], order[j]);
  }
  for (int i = 0; i < 6; ++i) {
    const double floor = i < 3 ? config_.min_translation_variance : config_.min_rotation_variance;
    r->covariance(i, i) = std::max(r->covariance(i, i), floor);
  }
  if (r->tilt_from_alignment) {
    // Roll and pitch were not estimated here: they are as good as the two gravity alignments, which the
    // registration disagreed with by more than registration_max_tilt_deg; nothing couples them to the rest.
    const double tilt_variance = std::pow(std::max(config_.registration_max_tilt_deg, 0.5) * M_PI / 180.0, 2);
    for (int i = 3; i < 5; ++i) {
      for (int j = 0; j < 6; ++j) r->covariance(i, j) = r->covariance(j, i) = 0.0;
      r->covariance(i, i) = std::max(tilt_variance, config_.min_rotation_variance);
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> horizontal(r->covariance.topLeftCorner<2, 2>());
  r->constraint_ratio = horizontal.eigenvalues()(0) / std::max(horizontal.eigenvalues()(1), 1e-12);
}

void VerificationResult::record(const Verdict& verdict) {
  accepted = verdict.accepted();
  reason = verdict.reason;
  rejected_by = rejectionTestName(verdict.test);
  rejection_value = verdict.value;
  rejection_limit = verdict.limit;
  needs_support = verdict.needs_support;
  odometry_contradicted = verdict.odometry_contradicted;
}

VerificationResult verify(const VoxelCloud& query, const VoxelCloud& match, const Eigen::Isometry3d& initial,
                          const VerificationConfig& config) {
  Verifier verifier(config);
  verifier.setQuery(query);
  return verifier.verify(match, {initial});
}

}  // namespace scan_context_loop
