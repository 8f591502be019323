#include "scan_context_loop/verification.h"

#include <chrono>
#include <cstring>
#include <limits>
#include <cmath>
#include <sstream>

#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

namespace scan_context_loop {

std::vector<std::string> VerificationConfig::validate() const {
  std::vector<std::string> e;
  const auto positive = [&](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0.0)) e.push_back(std::string(name) + " must be a positive number");
  };
  positive(voxel_leaf, "verify_voxel_leaf");
  positive(max_range, "verify_max_range");
  positive(coarse_correspondence, "verify_coarse_correspondence");
  positive(fine_correspondence, "verify_fine_correspondence");
  positive(inlier_distance, "verify_inlier_distance");
  positive(max_fitness, "verify_max_fitness");
  positive(ndt_resolution, "verify_ndt_resolution");
  positive(min_translation_variance, "verify_min_translation_variance");
  positive(min_rotation_variance, "verify_min_rotation_variance");
  if (min_points < 3) e.push_back("verify_min_points must be >= 3");
  if (max_iterations < 1) e.push_back("verify_max_iterations must be >= 1");
  if (!(min_inlier_ratio >= 0.0 && min_inlier_ratio <= 1.0)) e.push_back("verify_min_inlier_ratio must be in [0, 1]");
  return e;
}

VerificationCloud prepareCloud(const PointView& points, const VerificationConfig& config) {
  VerificationCloud kept;
  kept.reserve(points.count);
  const double max2 = config.max_range * config.max_range;
  for (std::size_t i = 0; i < points.count && points.data != nullptr; ++i) {
    const std::uint8_t* p = points.data + i * points.stride;
    float x, y, z;
    std::memcpy(&x, p + points.offset_x, 4);
    std::memcpy(&y, p + points.offset_y, 4);
    std::memcpy(&z, p + points.offset_z, 4);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
    if (static_cast<double>(x) * x + static_cast<double>(y) * y > max2) continue;
    kept.push_back(pcl::PointXYZ(x, y, z));
  }
  VerificationCloud out;
  if (kept.empty()) return out;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  const float leaf = static_cast<float>(config.voxel_leaf);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.setInputCloud(kept.makeShared());
  grid.filter(out);
  return out;
}

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// Inlier statistics and the covariance at the solution, from nearest-neighbour correspondences of
/// the query points in the aligned candidate cloud.
void judge(const VerificationCloud& query, const VerificationCloud& aligned, const VerificationConfig& config,
           VerificationResult* r) {
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(aligned.makeShared());
  std::vector<int> index(1);
  std::vector<float> d2(1);
  const double limit2 = config.inlier_distance * config.inlier_distance;
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  double sum2 = 0.0;
  std::size_t inliers = 0;
  for (const auto& q : query) {
    if (tree.nearestKSearch(q, 1, index, d2) < 1 || d2[0] > limit2) continue;
    ++inliers;
    sum2 += d2[0];
    // Residual e = p' - q with p' = exp(xi) * p: de/dxi = [I, -[p']x] for xi = (t, theta).
    const Eigen::Vector3d p = aligned[index[0]].getVector3fMap().cast<double>();
    Eigen::Matrix<double, 3, 6> j;
    j.leftCols<3>() = Eigen::Matrix3d::Identity();
    j.rightCols<3>() = -skew(p);
    hessian += j.transpose() * j;
  }
  r->inlier_ratio = query.empty() ? 0.0 : static_cast<double>(inliers) / query.size();
  r->fitness = inliers > 0 ? sum2 / inliers : std::numeric_limits<double>::infinity();
  if (inliers > 6) {
    const double sigma2 = sum2 / std::max<double>(1.0, 3.0 * inliers - 6.0);
    // Guard against a degenerate geometry (a straight corridor): floor the Hessian's eigenvalues.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(hessian);
    Eigen::Matrix<double, 6, 1> values = eig.eigenvalues().cwiseMax(1e-6);
    r->covariance = sigma2 * eig.eigenvectors() * values.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  }
  for (int i = 0; i < 6; ++i) {
    const double floor = i < 3 ? config.min_translation_variance : config.min_rotation_variance;
    r->covariance(i, i) = std::max(r->covariance(i, i), floor);
  }
}

}  // namespace

