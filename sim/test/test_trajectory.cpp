// Drives: the procedural city drive and its revisits, keyframes along real KITTI poses, drifting odometry.
#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_sim/trajectory.h"
#include "../../test/common/planar.h"

namespace scan_context_loop {
namespace sim {
namespace {

using scan_context_loop::test::headingGap;
using scan_context_loop::test::yawOf;

double pathLength(const std::vector<PathPoint>& path, std::size_t from, std::size_t to) {
  double length = 0.0;
  for (std::size_t i = from + 1; i <= to; ++i)
    length += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  return length;
}

TEST(Trajectory, ProceduralDriveRevisitsTheSameWayReversedAndOneLaneOver) {
  const auto path = proceduralPath();
  EXPECT_GT(pathLength(path, 0, path.size() - 1), 2000.0);
  EXPECT_LT(pathLength(path, 0, path.size() - 1), 2300.0);
  // For each point, the kinds of earlier passes (at least 200 m of driving before) nearby.
  int same = 0, reverse = 0, lane = 0;
  std::vector<double> along(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) along[i] = along[i - 1] + pathLength(path, i - 1, i);
  for (std::size_t i = 0; i < path.size(); i += 4) {
    bool s = false, r = false, l = false;
    for (std::size_t j = 0; j < i && along[i] - along[j] > 200.0; ++j) {
      const double d = std::hypot(path[i].x - path[j].x, path[i].y - path[j].y);
      const double turn = headingGap(path[i].heading, path[j].heading);
      s = s || (d < 0.3 && turn < 0.1);
      r = r || (d > 2.5 && d < 3.5 && turn > M_PI - 0.1);
      l = l || (d > 2.9 && d < 3.1 && turn < 0.1);
    }
    same += s;
    reverse += r;
    lane += l;
  }
  // Metres of each kind of revisit (points are 0.5 m apart, every 4th checked).
  EXPECT_GT(same * 2.0, 100.0);
  EXPECT_GT(reverse * 2.0, 200.0);
  EXPECT_GT(lane * 2.0, 500.0);
}

TEST(Trajectory, KeyframesEverySpacingMetres) {
  const auto path = proceduralPath();
  for (double spacing : {1.0, 2.0, 5.0}) {
    const auto keys = keyframesEvery(path, spacing);
    ASSERT_EQ(keys.front(), 0u);
    for (std::size_t k = 1; k < keys.size(); ++k) {
      const double travelled = pathLength(path, keys[k - 1], keys[k]);
      EXPECT_GE(travelled, spacing - 1e-9);
      EXPECT_LT(travelled, spacing + 0.5 + 1e-9);  // path points are 0.5 m apart
    }
    EXPECT_NEAR(keys.size(), pathLength(path, 0, path.size() - 1) / spacing, 0.12 * keys.size());
  }
}

TEST(Trajectory, KeyframesAlongRealKittiPoses) {
  const std::string dir = std::string(SCL_SHARED_DATA) + "/kitti/00";
  std::vector<Eigen::Isometry3d> camera;
  Eigen::Isometry3d tr;
  std::string error;
  if (!kitti::readPoses(dir + "/poses.txt", &camera, &error) || !kitti::readCalibTr(dir + "/calib.txt", &tr, &error)) {
    GTEST_SKIP() << "no KITTI 00 poses: " << error;
  }
  const auto lidar = kitti::lidarPoses(camera, tr);
  const auto path = pathFromPoses(lidar, 100, 900);
  ASSERT_EQ(path.size(), 801u);
  EXPECT_DOUBLE_EQ(path.front().x, lidar[100].translation().x());
  EXPECT_DOUBLE_EQ(path.back().y, lidar[900].translation().y());
  EXPECT_EQ(pathFromPoses(lidar, 4500, -1).size(), lidar.size() - 4500);
  // LiDAR x points forward: the heading follows the direction of travel.
  for (std::size_t k = 1; k < path.size(); ++k) {
    const double dx = path[k].x - path[k - 1].x, dy = path[k].y - path[k - 1].y;
    if (std::hypot(dx, dy) < 0.3) continue;
    EXPECT_LT(headingGap(std::atan2(dy, dx), path[k].heading), 0.2) << "frame " << 100 + k;
  }
  double max_step = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) max_step = std::max(max_step, pathLength(path, k - 1, k));
  const auto keys = keyframesEvery(path, 2.0);
  for (std::size_t k = 1; k < keys.size(); ++k) {
    const double travelled = pathLength(path, keys[k - 1], keys[k]);
    EXPECT_GE(travelled, 2.0);
    EXPECT_LT(travelled, 2.0 + max_step);
  }
  const double length = pathLength(path, 0, path.size() - 1);
  EXPECT_GT(keys.size(), length / (2.0 + max_step));
  EXPECT_LE(keys.size(), length / 2.0 + 1);
}

TEST(Trajectory, SensorPoseStandsOnTheSlopedGround) {
  const World world({}, Eigen::Vector3d(0.03, -0.04, 2.0));  // 5 % slope
  const Eigen::Isometry3d pose = sensorPose(world, {10.0, 20.0, 0.5}, 1.73);
  const Eigen::Vector3d up = Eigen::Vector3d(-0.03, 0.04, 1.0).normalized();
  EXPECT_TRUE((pose.linear() * Eigen::Vector3d::UnitZ()).isApprox(up, 1e-9));
  EXPECT_NEAR((pose.translation() - Eigen::Vector3d(10.0, 20.0, world.groundZ(10.0, 20.0))).dot(up), 1.73, 1e-9);
  // The forward axis keeps the heading in the horizontal plane.
  const Eigen::Vector3d forward = pose.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(forward.y(), forward.x()), 0.5, 0.01);
}

/// A drive of `length` metres in steps of `step` metres: straight, or turning `turn_deg` at each of
/// four evenly spaced corners.
std::vector<Eigen::Isometry3d> drive(double length, double step, double turn_deg) {
  std::vector<Eigen::Isometry3d> poses(1, Eigen::Isometry3d::Identity());
  const int steps = static_cast<int>(std::lround(length / step));
  for (int k = 1; k <= steps; ++k) {
    Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
    delta.translation().x() = step;
    if (k % (steps / 4) == 0)
      delta.linear() = Eigen::AngleAxisd(turn_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    poses.push_back(poses.back() * delta);
  }
  return poses;
}

/// Mean over seeds of the final translation and heading errors [m, deg].
std::pair<double, double> meanDrift(const std::vector<Eigen::Isometry3d>& truth, DriftOptions drift) {
  double translation = 0.0, heading = 0.0;
  const int seeds = 40;
  for (int seed = 1; seed <= seeds; ++seed) {
    drift.seed = seed;
    const Eigen::Isometry3d end = driftedOdometry(truth, drift).back();
    translation += (end.translation() - truth.back().translation()).norm();
    heading += std::fabs(std::remainder(yawOf(end) - yawOf(truth.back()), 2 * M_PI)) * 180.0 / M_PI;
  }
  return {translation / seeds, heading / seeds};
}

TEST(Trajectory, OdometryDriftsByTheConfiguredRates) {
  const auto straight = drive(200.0, 2.0, 0.0);
  DriftOptions none;
  none.translation_per_metre = none.yaw_per_metre = none.yaw_per_degree = 0.0;
  const auto exact = driftedOdometry(straight, none);
  ASSERT_EQ(exact.size(), straight.size());
  EXPECT_TRUE(exact.back().isApprox(straight.back(), 1e-9));

  // 1 % over 200 m: about 2 m (the bias wanders a little over the stretch).
  DriftOptions translation = none;
  translation.translation_per_metre = 0.01;
  const auto t2 = meanDrift(straight, translation);
  EXPECT_GT(t2.first, 0.5 * 2.0);
  EXPECT_LT(t2.first, 1.3 * 2.0);
  EXPECT_NEAR(t2.second, 0.0, 1e-9);
  // The same whatever the keyframe spacing: a rate per metre, not per step.
  const auto t1 = meanDrift(drive(200.0, 0.5, 0.0), translation);
  EXPECT_NEAR(t1.first / t2.first, 1.0, 0.3);

  // 0.01 deg/m over 200 m: about 2 deg of heading.
  DriftOptions yaw = none;
  yaw.yaw_per_metre = 0.01;
  const auto y = meanDrift(straight, yaw);
  EXPECT_GT(y.second, 0.5 * 2.0);
  EXPECT_LT(y.second, 1.3 * 2.0);

  // 1 % of four 90 deg turns: about 3.6 deg, and nothing when driving straight.
  DriftOptions turns = none;
  turns.yaw_per_degree = 0.01;
  const auto square = drive(200.0, 2.0, 90.0);
  const auto q = meanDrift(square, turns);
  EXPECT_GT(q.second, 0.5 * 3.6);
  EXPECT_LT(q.second, 1.3 * 3.6);
  EXPECT_NEAR(meanDrift(straight, turns).second, 0.0, 1e-9);
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
