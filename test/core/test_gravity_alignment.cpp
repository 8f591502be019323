// Gravity alignment: from a gravity-aligned orientation, and from the ground plane of real KITTI scans.
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/gravity_alignment.h"
#include "test_scenes.h"
#include "../common/planar.h"

namespace scan_context_loop {
namespace {

using test::kDeg;

Eigen::Matrix3d rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }
Eigen::Matrix3d ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }

/// world_R_sensor of a sensor with this heading, pitch and roll (ZYX Euler angles).
Eigen::Matrix3d orientation(double yaw, double pitch, double roll) { return rz(yaw) * ry(pitch) * rx(roll); }

/// Angle of the rotation a^T b [degrees].
double angleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() / kDeg;
}

TEST(GravityAlignmentOrientation, LevelPoseGivesIdentity) {
  EXPECT_TRUE(
      gravityAlignmentFromOrientation(Eigen::Matrix3d::Identity()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  // Heading alone is not gravity-aligned away.
  EXPECT_TRUE(gravityAlignmentFromOrientation(rz(2.5)).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(GravityAlignmentOrientation, RemovesRollAndPitchKeepsHeading) {
  for (double yaw : {0.0, 0.7, -2.9}) {
    for (double pitch : {-20.0, 0.0, 10.0, 35.0}) {
      for (double roll : {-15.0, 0.0, 20.0}) {
        const Eigen::Matrix3d world_R_sensor = orientation(yaw, pitch * kDeg, roll * kDeg);
        const Eigen::Matrix3d L = gravityAlignmentFromOrientation(world_R_sensor);
        SCOPED_TRACE(testing::Message() << "yaw " << yaw << " pitch " << pitch << " roll " << roll);
        // A rotation, and the documented formula.
        EXPECT_TRUE((L * L.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
        EXPECT_NEAR(L.determinant(), 1.0, 1e-12);
        EXPECT_TRUE(L.isApprox(rz(-yaw) * world_R_sensor, 1e-12));
        // World up, seen from the sensor, is L's z.
        EXPECT_TRUE(
            (L * world_R_sensor.transpose() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
        // The gravity-aligned frame differs from the world by the heading alone.
        EXPECT_TRUE((world_R_sensor * L.transpose()).isApprox(rz(yaw), 1e-12));
        // The sensor's x axis stays in L's x-z plane, pointing forward.
        const Eigen::Vector3d x = L * Eigen::Vector3d::UnitX();
        EXPECT_NEAR(x.y(), 0.0, 1e-12);
        EXPECT_GT(x.x(), 0.0);
      }
    }
  }
}

TEST(GravityAlignmentOrientation, SensorPointingStraightUpStillGivesARotation) {
  const Eigen::Matrix3d L = gravityAlignmentFromOrientation(ry(-M_PI / 2));
  EXPECT_TRUE((L * L.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_TRUE((L * ry(-M_PI / 2).transpose() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // The sensor's y axis is horizontal here and is kept as L's y.
  EXPECT_TRUE((L * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(GravityAlignmentCloud, RotatesFinitePointsAndDropsTheOthers) {
  pcl::PointCloud<pcl::PointXYZI> cloud;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  pcl::PointXYZI p;
  p.x = 1.0f, p.y = 2.0f, p.z = 3.0f, p.intensity = 0.5f;
  cloud.push_back(p);
  p.x = nan;
  cloud.push_back(p);
  p.x = 4.0f, p.z = inf;
  cloud.push_back(p);
  p.z = -1.0f;
  cloud.push_back(p);
  const Eigen::Matrix3f R = rz(M_PI / 2).cast<float>();
  const auto out = rotatedCloud(viewOf(cloud), R);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].getVector3fMap().isApprox(Eigen::Vector3f(-2.0f, 1.0f, 3.0f), 1e-6f));
  EXPECT_TRUE(out[1].getVector3fMap().isApprox(Eigen::Vector3f(-2.0f, 4.0f, -1.0f), 1e-6f));
  EXPECT_TRUE(rotatedCloud(PointView(), R).empty());
}

// KITTI's HDL-64E is mounted level, 1.73 m above the road.
TEST(GravityAlignmentGround, KittiScansAreLevelAtTheMountingHeight) {
  for (const auto& [sequence, frame] :
       {std::pair<std::string, int>{"00", 94}, {"00", 198}, {"08", 720}, {"08", 1500}}) {
    SCOPED_TRACE(sequence + "/" + std::to_string(frame));
    const auto cloud = test::kittiScan(sequence, frame);
    Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
    GroundFit fit;
    ASSERT_TRUE(gravityAlignmentFromGround(viewOf(cloud), GroundFitOptions(), &L, &fit)) << fit.reason;
    EXPECT_TRUE(fit.reason.empty());
    EXPECT_LT(fit.tilt_deg, 2.0);
    EXPECT_NEAR(fit.height, 1.73, 0.1);
    EXPECT_GT(fit.inliers, fit.considered / 3);
    EXPECT_NEAR(fit.normal.norm(), 1.0, 1e-9);
    EXPECT_LT(angleBetween(L, Eigen::Matrix3d::Identity()), 2.0);
  }
}

/// The scan a sensor would have taken with this roll and pitch added: points in the tilted frame.
pcl::PointCloud<pcl::PointXYZ> tilted(const pcl::PointCloud<pcl::PointXYZI>& cloud, const Eigen::Matrix3d& tilt) {
  return rotatedCloud(viewOf(cloud), tilt.transpose().cast<float>());
}

TEST(GravityAlignmentGround, TiltedKittiScanIsGravityAlignedBack) {
  const auto cloud = test::kittiScan("00", 94);
  Eigen::Matrix3d level_R_original;
  GroundFit original;
  ASSERT_TRUE(gravityAlignmentFromGround(viewOf(cloud), GroundFitOptions(), &level_R_original, &original))
      << original.reason;
  for (const auto& [roll, pitch] :
       {std::pair<double, double>{10, 0}, {0, 10}, {-20, 0}, {0, 20}, {10, -20}, {20, 20}}) {
    SCOPED_TRACE(testing::Message() << "roll " << roll << " pitch " << pitch);
    const Eigen::Matrix3d tilt = orientation(0.0, pitch * kDeg, roll * kDeg);
    const auto scan = tilted(cloud, tilt);
    Eigen::Matrix3d L;
    GroundFit fit;
    ASSERT_TRUE(gravityAlignmentFromGround(viewOf(scan), GroundFitOptions(), &L, &fit)) << fit.reason;
    // L should undo the tilt (original sensor <- tilted sensor is `tilt`), up to the original's own
    // small tilt, which the fit removes too.
    const double error = angleBetween(L, level_R_original * tilt);
    std::printf(
        "[ gravity alignment ] roll %3.0f pitch %3.0f: tilt found %.2f deg, %.2f deg from the inverse rotation\n", roll,
        pitch, fit.tilt_deg, error);
    EXPECT_LT(error, 1.0);
    EXPECT_NEAR(fit.tilt_deg, Eigen::AngleAxisd(tilt).angle() / kDeg, 1.0 + original.tilt_deg);
    // The road here has two levels about 0.15 m apart (road and verges); a different sample of the
    // tilted cloud can weigh them differently.
    EXPECT_NEAR(fit.height, original.height, 0.1);
  }
}

TEST(GravityAlignmentGround, GravityAlignmentRestoresTheScanContextDistance) {
  const Config config;
  const auto cloud = test::kittiScan("00", 94);
  const Descriptor reference = makeDescriptor(cloud, config);
  for (double degrees : {10.0, 20.0}) {
    SCOPED_TRACE(testing::Message() << degrees << " degrees of roll and pitch");
    const auto scan = tilted(cloud, orientation(0.0, degrees * kDeg, degrees * kDeg));
    Eigen::Matrix3d L;
    GroundFit fit;
    ASSERT_TRUE(gravityAlignmentFromGround(viewOf(scan), GroundFitOptions(), &L, &fit)) << fit.reason;
    const double before = align(reference, makeDescriptor(scan, config), config).distance;
    const double after =
        align(reference, makeDescriptor(rotatedCloud(viewOf(scan), L.cast<float>()), config), config).distance;
    std::printf(
        "[ gravity alignment ] %.0f deg roll and pitch: distance to the original %.3f tilted, %.3f gravity-aligned\n",
        degrees, before, after);
    EXPECT_LT(after, 0.1);
    EXPECT_LT(2.0 * after, before);
    EXPECT_GT(before, config.distance_threshold);
  }
}

TEST(GravityAlignmentGround, NoGroundGivesFalseAndAReason) {
  const auto expectNoFit = [](const PointView& view, const char* what) {
    SCOPED_TRACE(what);
    Eigen::Matrix3d L = 2.0 * Eigen::Matrix3d::Identity();
    GroundFit fit;
    EXPECT_FALSE(gravityAlignmentFromGround(view, GroundFitOptions(), &L, &fit));
    EXPECT_FALSE(fit.reason.empty());
    EXPECT_EQ(L, 2.0 * Eigen::Matrix3d::Identity()) << "left unchanged";
    EXPECT_FALSE(gravityAlignmentFromGround(view, GroundFitOptions(), nullptr, nullptr));
  };
  expectNoFit(PointView(), "empty view");
  const pcl::PointCloud<pcl::PointXYZ> empty;
  expectNoFit(viewOf(empty), "empty cloud");

  const float nan = std::numeric_limits<float>::quiet_NaN();
  pcl::PointCloud<pcl::PointXYZ> nans;
  for (int i = 0; i < 5000; ++i) nans.push_back(pcl::PointXYZ(nan, nan, nan));
  expectNoFit(viewOf(nans), "all NaN");

  // Real scans with only what is above the sensor left: facades, trees, signs.
  for (const auto& [sequence, frame] : {std::pair<std::string, int>{"00", 94}, {"08", 720}}) {
    pcl::PointCloud<pcl::PointXYZI> above;
    for (const auto& p : test::kittiScan(sequence, frame)) {
      if (p.z > 0.0f) above.push_back(p);
    }
    expectNoFit(viewOf(above), ("KITTI " + sequence + " above the sensor").c_str());
  }

  // A corridor 3 m wide and 3 m high whose floor the sensor does not see: walls and a ceiling.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> along(-25.0f, 25.0f), up(-1.0f, 2.0f), across(-1.5f, 1.5f);
  pcl::PointCloud<pcl::PointXYZ> corridor;
  for (int i = 0; i < 20000; ++i) {
    corridor.push_back(pcl::PointXYZ(along(rng), i % 2 == 0 ? 1.5f : -1.5f, up(rng)));
    if (i % 4 == 0) corridor.push_back(pcl::PointXYZ(along(rng), across(rng), 2.0f));
  }
  expectNoFit(viewOf(corridor), "corridor without floor");
}

TEST(GravityAlignmentGround, SameCloudSameFitAndInvalidOptionsAreRefused) {
  const auto cloud = test::kittiScan("08", 720);
  GroundFit a, b;
  ASSERT_TRUE(gravityAlignmentFromGround(viewOf(cloud), GroundFitOptions(), nullptr, &a));
  ASSERT_TRUE(gravityAlignmentFromGround(viewOf(cloud), GroundFitOptions(), nullptr, &b));
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.inliers, b.inliers);

  GroundFitOptions bad;
  bad.max_range = bad.min_range;
  GroundFit fit;
  EXPECT_FALSE(gravityAlignmentFromGround(viewOf(cloud), bad, nullptr, &fit));
  EXPECT_NE(fit.reason.find("range"), std::string::npos) << fit.reason;
}

}  // namespace
}  // namespace scan_context_loop

namespace scan_context_loop {
namespace {

/// Feeds `count` keyframes of one real scan tilted by 8 degrees of pitch, with poses that are
/// `tilted_pose` (the true attitude) or level (a world frame that started tilted with the sensor), and
/// returns the detector's estimate of the world's tilt and the last keyframe's gravity alignment [deg].
struct TiltOutcome {
  double world_tilt = -1.0, last_tilt = -1.0;
  std::string last_aligned_by;
};

TiltOutcome levelWith(const Eigen::Matrix3d& world, bool tilted_pose, int count) {
  const auto cloud = test::kittiScan("00", 94);
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(8.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const auto scan = rotatedCloud(viewOf(cloud), tilt.transpose().cast<float>());
  Config config;
  config.verification.enabled = false;
  LoopDetector detector(config);
  TiltOutcome out;
  for (int k = 0; k < count; ++k) {
    KeyframeInfo info;
    info.stamp = k;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = 2.0 * k;
    if (tilted_pose) pose.linear() = tilt;
    pose.linear() = world * pose.linear();
    info.pose = pose;
    const Detection d = detector.process(viewOf(scan), info);
    if (d.world_tilt_deg >= 0.0) out.world_tilt = d.world_tilt_deg;
    out.last_tilt = d.tilt_deg;
    out.last_aligned_by = d.aligned_by;
  }
  return out;
}

TEST(GravityAlignmentWorldTilt, ATiltedOdometryWorldIsMeasuredAndAYUpOneTurned) {
  const int count = static_cast<int>(WorldTilt::kMinFits + 2 * LoopDetector::kGravityCheckInterval);
  const Eigen::Matrix3d z_up = Eigen::Matrix3d::Identity();
  const TiltOutcome level_world = levelWith(z_up, true, count);
  const TiltOutcome tilted_world = levelWith(z_up, false, count);
  // LeGO-LOAM's world: y up (the sensor's axes turned into camera axes), tilted as the first scan was.
  const Eigen::Matrix3d y_up = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const TiltOutcome camera_world = levelWith(y_up, true, count);
  std::printf("[ gravity alignment ] world tilt: %.2f deg gravity-aligned, %.2f deg started tilted, %.2f deg y up\n",
              level_world.world_tilt, tilted_world.world_tilt, camera_world.world_tilt);
  // The scan itself is about 1 degree off level (KITTI 00 frame 94, GravityAlignmentGround above).
  EXPECT_GE(level_world.world_tilt, 0.0);
  EXPECT_LT(level_world.world_tilt, 2.0);
  EXPECT_GT(tilted_world.world_tilt, LoopDetector::kGravitySuspectDeg);
  EXPECT_NEAR(tilted_world.world_tilt, 8.0, 1.5);
  // Its y axis is found to point up, exactly, and what is left is the scan's own degree.
  EXPECT_LT(camera_world.world_tilt, 2.0);
  // A gravity-aligned pose levels the whole 8 degrees; a world a few degrees off keeps the pose as it is
  // (the same tilt for every keyframe of the session); a y-up world is turned z up from its first keyframe.
  EXPECT_EQ(level_world.last_aligned_by, "pose");
  EXPECT_NEAR(level_world.last_tilt, 8.0, 1.5);
  EXPECT_EQ(tilted_world.last_aligned_by, "pose");
  EXPECT_LT(tilted_world.last_tilt, 0.5);
  EXPECT_EQ(camera_world.last_aligned_by, "pose");
  EXPECT_NEAR(camera_world.last_tilt, 8.0, 1.5);
}

TEST(GravityAlignmentWorldTilt, FitsThatDisagreeAreNotAnEstimate) {
  WorldTilt tilt;
  for (std::size_t k = 0; k < 3 * WorldTilt::kMinFits; ++k) {
    // Up pointing 30 degrees off in a direction that turns with k: they scatter by ~30 degrees.
    const double a = 2.0 * M_PI * static_cast<double>(k) / 7.0;
    tilt.add(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5 * std::cos(a), 0.5 * std::sin(a), 0.866));
  }
  EXPECT_FALSE(tilt.established());
  EXPECT_TRUE(tilt.correction().isIdentity());
  tilt.reset();
  for (std::size_t k = 0; k < WorldTilt::kMinFits; ++k)
    tilt.add(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0.1, 1).normalized());
  ASSERT_TRUE(tilt.established());
  EXPECT_TRUE(tilt.axisKnown());
  EXPECT_TRUE(tilt.axisCorrection().isIdentity());
  EXPECT_NEAR(tilt.tiltDeg(), std::atan(0.1) * 180.0 / M_PI, 1e-6);
  EXPECT_TRUE((tilt.correction() * Eigen::Vector3d(0, 0.1, 1).normalized()).isApprox(Eigen::Vector3d::UnitZ()));
}

}  // namespace
}  // namespace scan_context_loop
