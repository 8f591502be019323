// Geometric verification on real scans from ../shared/data and on degenerate input.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/common/transforms.h>
#include <pcl/io/pcd_io.h>
#include <pcl/kdtree/kdtree_flann.h>

#include "scan_context_loop/alignment.h"
#include "scan_context_loop/detector.h"
#include "scan_context_loop/verification.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

constexpr double kDeg = M_PI / 180.0;

double yawOf(const Eigen::Isometry3d& t) { return std::atan2(t(1, 0), t(0, 0)); }

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, y, 0.0);
  return t;
}

VerificationCloud prepared(const std::string& sequence, int frame, const VerificationConfig& config) {
  return prepareCloud(viewOf(test::kittiScan(sequence, frame)), config);
}

/// The Scan Context yaw prior between two real scans.
double yawPrior(const std::string& sequence, int query, int match) {
  Config config;
  return align(makeDescriptor(test::kittiScan(sequence, query), config),
               makeDescriptor(test::kittiScan(sequence, match), config), config)
      .yaw;
}

void expectPose(const VerificationResult& r, const Eigen::Isometry3d& truth, double metres, double degrees) {
  EXPECT_LT((r.relative.translation() - truth.translation()).norm(), metres)
      << "estimated " << r.relative.translation().transpose() << ", true " << truth.translation().transpose();
  EXPECT_LT(std::fabs(wrapAngle(yawOf(r.relative) - yawOf(truth))), degrees * kDeg)
      << "estimated yaw " << yawOf(r.relative) / kDeg << ", true " << yawOf(truth) / kDeg;
}

TEST(Verification, RecoversAKnownTransformFromAnOffPrior) {
  VerificationConfig config;
  const VerificationCloud query = prepared("00", 94, config);
  // The candidate is the same scan seen from a sensor 1.5 m ahead and 2 m to the right, turned 20 deg.
  const Eigen::Isometry3d truth = planar(1.5, -2.0, 20.0 * kDeg);  // T_query<-match
  VerificationCloud match;
  pcl::transformPointCloud(query, match, truth.inverse().matrix().cast<float>());
  const VerificationResult r = verifyWithYaw(query, match, 23.0 * kDeg, config);  // prior 3 deg off
  ASSERT_TRUE(r.accepted) << r.reason;
  expectPose(r, truth, 0.1, 0.5);
  EXPECT_GT(r.inlier_ratio, 0.9);
  // The floors hold the reported variances (the Hessian alone would claim far less here).
  EXPECT_DOUBLE_EQ(r.covariance(0, 0), config.min_translation_variance);
  EXPECT_DOUBLE_EQ(r.covariance(5, 5), config.min_rotation_variance);
}

/// Fraction of `query` points with a point of `match`, moved by T, within 0.5 m.
double overlap(const VerificationCloud& query, const VerificationCloud& match, const Eigen::Isometry3d& t) {
  VerificationCloud moved;
  pcl::transformPointCloud(match, moved, t.matrix().cast<float>());
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(moved.makeShared());
  std::vector<int> index(1);
  std::vector<float> d2(1);
  std::size_t close = 0;
  for (const auto& p : query) close += tree.nearestKSearch(p, 1, index, d2) == 1 && d2[0] < 0.25f;
  return static_cast<double>(close) / query.size();
}

TEST(Verification, RealReverseRevisitKitti08) {
  VerificationConfig config;
  const Eigen::Isometry3d truth = test::kittiRelative("08", 720, 1500);
  EXPECT_NEAR(truth.translation().x(), -2.08, 0.01) << "oracle from ../shared/data/README.md";
  const double prior = yawPrior("08", 720, 1500);
  ASSERT_LT(std::fabs(wrapAngle(prior - yawOf(truth))), 6.0 * kDeg);
  const VerificationCloud query = prepared("08", 720, config), match = prepared("08", 1500, config);
  const VerificationResult r = verifyWithYaw(query, match, prior, config);
  ASSERT_TRUE(r.accepted) << r.reason;
  // Yaw and the horizontal offset agree with KITTI's ground truth...
  EXPECT_LT(std::fabs(wrapAngle(yawOf(r.relative) - yawOf(truth))), 1.0 * kDeg);
  EXPECT_LT((r.relative.translation() - truth.translation()).head<2>().norm(), 0.5);
  // ...but not its height: the ground truth puts 1500 1.06 m below 720, and applied to the two scans it
  // leaves only a quarter of the points within 0.5 m, where the registered pose leaves most of them.
  // Registration started from the ground truth itself lands on the same pose as from the yaw prior.
  const double truth_overlap = overlap(query, match, truth);
  EXPECT_GT(r.inlier_ratio, 0.8);
  EXPECT_LT(truth_overlap, 0.5 * r.inlier_ratio);
  const VerificationResult from_truth = verify(query, match, truth, config);
  EXPECT_LT((from_truth.relative.translation() - r.relative.translation()).norm(), 0.05);
  EXPECT_LT(std::fabs(wrapAngle(yawOf(from_truth.relative) - yawOf(r.relative))), 0.1 * kDeg);
  std::printf("KITTI 08 720/1500: registered t = (%.2f, %.2f, %.2f), truth (%.2f, %.2f, %.2f); yaw error %.2f deg; "
              "inliers %.2f (ground truth pose: %.2f); %.0f ms\n",
              r.relative.translation().x(), r.relative.translation().y(), r.relative.translation().z(),
              truth.translation().x(), truth.translation().y(), truth.translation().z(),
              std::fabs(wrapAngle(yawOf(r.relative) - yawOf(truth))) / kDeg, r.inlier_ratio, truth_overlap,
              r.seconds * 1e3);
}