VerificationResult verify(const VerificationCloud& query, const VerificationCloud& match,
                          const Eigen::Isometry3d& initial, const VerificationConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  VerificationResult r;
  r.query_points = query.size();
  r.match_points = match.size();
  r.relative = initial;
  const auto finish = [&](const std::string& reason) {
    r.reason = reason;
    r.accepted = reason.empty();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };
  if (query.size() < static_cast<std::size_t>(config.min_points) ||
      match.size() < static_cast<std::size_t>(config.min_points)) {
    std::ostringstream why;
    why << "too few points to verify (query " << query.size() << ", candidate " << match.size() << ", need "
        << config.min_points << ")";
    return finish(why.str());
  }
  if (!initial.matrix().allFinite()) return finish("initial guess is not finite");

  // Coarse, then fine: the first stage pulls in a translation the prior lacks (a wide correspondence
  // distance, or NDT's coarser cells), the second settles on the local surfaces.
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>* registration = &gicp;
  if (config.method == RegistrationMethod::kIcp) registration = &icp;
  if (config.method == RegistrationMethod::kNdt) {
    ndt.setStepSize(0.5);
    registration = &ndt;
  }
  registration->setInputSource(match.makeShared());
  registration->setInputTarget(query.makeShared());
  registration->setMaximumIterations(config.max_iterations);
  registration->setTransformationEpsilon(1e-6);
  VerificationCloud aligned;
  Eigen::Matrix4f guess = initial.matrix().cast<float>();
  for (int stage = 0; stage < 2; ++stage) {
    if (config.method == RegistrationMethod::kNdt) {
      ndt.setResolution(static_cast<float>(stage == 0 ? 2.0 * config.ndt_resolution : config.ndt_resolution));
    } else {
      registration->setMaxCorrespondenceDistance(stage == 0 ? config.coarse_correspondence
                                                            : config.fine_correspondence);
    }
    registration->align(aligned, guess);
    if (!registration->hasConverged()) return finish("registration did not converge");
    guess = registration->getFinalTransformation();
  }
  r.relative.matrix() = guess.cast<double>();
  if (!r.relative.matrix().allFinite()) return finish("registration diverged");
  judge(query, aligned, config, &r);
  std::ostringstream why;
  if (r.inlier_ratio < config.min_inlier_ratio) {
    why << "inlier ratio " << r.inlier_ratio << " below " << config.min_inlier_ratio;
  } else if (!(r.fitness <= config.max_fitness)) {
    why << "fitness " << r.fitness << " m^2 above " << config.max_fitness;
  }
  return finish(why.str());
}

VerificationConfig verificationConfig(const Config& c) {
  VerificationConfig v;
  v.voxel_leaf = c.verify_voxel_leaf;
  v.max_range = c.verify_max_range;
  v.min_inlier_ratio = c.verify_min_inlier_ratio;
  v.max_fitness = c.verify_max_fitness;
  v.method = c.verify_method;
  return v;
}

void CloudStore::add(std::size_t index, VerificationCloud cloud) {
  if (index % stride_ != 0) return;  // between the kept keyframes at the current density
  const std::size_t size = bytesOf(cloud);
  while (bytes_ + size > max_bytes_ && stride_ < (std::size_t(1) << 30)) {
    // Halve the density everywhere: keep only multiples of the doubled stride.
    stride_ *= 2;
    for (std::size_t i = 0; i < clouds_.size(); ++i) {
      if (clouds_[i] && i % stride_ != 0) {
        bytes_ -= bytesOf(*clouds_[i]);
        clouds_[i].reset();
        ++dropped_;
      }
    }
    if (index % stride_ != 0) return;
  }
  if (clouds_.size() <= index) clouds_.resize(index + 1);
  bytes_ += size;
  clouds_[index].reset(new VerificationCloud(std::move(cloud)));
}

const VerificationCloud* CloudStore::get(std::size_t index) const {
  return index < clouds_.size() ? clouds_[index].get() : nullptr;
}

std::size_t CloudStore::stored() const {
  std::size_t n = 0;
  for (const auto& c : clouds_) n += c != nullptr;
  return n;
}

Eigen::Isometry3d priorPose(double yaw, const Eigen::Vector2d& viewpoint) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() << viewpoint.x(), viewpoint.y(), 0.0;
  return pose;
}

VerificationResult verifyWithYaw(const VerificationCloud& query, const VerificationCloud& match, double yaw,
                                 const VerificationConfig& config, const Eigen::Vector2d& viewpoint) {
  return verify(query, match, priorPose(yaw, viewpoint), config);
}

}  // namespace scan_context_loop
