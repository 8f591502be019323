#include "scan_context_loop/core/world_tilt.h"

#include <algorithm>
#include <cmath>

namespace scan_context_loop {

namespace {
double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}
}  // namespace

void WorldTilt::add(const Eigen::Matrix3d& world_R_sensor, const Eigen::Vector3d& up) {
  const Eigen::Vector3d world_up = (world_R_sensor * up).normalized();
  if (!world_up.allFinite()) return;
  if (!axis_known_) {
    int axis = 0;
    world_up.cwiseAbs().maxCoeff(&axis);
    Eigen::Vector3d unit = Eigen::Vector3d::Zero();
    unit[axis] = world_up[axis] > 0.0 ? 1.0 : -1.0;
    if (angleDeg(world_up, unit) <= kAxisDeg) {
      axis_known_ = true;
      if (axis == 2 && unit.z() > 0.0) {
        axis_correction_.setIdentity();
      } else if (axis == 2) {
        axis_correction_ = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
      } else {
        // A quarter turn about the axis orthogonal to both.
        const Eigen::Vector3d about = unit.cross(Eigen::Vector3d::UnitZ()).normalized();
        axis_correction_ = Eigen::AngleAxisd(M_PI / 2, about).toRotationMatrix();
      }
    }
  }
  sum_ += world_up;
  if (recent_.size() < kRecent) {
    recent_.push_back(world_up);
  } else {
    recent_[count_ % kRecent] = world_up;
  }
  ++count_;
  if (count_ < kMinFits || sum_.norm() < 1e-9) return;
  const Eigen::Vector3d mean = sum_.normalized();
  std::vector<double> scatter;
  scatter.reserve(recent_.size());
  for (const Eigen::Vector3d& u : recent_) scatter.push_back(angleDeg(u, mean));
  std::nth_element(scatter.begin(), scatter.begin() + scatter.size() / 2, scatter.end());
  if (scatter[scatter.size() / 2] > kMaxScatterDeg) return;  // the fits do not agree on a direction (yet)
  established_ = true;
  tilt_deg_ = angleDeg(axis_correction_ * mean, Eigen::Vector3d::UnitZ());
  correction_ = tilt_deg_ < kAlignedDeg
                    ? Eigen::Matrix3d::Identity()
                    : Eigen::Quaterniond::FromTwoVectors(mean, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

void WorldTilt::reset() { *this = WorldTilt(); }

}  // namespace scan_context_loop
