#include "scan_context_sim/odometry_failures.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace scan_context_loop {
namespace sim {

std::string checkFailures(const OdometryFailures& f) {
  if (!std::isfinite(f.heading_ramp_deg)) return "the heading ramp must be finite";
  if (!(f.ramp_start >= 0.0 && f.ramp_start < 1.0)) return "the heading ramp's start must be in [0, 1)";
  if (f.heading_jumps < 0) return "the number of heading jumps must be >= 0";
  if (!std::isfinite(f.heading_jump_deg)) return "the heading jump must be finite";
  if (!(f.slip_length >= 0.0) || !(f.slip_start >= 0.0)) return "the slip's start and length must be >= 0";
  if (!(f.slip_scale >= 0.0) || !std::isfinite(f.slip_scale)) return "the slip scale must be >= 0";
  if (!std::isfinite(f.restart_at)) return "the restart distance must be finite";
  return "";
}

std::vector<Eigen::Isometry3d> withFailures(const std::vector<Eigen::Isometry3d>& odometry, const OdometryFailures& f) {
  if (odometry.size() < 2 || !f.any()) return odometry;
  std::vector<double> along(odometry.size(), 0.0);
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    along[k] = along[k - 1] + (odometry[k - 1].inverse() * odometry[k]).translation().norm();
  }
  const double total = along.back();
  const double ramp_from = f.ramp_start * total;
  const double ramp_rate = total > ramp_from ? f.heading_ramp_deg * M_PI / 180.0 / (total - ramp_from) : 0.0;
  std::mt19937 rng(f.seed ^ 0xFA11u);
  std::vector<double> jump(odometry.size(), 0.0);
  std::uniform_int_distribution<std::size_t> where(1, odometry.size() - 1);
  for (int n = 0; n < f.heading_jumps; ++n) {
    jump[where(rng)] += (rng() % 2 ? 1.0 : -1.0) * f.heading_jump_deg * M_PI / 180.0;
  }
  std::vector<Eigen::Isometry3d> out = {odometry.front()};
  bool restarted = false;
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    Eigen::Isometry3d delta = odometry[k - 1].inverse() * odometry[k];
    const double metres = along[k] - along[k - 1];
    // The part of this step inside the ramp and inside the slip.
    const double in_ramp = std::max(0.0, along[k] - std::max(along[k - 1], ramp_from));
    const double slip_end = f.slip_start + f.slip_length;
    const double in_slip =
        f.slip_length > 0.0 ? std::max(0.0, std::min(along[k], slip_end) - std::max(along[k - 1], f.slip_start)) : 0.0;
    if (metres > 0.0 && in_slip > 0.0) {
      delta.translation() *= 1.0 - (1.0 - f.slip_scale) * in_slip / metres;
    }
    const double yaw = ramp_rate * in_ramp + jump[k];
    delta = delta * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
    if (!restarted && f.restart_at >= 0.0 && along[k] >= f.restart_at) {
      restarted = true;
      out.push_back(Eigen::Isometry3d::Identity());
      continue;
    }
    out.push_back(out.back() * delta);
  }
  return out;
}

}  // namespace sim
}  // namespace scan_context_loop
