// The hard-case drives: a tilting sensor platform, the city drive through oblique streets, and the
// default drive left as it was.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/platform_tilt.h"
#include "scan_context_sim/sensor.h"
#include "scan_context_sim/trajectory.h"
#include "../../test/common/planar.h"

namespace scan_context_loop {
namespace sim {
namespace {

using scan_context_loop::test::kDeg;
using scan_context_loop::test::headingGap;

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * (v.size() - 1))];
}

/// A straight path of `length` metres, a point every `step` metres.
std::vector<PathPoint> straight(double length, double step = 0.5) {
  std::vector<PathPoint> path;
  for (double s = 0.0; s <= length; s += step) path.push_back({s, 0.0, 0.0});
  return path;
}

TEST(Tilt, OffByDefaultAndTheTypicalMagnitudeWhenOn) {
  const auto path = straight(20000.0);
  for (const auto& rp : platformTilt(path, TiltOptions())) ASSERT_EQ(rp, Eigen::Vector2d::Zero());
  for (std::uint32_t seed : {1u, 2u}) {
    TiltOptions options;
    options.typical_deg = 15.0;
    options.seed = seed;
    const auto roll_pitch = platformTilt(path, options);
    ASSERT_EQ(roll_pitch.size(), path.size());
    std::vector<double> angles, roll, pitch;
    for (const auto& rp : roll_pitch) {
      angles.push_back(tiltAngle(tiltPose(Eigen::Isometry3d::Identity(), rp)) / kDeg);
      roll.push_back(rp.x() / kDeg);
      pitch.push_back(rp.y() / kDeg);
    }
    // Asked for 15 degrees: |tilt| has a median near 10 and a 90th percentile near 19.
    EXPECT_GT(quantile(angles, 0.5), 8.5) << "seed " << seed;
    EXPECT_LT(quantile(angles, 0.5), 12.0) << "seed " << seed;
    EXPECT_GT(quantile(angles, 0.9), 16.0) << "seed " << seed;
    EXPECT_LT(quantile(angles, 0.9), 22.5) << "seed " << seed;
    // Both roll and pitch wander, about zero.
    for (const auto* v : {&roll, &pitch}) {
      EXPECT_LT(std::fabs(std::accumulate(v->begin(), v->end(), 0.0) / v->size()), 2.0);
      EXPECT_GT(quantile(*v, 0.9) - quantile(*v, 0.1), 15.0);
    }
    // Smooth: over 5 cm it never moves by more than the gait's swing allows (about 2 degrees), even
    // when sampled that finely.
    const auto fine = platformTilt(straight(300.0, 0.05), options);
    double largest = 0.0;
    for (std::size_t k = 1; k < fine.size(); ++k) largest = std::max(largest, (fine[k] - fine[k - 1]).norm());
    EXPECT_LT(largest / kDeg, 2.5);
    // Not frozen either: keyframes 2 m apart differ.
    double moved = 0.0;
    for (std::size_t k = 4; k < roll_pitch.size(); k += 4) moved += (roll_pitch[k] - roll_pitch[k - 4]).norm();
    EXPECT_GT(moved / (roll_pitch.size() / 4) / kDeg, 1.0);
  }
}