TEST(Verification, ConsecutiveScansAcceptedWithTheirPose) {
  VerificationConfig config;
  const VerificationResult r =
      verifyWithYaw(prepared("00", 94, config), prepared("00", 95, config), yawPrior("00", 94, 95), config);
  ASSERT_TRUE(r.accepted) << r.reason;
  expectPose(r, test::kittiRelative("00", 94, 95), 0.1, 0.5);
}

TEST(Verification, RejectsPlacesFiftyEightMetresApart) {
  VerificationConfig config;
  const VerificationResult r =
      verifyWithYaw(prepared("00", 94, config), prepared("00", 198, config), yawPrior("00", 94, 198), config);
  EXPECT_FALSE(r.accepted);
  EXPECT_FALSE(r.reason.empty());
}

TEST(Verification, ApolloPairFromAGuessNearTheTruth) {
  // Finer than the defaults: at 0.6 m voxels and 40 m the slide along this road reaches 7.5 m.
  VerificationConfig config;
  config.voxel_leaf = 0.4;
  config.max_range = 60.0;
  pcl::PointCloud<pcl::PointXYZ> a, b;
  ASSERT_EQ(pcl::io::loadPCDFile(test::sharedData() + "/apollo/apollo_21_36822.pcd", a), 0);
  ASSERT_EQ(pcl::io::loadPCDFile(test::sharedData() + "/apollo/apollo_21_38908.pcd", b), 0);
  // Truth: 38908 in 36822's frame at (28.51, -0.07, 0.02), near-zero yaw; start 1 m and 2 deg off, as an
  // odometry prior would. The two scans share little at 28.5 m, along a road: lateral offset, height
  // and yaw are well determined, the position along the road only to a few metres.
  const Eigen::Isometry3d guess = planar(29.3, 0.5, 2.0 * kDeg);
  const VerificationResult r = verify(prepareCloud(viewOf(a), config), prepareCloud(viewOf(b), config), guess, config);
  const Eigen::Vector3d t = r.relative.translation();
  EXPECT_LT(std::fabs(t.y() + 0.07), 0.6) << t.transpose();
  EXPECT_LT(std::fabs(t.z() - 0.02), 0.3) << t.transpose();
  EXPECT_LT(std::fabs(t.x() - 28.51), 2.5) << t.transpose();
  EXPECT_LT(std::fabs(yawOf(r.relative)), 1.5 * kDeg);
  // With so little overlap the default acceptance rule stays on the safe side.
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("inlier ratio"), std::string::npos) << r.reason;
}

TEST(Verification, EmptyTinyAndNaNCloudsAreRejectedCleanly) {
  VerificationConfig config;
  const VerificationCloud real = prepared("00", 94, config);
  const VerificationCloud empty;
  VerificationCloud tiny_cloud;
  for (int i = 0; i < 10; ++i) tiny_cloud.push_back(pcl::PointXYZ(i, 0, 0));
  const VerificationCloud& tiny = tiny_cloud;
  pcl::PointCloud<pcl::PointXYZ> nan_cloud;
  for (int i = 0; i < 1000; ++i) nan_cloud.push_back(pcl::PointXYZ(NAN, 1, 2));
  const VerificationCloud from_nan = prepareCloud(viewOf(nan_cloud), config);
  EXPECT_TRUE(from_nan.empty());
  for (const VerificationCloud* bad : {&empty, &tiny, &from_nan}) {
    const VerificationResult r = verifyWithYaw(real, *bad, 0.0, config);
    EXPECT_FALSE(r.accepted);
    EXPECT_NE(r.reason.find("too few points"), std::string::npos) << r.reason;
    const VerificationResult s = verifyWithYaw(*bad, real, 0.0, config);
    EXPECT_FALSE(s.accepted);
  }
  EXPECT_FALSE(verify(real, real, Eigen::Isometry3d(Eigen::Matrix4d::Constant(NAN)), config).accepted);
  EXPECT_TRUE(VerificationConfig().validate().empty());
  VerificationConfig broken;
  broken.voxel_leaf = 0;
  broken.min_inlier_ratio = 2;
  EXPECT_EQ(broken.validate().size(), 2u);
}

}  // namespace
}  // namespace scan_context_loop

