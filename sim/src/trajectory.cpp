#include "scan_context_sim/trajectory.h"

#include <cmath>
#include <random>

#include "polyline.h"

namespace scan_context_loop {
namespace sim {

std::vector<PathPoint> pathFromPoses(const std::vector<Eigen::Isometry3d>& lidar_poses, int first, int last) {
  std::vector<PathPoint> path;
  const int n = static_cast<int>(lidar_poses.size());
  first = std::max(0, first);
  last = last < 0 ? n - 1 : std::min(last, n - 1);
  for (int k = first; k <= last; ++k) {
    const Eigen::Matrix3d r = lidar_poses[k].linear();
    path.push_back({lidar_poses[k].translation().x(), lidar_poses[k].translation().y(), std::atan2(r(1, 0), r(0, 0))});
  }
  return path;
}

std::vector<PathPoint> proceduralPath() {
  using V = Eigen::Vector2d;
  const double lane = 3.0;
  const std::vector<V> waypoints = {
      // Loop 1, counter-clockwise around the block.
      V(0, 0), V(250, 0), V(250, 150), V(0, 150), V(0, -lane),
      // Loop 2, one lane further out (on the right of the direction of travel).
      V(250 + lane, -lane), V(250 + lane, 150 + lane), V(-lane, 150 + lane), V(-lane, 0),
      // Bottom street again in the first lane, then north through the middle of the block.
      V(125, 0), V(125, 150 - lane),
      // East along the top street and south along the east street: against loop 1's direction, in the
      // opposite lane as traffic drives (3 m to the side of loop 1's track).
      V(250 - lane, 150 - lane), V(250 - lane, 10)};
  return roundedPolyline(waypoints, 8.0, 0.5);
}

std::vector<PathPoint> blockPath(bool reverse_second_lap) {
  using V = Eigen::Vector2d;
  const std::vector<V> ccw = {V(0, 0), V(60, 0), V(60, 40), V(0, 40)};
  std::vector<PathPoint> path;
  const auto leg = [&](const V& a, const V& b) {
    const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
    for (double s = 0; s < (b - a).norm(); s += 0.5) {
      const V p = a + (b - a).normalized() * s;
      path.push_back({p.x(), p.y(), heading});
    }
  };
  for (int c = 0; c < 4; ++c) leg(ccw[c], ccw[(c + 1) % 4]);
  if (reverse_second_lap) {
    for (int c = 4; c > 0; --c) leg(ccw[c % 4], ccw[c - 1]);
  } else {
    // Lap 1 again, 3 m further out: ignoring the corners, it runs parallel to lap 1.
    const double o = 3.0;
    const std::vector<V> out = {V(0, -o), V(60 + o, -o), V(60 + o, 40 + o), V(-o, 40 + o)};
    for (int c = 0; c < 4; ++c) leg(out[c], out[(c + 1) % 4]);
  }
  return path;
}

std::vector<double> distanceAlong(const std::vector<PathPoint>& path) {
  std::vector<double> along(path.size(), 0.0);
  for (std::size_t k = 1; k < path.size(); ++k) {
    along[k] = along[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y);
  }
  return along;
}

std::vector<std::size_t> keyframesEvery(const std::vector<PathPoint>& path, double spacing) {
  std::vector<std::size_t> keep;
  double travelled = 0.0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (k > 0) travelled += std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y);
    if (keep.empty() || travelled >= spacing) {
      keep.push_back(k);
      travelled = 0.0;
    }
  }
  return keep;
}

std::vector<std::size_t> framesEvery(const std::vector<double>& times, double period) {
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < times.size(); ++k) {
    // A little slack, so frames sampled exactly `period` apart are all kept despite rounding.
    if (keep.empty() || times[k] - times[keep.back()] >= period - 1e-6) keep.push_back(k);
  }
  return keep;
}

Eigen::Isometry3d sensorPose(const World& world, const PathPoint& p, double mount_height) {
  // The vehicle stands on the sloped ground: its up axis is the ground's normal, so it pitches and
  // rolls with the slope, and the ground is level in the sensor frame as on a real car.
  const double gx = (world.groundZ(p.x + 1.0, p.y) - world.groundZ(p.x - 1.0, p.y)) / 2.0;
  const double gy = (world.groundZ(p.x, p.y + 1.0) - world.groundZ(p.x, p.y - 1.0)) / 2.0;
  const Eigen::Vector3d up = Eigen::Vector3d(-gx, -gy, 1.0).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), up).toRotationMatrix() *
                  Eigen::AngleAxisd(p.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p.x, p.y, world.groundZ(p.x, p.y)) + mount_height * up;
  return pose;
}

std::vector<Eigen::Isometry3d> driftedOdometry(const std::vector<Eigen::Isometry3d>& truth,
                                               const DriftOptions& options) {
  std::vector<Eigen::Isometry3d> odom;
  if (truth.empty()) return odom;
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // Biases: forward (scale), sideways and vertical translation error per metre, heading error per metre
  // and per degree turned. Each is stationary with standard deviation `sigma`.
  const double t = options.translation_per_metre;
  const Eigen::Matrix<double, 5, 1> sigma = (Eigen::Matrix<double, 5, 1>() << t / std::sqrt(2.0), t / std::sqrt(2.0),
                                             0.2 * t, options.yaw_per_metre * M_PI / 180.0, options.yaw_per_degree)
                                                .finished();
  Eigen::Matrix<double, 5, 1> bias;
  for (int i = 0; i < 5; ++i) bias[i] = sigma[i] * gauss(rng);
  odom.push_back(truth.front());
  for (std::size_t k = 1; k < truth.size(); ++k) {
    const Eigen::Isometry3d delta = truth[k - 1].inverse() * truth[k];
    const double metres = delta.translation().norm();
    const Eigen::Matrix3d r = delta.linear();
    const double turned = std::atan2(r(1, 0), r(0, 0));
    const double keep = options.correlation_length > 0.0 ? std::exp(-metres / options.correlation_length) : 1.0;
    for (int i = 0; i < 5; ++i) bias[i] = keep * bias[i] + std::sqrt(1.0 - keep * keep) * sigma[i] * gauss(rng);
    // White noise a tenth of the bias, so the odometry is not perfectly smooth.
    Eigen::Isometry3d error = Eigen::Isometry3d::Identity();
    error.translation() =
        metres *
        (bias.head<3>() + 0.1 * sigma.head<3>().cwiseProduct(Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng))));
    const double yaw_error = bias[3] * metres + bias[4] * turned + 0.1 * sigma[3] * metres * gauss(rng);
    error.linear() = Eigen::AngleAxisd(yaw_error, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    odom.push_back(odom.back() * delta * error);
  }
  return odom;
}

}  // namespace sim
}  // namespace scan_context_loop