TEST(Tilt, KeepsTheHeadingAndTiltsAboutTheSensorAxes) {
  const Eigen::Isometry3d level = sensorPose(World({}, Eigen::Vector3d::Zero()), {3.0, 4.0, 1.0}, 1.73);
  const Eigen::Isometry3d pitched = tiltPose(level, Eigen::Vector2d(0.0, 0.2));
  EXPECT_TRUE(pitched.translation().isApprox(level.translation()));
  EXPECT_NEAR(tiltAngle(pitched), 0.2, 1e-9);
  // Pitching about the left axis keeps the left axis and the heading of the forward axis.
  EXPECT_TRUE((pitched.linear() * Eigen::Vector3d::UnitY()).isApprox(level.linear() * Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d forward = pitched.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(forward.y(), forward.x()), 1.0, 1e-9);
  const Eigen::Isometry3d rolled = tiltPose(level, Eigen::Vector2d(-0.3, 0.0));
  EXPECT_TRUE((rolled.linear() * Eigen::Vector3d::UnitX()).isApprox(level.linear() * Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(tiltAngle(rolled), 0.3, 1e-9);
  EXPECT_TRUE(tiltPose(level, Eigen::Vector2d::Zero()).isApprox(level));
}

/// Unit normal (pointing up in the sensor frame) of the ground in a scan: the plane through most points
/// within 15 m (RANSAC) among those no steeper than 45 degrees in the sensor frame, which keeps facades
/// out, refitted to its inliers by least squares.
Eigen::Vector3d groundNormal(const pcl::PointCloud<pcl::PointXYZI>& cloud) {
  std::vector<Eigen::Vector3d> near;
  for (const auto& q : cloud) {
    if (Eigen::Vector3d(q.x, q.y, q.z).norm() < 15.0) near.emplace_back(q.x, q.y, q.z);
  }
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, near.size() - 1);
  const auto inliers = [&](const Eigen::Vector3d& n, double offset) {
    std::vector<Eigen::Vector3d> in;
    for (const auto& p : near) {
      if (std::fabs(n.dot(p) - offset) < 0.05) in.push_back(p);
    }
    return in;
  };
  std::vector<Eigen::Vector3d> best;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector3d a = near[pick(rng)], b = near[pick(rng)], c = near[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-6) continue;
    n.normalize();
    if (std::fabs(n.z()) < std::cos(45.0 * kDeg)) continue;
    auto in = inliers(n, n.dot(a));
    if (in.size() > best.size()) best = std::move(in);
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : best) mean += p;
  mean /= static_cast<double>(best.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : best) scatter += (p - mean) * (p - mean).transpose();
  Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
  return normal.z() < 0 ? -normal : normal;
}

TEST(Tilt, TheScanIsCastFromTheTiltedSensor) {
  // A street along x; the sensor rolls and pitches as the platform drives it.
  const auto path = straight(120.0);
  WorldOptions world_options;
  world_options.seed = 3;
  const World world = generateWorld(path, world_options);
  SensorModel hdl;
  ASSERT_TRUE(sensorPreset("hdl64", &hdl));
  TiltOptions options;
  options.typical_deg = 15.0;
  const auto roll_pitch = platformTilt(path, options);
  const Eigen::Vector3d ground_up =
      Eigen::Vector3d(world.groundZ(0, 0) - world.groundZ(1, 0), world.groundZ(0, 0) - world.groundZ(0, 1), 1.0)
          .normalized();
  int tilted = 0;
  for (std::size_t k = 40; k < path.size() - 40; k += 20) {
    const Eigen::Isometry3d level = sensorPose(world, path[k], hdl.mount_height);
    const Eigen::Isometry3d pose = tiltPose(level, roll_pitch[k]);
    const Eigen::Vector3d normal = groundNormal(scan(world, hdl, pose, 0.0, k));
    // The ground in the sensor frame is where the pose says it is, so its normal is off the sensor's
    // z axis by the pose's tilt against the ground.
    const Eigen::Vector3d expected = pose.linear().transpose() * ground_up;
    EXPECT_LT(std::acos(std::min(1.0, normal.dot(expected))) / kDeg, 0.5) << "keyframe at " << path[k].x;
    const double tilt = std::acos(std::min(1.0, (level.linear().transpose() * pose.linear()).col(2).z()));
    EXPECT_NEAR(std::acos(normal.z()), tilt, 0.5 * kDeg);
    tilted += tilt > 8.0 * kDeg;
  }
  EXPECT_GE(tilted, 3);  // the check above saw real tilts, not only near-level poses
  // Level pose: level ground.
  const Eigen::Vector3d level = groundNormal(scan(world, hdl, sensorPose(world, path[100], hdl.mount_height), 0.0, 1));
  EXPECT_LT(std::acos(std::min(1.0, level.z())) / kDeg, 0.3);
}

/// Turns of the drive [deg, signed]: the largest heading change between 25 m before and 25 m after a
/// point, for each stretch where it exceeds 30 degrees (gently curved streets stay below that).
std::vector<double> turns(const std::vector<PathPoint>& path) {
  const auto along = distanceAlong(path);
  std::vector<double> found;
  std::size_t back = 0, ahead = 0;
  double peak = 0.0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    while (along[k] - along[back] > 25.0) ++back;
    while (ahead + 1 < path.size() && along[ahead] - along[k] < 25.0) ++ahead;
    const double change = std::remainder(path[ahead].heading - path[back].heading, 2.0 * M_PI) / kDeg;
    if (std::fabs(change) > 30.0) {
      if (std::fabs(change) > std::fabs(peak)) peak = change;
    } else if (peak != 0.0) {
      found.push_back(peak);
      peak = 0.0;
    }
  }
  return found;
}