namespace scan_context_loop {
namespace {

VerificationCloud cloudOf(std::size_t points) {
  VerificationCloud c;
  for (std::size_t i = 0; i < points; ++i) c.push_back(pcl::PointXYZ(i, 0, 0));
  return c;
}

TEST(CloudStore, HalvesItsDensityToStayWithinItsBudget) {
  const std::size_t per_cloud = 100 * sizeof(pcl::PointXYZ);
  CloudStore store(10 * per_cloud);
  for (std::size_t i = 0; i < 10; ++i) store.add(i, cloudOf(100));
  EXPECT_EQ(store.stored(), 10u);
  EXPECT_EQ(store.dropped(), 0u);
  store.add(10, cloudOf(100));  // one too many: only even keyframes are kept from now on
  EXPECT_LE(store.bytes(), 10 * per_cloud);
  EXPECT_EQ(store.dropped(), 5u);
  EXPECT_NE(store.get(0), nullptr);
  EXPECT_EQ(store.get(1), nullptr);
  EXPECT_NE(store.get(2), nullptr);
  EXPECT_EQ(store.get(3), nullptr);
  EXPECT_NE(store.get(10), nullptr);
  store.add(11, cloudOf(100));
  EXPECT_EQ(store.get(11), nullptr);
  for (std::size_t i = 11; i < 200; ++i) store.add(i, cloudOf(100));
  EXPECT_LE(store.bytes(), 10 * per_cloud);
  // Still spread over the whole drive, not only its end.
  std::size_t early = 0;
  for (std::size_t i = 0; i < 100; ++i) early += store.get(i) != nullptr;
  EXPECT_GE(early, 2u);
}

TEST(Verification, EveryRegistrationMethodRecoversAKnownTransform) {
  for (RegistrationMethod method : {RegistrationMethod::kGicp, RegistrationMethod::kIcp, RegistrationMethod::kNdt}) {
    SCOPED_TRACE(registrationMethodName(method));
    VerificationConfig config;
    config.method = method;
    const VerificationCloud query = prepared("00", 198, config);
    const Eigen::Isometry3d truth = planar(-1.0, 1.5, -10.0 * kDeg);
    VerificationCloud match;
    pcl::transformPointCloud(query, match, truth.inverse().matrix().cast<float>());
    const VerificationResult r = verifyWithYaw(query, match, -12.0 * kDeg, config);
    ASSERT_TRUE(r.accepted) << r.reason;
    expectPose(r, truth, 0.15, 0.5);
    // And each turns down the 58 m pair.
    const VerificationResult far = verifyWithYaw(query, prepared("00", 94, config), yawPrior("00", 198, 94), config);
    EXPECT_FALSE(far.accepted) << "inlier ratio " << far.inlier_ratio;
  }
}

TEST(VerifiedDetection, RealPairsThroughTheDetector) {
  Config config;
  config.exclude_recent_frames = 0;
  config.verify = true;
  config.consistency_min_support = 0;  // single pairs: report each verified loop at once
  LoopDetector detector(config);
  KeyframeInfo info;
  const auto feed = [&](const std::string& sequence, int frame) {
    info.stamp += 1.0;
    return detector.process(test::kittiScan(sequence, frame), info);
  };
  ASSERT_TRUE(feed("08", 720).accepted);
  ASSERT_TRUE(feed("00", 94).accepted);
  // 1500 revisits 720 in reverse: its descriptor distance (0.2198) misses the 0.21 threshold, but it is
  // under verify_threshold, and registration accepts it with the refined pose.
  const Detection reverse = feed("08", 1500);
  EXPECT_FALSE(reverse.query.matched);
  ASSERT_TRUE(reverse.verified);
  ASSERT_EQ(reverse.loops.size(), 1u);
  EXPECT_TRUE(reverse.loops[0].verified);
  EXPECT_EQ(reverse.loops[0].match, 0u);
  EXPECT_EQ(reverse.verifications.back().index, 0u);
  EXPECT_GT(reverse.verifications.back().result.inlier_ratio, 0.7);
  // 198 is 58 m from 94: never a loop.
  const Detection far = feed("00", 198);
  EXPECT_TRUE(far.loops.empty());
  for (const auto& v : far.verifications) EXPECT_FALSE(v.result.accepted);
  // 95 revisits 94 with the right pose.
  const Detection next = feed("00", 95);
  ASSERT_EQ(next.loops.size(), 1u);
  EXPECT_EQ(next.verifications.back().index, 1u);
  const Eigen::Isometry3d truth = test::kittiRelative("00", 95, 94);
  EXPECT_LT((next.verifications.back().result.relative.translation() - truth.translation()).norm(), 0.1);
  EXPECT_EQ(detector.cloudStore().stored(), 5u);
}

}  // namespace
}  // namespace scan_context_loop
