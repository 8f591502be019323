#include "scan_context_sim/platform_tilt.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {

std::vector<Eigen::Vector2d> platformTilt(const std::vector<PathPoint>& path, const TiltOptions& options) {
  std::vector<Eigen::Vector2d> tilt(path.size(), Eigen::Vector2d::Zero());
  if (!(options.typical_deg > 0.0) || path.empty()) return tilt;
  // A generator of its own, so that tilting changes nothing else that is drawn from the seed.
  std::mt19937 rng(options.seed ^ 0x71C7A5EDu);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double sigma = 0.58 * options.typical_deg * M_PI / 180.0;
  const double share = std::clamp(options.gait_share, 0.0, 1.0);
  const double sway_sigma = sigma * std::sqrt(1.0 - share);
  const double gait_amplitude = sigma * std::sqrt(2.0 * share);  // a sine of amplitude A has variance A^2 / 2

  const std::vector<double> along = distanceAlong(path);
  // Everything is generated on a fixed grid of distance travelled, so the statistics do not depend on
  // how densely the path is sampled, then read off at each path point.
  const double grid = 0.25;
  const std::size_t n = static_cast<std::size_t>(along.back() / grid) + 2;
  const double a = std::exp(-grid / std::max(options.correlation_length, grid));
  // Two first-order filters in a row (impulse response (k + 1) a^k) give a sway without kinks; its
  // variance for unit input is (1 + a^2) / (1 - a^2)^3.
  const double scale = sway_sigma / std::sqrt((1.0 + a * a) / std::pow(1.0 - a * a, 3));
  Eigen::Vector2d inner = Eigen::Vector2d::Zero(), outer = Eigen::Vector2d::Zero();
  const auto sway_step = [&] {
    inner = a * inner + Eigen::Vector2d(gauss(rng), gauss(rng));
    outer = a * outer + inner;
  };
  // Start from the stationary state: run the filters for many correlation lengths first.
  for (int k = 0; k < static_cast<int>(40.0 * options.correlation_length / grid); ++k) sway_step();
  // The cadence wanders by about 10 % (a first-order process over the same length), so the gait's
  // phase drifts against any fixed keyframe spacing.
  double cadence = gauss(rng);
  const double phase0 = 2.0 * M_PI * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  std::vector<Eigen::Vector2d> sway(n);
  std::vector<double> phase(n);  // of the stride: roll once per stride, pitch once per step
  for (std::size_t i = 0; i < n; ++i) {
    sway_step();
    sway[i] = scale * outer;
    cadence = a * cadence + std::sqrt(1.0 - a * a) * gauss(rng);
    const double stride = 2.0 * options.step_length * (1.0 + 0.1 * std::clamp(cadence, -3.0, 3.0));
    phase[i] = i == 0 ? phase0 : phase[i - 1] + 2.0 * M_PI * grid / stride;
  }
  for (std::size_t k = 0; k < path.size(); ++k) {
    const double u = along[k] / grid;
    const std::size_t i = std::min(static_cast<std::size_t>(u), n - 2);
    const double f = u - static_cast<double>(i);
    const Eigen::Vector2d s = (1.0 - f) * sway[i] + f * sway[i + 1];
    const double p = (1.0 - f) * phase[i] + f * phase[i + 1];
    tilt[k] = s + gait_amplitude * Eigen::Vector2d(std::sin(p), std::sin(2.0 * p + 1.0));
  }
  return tilt;
}

Eigen::Isometry3d tiltPose(const Eigen::Isometry3d& pose, const Eigen::Vector2d& roll_pitch) {
  Eigen::Isometry3d out = pose;
  out.linear() = pose.linear() * (Eigen::AngleAxisd(roll_pitch.y(), Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(roll_pitch.x(), Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
  return out;
}

double tiltAngle(const Eigen::Isometry3d& pose) {
  return std::acos(std::clamp((pose.linear() * Eigen::Vector3d::UnitZ()).z(), -1.0, 1.0));
}

}  // namespace sim
}  // namespace scan_context_loop
