#include "scan_context_loop/core/odometry_trust.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/database.h"

namespace scan_context_loop {

void OdometryTrust::add(const Keyframe& query, const Keyframe& match, const Eigen::Isometry3d& relative,
                        const Config& config) {
  if (!query.info.pose || !match.info.pose || query.session != match.session) return;
  Anchor a;
  a.query_pose = *query.info.pose;
  a.match_pose = *match.info.pose;
  a.relative = relative;
  a.query_path = query.path_length;
  a.match_path = match.path_length;
  a.query_session = query.session;
  a.match_session = match.session;
  anchors_.push_back(a);
  // How wrong the direct odometry between the two keyframes was.
  const double path = std::fabs(query.path_length - match.path_length);
  if (!(path >= kMinMeasuredPath)) return;
  const Eigen::Isometry3d direct = a.query_pose.inverse() * a.match_pose;
  const double beyond = (direct.translation() - relative.translation()).norm() - config.gate_odometry_distance;
  if (std::isfinite(beyond)) translation_rate_ = std::max(translation_rate_, beyond / path);
}

OdometryPrediction OdometryTrust::predict(const Eigen::Isometry3d& pose, double path, std::uint32_t session,
                                          const Keyframe& candidate) const {
  OdometryPrediction best;
  best.relative = pose.inverse() * *candidate.info.pose;
  best.path = std::fabs(path - candidate.path_length);
  const Anchor* via = nullptr;
  for (const Anchor& a : anchors_) {
    if (a.query_session != session || a.match_session != candidate.session) continue;
    const double length = std::fabs(path - a.query_path) + std::fabs(a.match_path - candidate.path_length);
    if (length < best.path) {
      best.path = length;
      via = &a;
    }
  }
  if (via != nullptr) {
    best.relative = pose.inverse() * via->query_pose * via->relative * via->match_pose.inverse() * *candidate.info.pose;
    best.anchored = true;
  }
  return best;
}

double rotationAllowance(const VerificationConfig& config, double path) {
  return config.odometry_rotation + config.odometry_rotation_drift * path;
}

namespace {
double translationRate(const Config& config, const OdometryTrust& trust) {
  return std::max(config.gate_odometry_drift, OdometryTrust::kMeasuredDriftMargin * trust.translationRate());
}
}  // namespace

double gateRadius(const Config& config, const OdometryTrust& trust, double path) {
  return config.gate_odometry_distance + translationRate(config, trust) * path;
}

double anchoredTranslationAllowance(const Config& config, const OdometryTrust& trust, double path) {
  return config.consistency_translation + translationRate(config, trust) * path;
}

}  // namespace scan_context_loop