TEST(CityDrive, ObliqueStreetsAndAWellSampledPath) {
  int oblique = 0, all = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    CityOptions options;
    options.seed = seed;
    const TimedPath drive = cityDrive(options);
    const auto& path = drive.path;
    const auto along = distanceAlong(path);
    EXPECT_GT(along.back(), 2000.0) << "seed " << seed;
    EXPECT_LT(along.back(), 3200.0) << "seed " << seed;
    for (std::size_t k = 1; k < path.size(); ++k) {
      const double dx = path[k].x - path[k - 1].x, dy = path[k].y - path[k - 1].y;
      ASSERT_GT(std::hypot(dx, dy), 0.2) << "seed " << seed << " point " << k;
      ASSERT_LT(std::hypot(dx, dy), 0.55) << "seed " << seed << " point " << k;
      // The heading follows the direction of travel and turns smoothly (a corner of 10 m radius turns
      // 3 degrees per 0.5 m).
      ASSERT_LT(headingGap(std::atan2(dy, dx), path[k].heading), 0.1) << "seed " << seed << " point " << k;
      ASSERT_LT(headingGap(path[k].heading, path[k - 1].heading), 0.12) << "seed " << seed << " point " << k;
    }
    // Ten corners: three on the loop, one onto the second half, six on it; the junction angle is
    // 180 - |turn|.
    const auto corners = turns(path);
    EXPECT_EQ(corners.size(), 10u) << "seed " << seed;
    for (double turn : corners) {
      const double junction = 180.0 - std::fabs(turn);
      EXPECT_GT(junction, 30.0) << "seed " << seed;
      EXPECT_LT(junction, 150.0) << "seed " << seed;
      oblique += std::fabs(junction - 90.0) > 12.0;
      ++all;
    }
    // Deterministic from the seed.
    const TimedPath again = cityDrive(options);
    ASSERT_EQ(again.path.size(), path.size());
    EXPECT_EQ(again.path.back().x, path.back().x);
    EXPECT_EQ(again.times.back(), drive.times.back());
    options.seed = seed + 100;
    EXPECT_NE(cityDrive(options).path[200].x, path[200].x);
  }
  // Not a grid: most junctions are far from square.
  EXPECT_GT(oblique, all / 2);
}

TEST(CityDrive, RevisitsAnHourLaterTheSameWayReversedAndOneLaneOver) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    CityOptions options;
    options.seed = seed;
    const TimedPath drive = cityDrive(options);
    const auto& path = drive.path;
    const auto& times = drive.times;
    ASSERT_EQ(times.size(), path.size());
    // One stop of an hour between the halves; otherwise 10 m/s.
    int stops = 0;
    for (std::size_t k = 1; k < times.size(); ++k) {
      const double dt = times[k] - times[k - 1];
      ASSERT_GT(dt, 0.0);
      if (dt > 3600.0) {
        ++stops;
      } else {
        ASSERT_LT(dt, 0.06);
      }
    }
    EXPECT_EQ(stops, 1) << "seed " << seed;
    const auto along = distanceAlong(path);
    // Points on straight stretches (not in a corner, where turning curves of two passes in different
    // lanes may run side by side a few metres apart).
    std::vector<bool> on_straight(path.size(), false);
    for (std::size_t k = 20; k + 20 < path.size(); ++k)
      on_straight[k] = headingGap(path[k - 20].heading, path[k + 20].heading) < 0.1;
    int same = 0, reverse = 0, lane = 0, near_parallel = 0;
    for (std::size_t i = 0; i < path.size(); i += 4) {
      bool s = false, r = false, l = false;
      for (std::size_t j = 0; j < i; ++j) {
        const Eigen::Vector2d offset(path[i].x - path[j].x, path[i].y - path[j].y);
        const double d = offset.norm();
        const double turn = headingGap(path[i].heading, path[j].heading);
        // Parallel streets are far enough apart for buildings between them: where the drive runs
        // abreast of an earlier stretch, it is on the same street (within a lane) or 25 m or more away.
        const Eigen::Vector2d forward(std::cos(path[j].heading), std::sin(path[j].heading));
        const double ahead = std::fabs(forward.dot(offset));
        const bool abreast = ahead < 1.0 && (turn < 0.15 || turn > M_PI - 0.15);
        if (on_straight[i] && on_straight[j] && along[i] - along[j] > 60.0 && abreast && d > 4.0 && d < 25.0)
          ++near_parallel;
        if (along[i] - along[j] < 200.0) continue;
        const bool later = times[i] - times[j] > 3600.0;
        const bool next_lane = ahead < 0.3 && d > 3.0 && d < 3.5;
        s = s || (d < 0.3 && turn < 0.1 && later);
        r = r || (next_lane && turn > M_PI - 0.1 && later);
        l = l || (next_lane && turn < 0.1 && later);
      }
      same += s;
      reverse += r;
      lane += l;
    }
    EXPECT_EQ(near_parallel, 0) << "seed " << seed;
    // Metres of each kind of revisit, an hour after the first visit (every 4th point checked).
    EXPECT_GT(same * 2.0, 250.0) << "seed " << seed;
    EXPECT_GT(reverse * 2.0, 250.0) << "seed " << seed;
    EXPECT_GT(lane * 2.0, 250.0) << "seed " << seed;
  }
}

TEST(DefaultDrive, ProceduralPathUnchanged) {
  // The default drive's points, summed: any change to them (and to every default sequence) shows.
  const auto path = proceduralPath();
  ASSERT_EQ(path.size(), 4245u);
  double x = 0.0, y = 0.0, heading = 0.0;
  for (const auto& p : path) x += p.x, y += p.y, heading += p.heading;
  EXPECT_DOUBLE_EQ(x, 562594.30613008048);
  EXPECT_DOUBLE_EQ(y, 317235.89662101399);
  EXPECT_DOUBLE_EQ(heading, 3329.3332470667738);
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
