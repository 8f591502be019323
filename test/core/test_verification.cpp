// Geometric verification on real scans from ../shared/data and on degenerate input.
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/common/transforms.h>
#include <pcl/io/pcd_io.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/verification.h"
#include "test_scenes.h"
#include "../common/planar.h"

namespace scan_context_loop {
namespace {

using test::kDeg;
using test::yawOf;
using test::planar;

VoxelCloud prepared(const std::string& sequence, int frame, const VerificationConfig& config) {
  return prepareCloud(viewOf(test::kittiScan(sequence, frame)), config);
}

/// The raw scan as a sensor at T (query frame) would see it: points in that sensor's frame.
VoxelCloud preparedFrom(const std::string& sequence, int frame, const Eigen::Isometry3d& query_from_match,
                        const VerificationConfig& config) {
  pcl::PointCloud<pcl::PointXYZI> moved;
  pcl::transformPointCloud(test::kittiScan(sequence, frame), moved, query_from_match.inverse().matrix().cast<float>());
  return prepareCloud(viewOf(moved), config);
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

void print(const char* what, const VerificationResult& r) {
  std::printf(
      "%s: %s%s; overlap %.3f (query %.3f, candidate %.3f), fitness %.4f, constraint %.3f, coarse %.3f, "
      "hypotheses %d, t = (%.2f, %.2f, %.2f), yaw %.2f deg, %.2f ms\n",
      what, r.accepted ? "accepted" : "rejected: ", r.reason.c_str(), r.inlier_ratio, r.overlap_query, r.overlap_match,
      r.fitness, r.constraint_ratio, r.coarse_score, r.hypotheses, r.relative.translation().x(),
      r.relative.translation().y(), r.relative.translation().z(), yawOf(r.relative) / kDeg, r.seconds * 1e3);
}

TEST(Verification, RecoversAKnownTransformFromAnOffPrior) {
  VerificationConfig config;
  const VoxelCloud query = prepared("00", 94, config);
  // The candidate is the same scan seen from a sensor 1.5 m ahead and 2 m to the right, turned 20 deg;
  // voxelised in its own frame, so no voxel mean is shared exactly.
  const Eigen::Isometry3d truth = planar(1.5, -2.0, 20.0 * kDeg);  // T_query<-match
  const VoxelCloud match = preparedFrom("00", 94, truth, config);
  // The prior has the yaw 3 deg off and no translation at all.
  const VerificationResult r = verify(query, match, planar(0.0, 0.0, 23.0 * kDeg), config);
  print("00 94 moved", r);
  ASSERT_TRUE(r.accepted) << r.reason;
  expectPose(r, truth, 0.05, 0.1);
  EXPECT_GT(r.inlier_ratio, 0.8);
  EXPECT_GT(r.constraint_ratio, 0.1);
  for (int i = 0; i < 6; ++i)
    EXPECT_GE(r.covariance(i, i), i < 3 ? config.min_translation_variance : config.min_rotation_variance);
}

TEST(Verification, RealReverseRevisitKitti08) {
  VerificationConfig config;
  const Eigen::Isometry3d truth = test::kittiRelative("08", 720, 1500);
  EXPECT_NEAR(truth.translation().x(), -2.08, 0.01) << "oracle from ../shared/data/README.md";
  const double prior = yawPrior("08", 720, 1500);
  ASSERT_LT(std::fabs(wrapAngle(prior - yawOf(truth))), 6.0 * kDeg);
  const VerificationResult r =
      verify(prepared("08", 720, config), prepared("08", 1500, config), priorPose(prior), config);
  print("08 720/1500", r);
  ASSERT_TRUE(r.accepted) << r.reason;
  // Yaw and the horizontal offset agree with KITTI's ground truth (whose height here is 1.1 m off: the
  // scans' ground planes agree to a few centimetres, so z is not compared). Poles and trunks are seen
  // from opposite sides on this reverse revisit, which moves their voxel means by a few decimetres.
  EXPECT_LT(std::fabs(wrapAngle(yawOf(r.relative) - yawOf(truth))), 0.3 * kDeg);
  EXPECT_LT((r.relative.translation() - truth.translation()).head<2>().norm(), 0.5);
}

TEST(Verification, ConsecutiveScansAcceptedWithTheirPose) {
  VerificationConfig config;
  const VerificationResult r =
      verify(prepared("00", 94, config), prepared("00", 95, config), priorPose(yawPrior("00", 94, 95)), config);
  print("00 94/95", r);
  ASSERT_TRUE(r.accepted) << r.reason;
  expectPose(r, test::kittiRelative("00", 94, 95), 0.1, 0.3);
}

TEST(Verification, AnAcceptedRegistrationNamesNoTest) {
  VerificationConfig config;
  const VerificationResult r =
      verify(prepared("00", 94, config), prepared("00", 95, config), priorPose(yawPrior("00", 94, 95)), config);
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_TRUE(r.rejected_by.empty());
  EXPECT_EQ(r.rejection_limit, 0.0);
}

TEST(Verification, AnOverlapBetweenTheTwoCutsNeedsSupport) {
  // The consecutive pair overlaps by about 0.9: with the full cut above that it is not accepted but
  // marked as a loop that needs support, at its registered pose; with the floor above it too, rejected.
  VerificationConfig config;
  config.min_inlier_ratio = 0.97;
  config.min_column_overlap = config.supported_column_overlap = 1.0;  // the voxel overlap's floors alone
  const VoxelCloud query = prepared("00", 94, config), match = prepared("00", 95, config);
  const Eigen::Isometry3d prior = priorPose(yawPrior("00", 94, 95));
  const VerificationResult r = verify(query, match, prior, config);
  print("00 94/95 needing support", r);
  EXPECT_FALSE(r.accepted);
  ASSERT_TRUE(r.needs_support) << r.reason;
  EXPECT_NE(r.reason.find("needs support"), std::string::npos) << r.reason;
  // The test that held it back, with the overlap it measured and the cut it missed.
  EXPECT_EQ(r.rejected_by, "overlap");
  EXPECT_DOUBLE_EQ(r.rejection_value, r.inlier_ratio);
  EXPECT_DOUBLE_EQ(r.rejection_limit, 0.97);
  expectPose(r, test::kittiRelative("00", 94, 95), 0.1, 0.3);
  config.supported_inlier_ratio = 0.96;
  const VerificationResult below = verify(query, match, prior, config);
  EXPECT_FALSE(below.accepted);
  EXPECT_FALSE(below.needs_support) << below.reason;
  EXPECT_EQ(below.rejected_by, "overlap");
  EXPECT_DOUBLE_EQ(below.rejection_limit, 0.96);
  // The column overlap's floors work the same way: either overlap reaching its floor passes.
  EXPECT_EQ(below.column_overlap, 0.0) << "not measured while its floors are off";
  config.min_column_overlap = 0.999;
  config.supported_column_overlap = 0.5;  // measured in full while it stays above this
  const VerificationResult measured = verify(query, match, prior, config);
  ASSERT_TRUE(measured.needs_support) << measured.reason;
  EXPECT_GT(measured.column_overlap, measured.inlier_ratio);
  EXPECT_LT(measured.column_overlap, 0.999);
  config.supported_column_overlap = 0.999;  // out of reach: rejected, and counting stopped below it
  const VerificationResult out_of_reach = verify(query, match, prior, config);
  EXPECT_FALSE(out_of_reach.accepted || out_of_reach.needs_support);
  EXPECT_LT(out_of_reach.column_overlap, 0.999);
  config.supported_column_overlap = measured.column_overlap - 0.01;
  const VerificationResult column = verify(query, match, prior, config);
  EXPECT_TRUE(column.needs_support) << column.reason;
  EXPECT_NE(column.reason.find("column overlap"), std::string::npos) << column.reason;
  config.min_column_overlap = measured.column_overlap - 0.01;
  EXPECT_TRUE(verify(query, match, prior, config).accepted);
  config.supported_inlier_ratio = 0.98;  // above the full cut: a configuration error
  EXPECT_EQ(config.validate().size(), 1u);
}

TEST(Verification, RejectsPlacesFiftyEightMetresApart) {
  VerificationConfig config;
  for (const auto& pair : {std::make_pair(94, 198), std::make_pair(198, 94), std::make_pair(95, 199)}) {
    const VerificationResult r = verify(prepared("00", pair.first, config), prepared("00", pair.second, config),
                                        priorPose(yawPrior("00", pair.first, pair.second)), config);
    print("00 far pair", r);
    EXPECT_FALSE(r.accepted);
    EXPECT_FALSE(r.needs_support) << "a wrong place is not even a loop that needs support: " << r.reason;
    EXPECT_FALSE(r.reason.empty());
    // Named by one of the tests, with a value beyond its limit where the test has numbers.
    EXPECT_TRUE(std::any_of(std::begin(kRejectionTests), std::end(kRejectionTests), [&](const char* t) {
      return r.rejected_by == t;
    })) << r.rejected_by;
  }
}

TEST(Verification, WrongYawPriorIsRecoveredByTheOtherHypotheses) {
  VerificationConfig config;
  const Eigen::Isometry3d truth = test::kittiRelative("08", 720, 1500);
  const VoxelCloud query = prepared("08", 720, config), match = prepared("08", 1500, config);
  // A coarse shift 72 deg off (what a tilted sensor gave on a real sequence) fails on its own...
  const Eigen::Isometry3d wrong = priorPose(yawOf(truth) + 72.0 * kDeg);
  const VerificationResult alone = verify(query, match, wrong, config);
  print("08 wrong yaw alone", alone);
  EXPECT_FALSE(alone.accepted && std::fabs(wrapAngle(yawOf(alone.relative) - yawOf(truth))) > 1.0 * kDeg);
  // ...and the descriptor's other distinct column shifts contain the right one.
  Config sc;
  const std::vector<Alignment> yaws = alignHypotheses(makeDescriptor(test::kittiScan("08", 720), sc),
                                                      makeDescriptor(test::kittiScan("08", 1500), sc), 3, 3);
  ASSERT_GE(yaws.size(), 2u);
  std::vector<Eigen::Isometry3d> guesses = {wrong};
  bool has_right = false;
  for (const Alignment& a : yaws) {
    guesses.push_back(priorPose(a.yaw));
    has_right |= std::fabs(wrapAngle(a.yaw - yawOf(truth))) < 6.0 * kDeg;
  }
  EXPECT_TRUE(has_right);
  Verifier verifier(config);
  verifier.setQuery(query);
  const VerificationResult r = verifier.verify(match, guesses);
  print("08 with hypotheses", r);
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT(std::fabs(wrapAngle(yawOf(r.relative) - yawOf(truth))), 0.5 * kDeg);
}

TEST(Verification, ApolloPairFromAGuessNearTheTruth) {
  VerificationConfig config;
  config.max_range = 60.0;
  pcl::PointCloud<pcl::PointXYZ> a, b;
  ASSERT_EQ(pcl::io::loadPCDFile(test::sharedData() + "/apollo/apollo_21_36822.pcd", a), 0);
  ASSERT_EQ(pcl::io::loadPCDFile(test::sharedData() + "/apollo/apollo_21_38908.pcd", b), 0);
  // Truth: 38908 in 36822's frame at (28.51, -0.07, 0.02), near-zero yaw; start 1 m and 2 deg off, as an
  // odometry prior would. The scans share little at 28.5 m, along a road.
  const Eigen::Isometry3d guess = planar(29.3, 0.5, 2.0 * kDeg);
  const VerificationResult r = verify(prepareCloud(viewOf(a), config), prepareCloud(viewOf(b), config), guess, config);
  print("apollo", r);
  const Eigen::Vector3d t = r.relative.translation();
  // Whatever the decision, an accepted pose must be the true one.
  if (r.accepted) {
    EXPECT_LT(std::fabs(t.y() + 0.07), 0.5) << t.transpose();
    EXPECT_LT(std::fabs(t.x() - 28.51), 1.0) << t.transpose();
    EXPECT_LT(std::fabs(yawOf(r.relative)), 0.5 * kDeg);
  } else {
    EXPECT_FALSE(r.reason.empty());
  }
}

TEST(Verification, CorridorCovarianceReportsTheSlide) {
  // Two long parallel walls 6 m apart, a floor and a ceiling: nothing fixes the position along x.
  pcl::PointCloud<pcl::PointXYZ> corridor;
  for (double x = -35.0; x <= 35.0; x += 0.1) {
    for (double z = -1.5; z <= 1.5; z += 0.1) {
      corridor.push_back(pcl::PointXYZ(x, 3.0, z));
      corridor.push_back(pcl::PointXYZ(x, -3.0, z));
    }
    for (double y = -3.0; y <= 3.0; y += 0.1) {
      corridor.push_back(pcl::PointXYZ(x, y, -1.5));
      corridor.push_back(pcl::PointXYZ(x, y, 1.5));
    }
  }
  VerificationConfig config;
  const VoxelCloud query = prepareCloud(viewOf(corridor), config);
  pcl::PointCloud<pcl::PointXYZ> shifted;
  // The candidate's sensor stands 0.3 m further along and 0.4 m to the right: T_query<-match.
  const Eigen::Isometry3d truth = planar(0.3, -0.4, 0.0);
  pcl::transformPointCloud(corridor, shifted, truth.inverse().matrix().cast<float>());
  const VoxelCloud match = prepareCloud(viewOf(shifted), config);
  const VerificationResult r = verify(query, match, planar(0.0, 0.0, 0.0), config);
  print("corridor", r);
  // Across the corridor the pose is pinned down; along it the variance is orders of magnitude larger.
  EXPECT_LT(r.covariance(1, 1), 0.05);
  EXPECT_GT(r.covariance(0, 0), 100.0 * r.covariance(1, 1));
  EXPECT_LT(r.constraint_ratio, 0.01);
  EXPECT_NEAR(r.relative.translation().y(), truth.translation().y(), 0.05);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.reason.find("degenerate"), std::string::npos) << r.reason;
  // A backend that wants such constraints can have them, with that covariance.
  config.allow_degenerate = true;
  const VerificationResult allowed = verify(query, match, planar(0.0, 0.0, 0.0), config);
  EXPECT_TRUE(allowed.accepted) << allowed.reason;
  EXPECT_GT(allowed.covariance(0, 0), 100.0 * allowed.covariance(1, 1));
}

/// The candidate's data with a gravity alignment `degrees` off in roll, as if it had been levelled wrongly.
VoxelCloud preparedTilted(const std::string& sequence, int frame, const Eigen::Isometry3d& query_from_match,
                          double degrees, const VerificationConfig& config) {
  pcl::PointCloud<pcl::PointXYZI> moved;
  pcl::transformPointCloud(test::kittiScan(sequence, frame), moved, query_from_match.inverse().matrix().cast<float>());
  const Eigen::Matrix3f roll =
      Eigen::AngleAxisf(static_cast<float>(degrees * kDeg), Eigen::Vector3f::UnitX()).toRotationMatrix();
  return prepareCloud(viewOf(moved), config, roll);
}

double tiltOf(const Eigen::Isometry3d& t) { return std::acos(std::min(1.0, t(2, 2))) / kDeg; }

TEST(Verification, ATiltTheRegistrationFindsBeyondTheLimitIsLeftToTheGravityAlignment) {
  VerificationConfig config;
  const VoxelCloud query = prepared("00", 94, config);
  const Eigen::Isometry3d truth = planar(1.0, -1.5, 10.0 * kDeg);
  const VoxelCloud match = preparedTilted("00", 94, truth, 2.5, config);

  // Trusted (90 deg): the registration finds the 2.5 deg the candidate's data are rolled by.
  config.registration_max_tilt_deg = 90.0;
  const VerificationResult registered = verify(query, match, planar(0.0, 0.0, 12.0 * kDeg), config);
  print("tilt registered", registered);
  EXPECT_FALSE(registered.tilt_from_alignment);
  EXPECT_NEAR(registered.tilt_deg, 2.5, 0.2);
  EXPECT_NEAR(tiltOf(registered.relative), 2.5, 0.2);

  // Default (1 deg): above the limit, so roll and pitch stay the gravity alignment's (no tilt between the
  // aligned frames), yaw and translation are registered again, and the covariance says how loose roll
  // and pitch are.
  config.registration_max_tilt_deg = 1.0;
  const VerificationResult levelled = verify(query, match, planar(0.0, 0.0, 12.0 * kDeg), config);
  print("tilt from the alignment", levelled);
  EXPECT_TRUE(levelled.tilt_from_alignment);
  EXPECT_NEAR(levelled.tilt_deg, 2.5, 0.2) << "the tilt the registration found is still reported";
  EXPECT_LT(tiltOf(levelled.relative), 0.01);
  expectPose(levelled, truth, 0.3, 0.3);
  const double variance = std::pow(1.0 * kDeg, 2);
  for (int i = 3; i < 5; ++i) {
    EXPECT_NEAR(levelled.covariance(i, i), variance, 1e-12);
    for (int j = 0; j < 6; ++j) {
      if (j != i) EXPECT_EQ(levelled.covariance(i, j), 0.0);
    }
  }

  // Within the limit the registration's own roll and pitch are kept.
  const VoxelCloud slight = preparedTilted("00", 94, truth, 0.5, config);
  const VerificationResult kept = verify(query, slight, planar(0.0, 0.0, 12.0 * kDeg), config);
  EXPECT_FALSE(kept.tilt_from_alignment);
  EXPECT_NEAR(tiltOf(kept.relative), 0.5, 0.2);
}

TEST(VoxelIndex, ARebuildForgetsTheCloudBefore) {
  // Two facades, each its own cloud: the index built on one finds its voxels and none of the other's,
  // however often it is rebuilt in turn (its cells are emptied by the next build, not all cleared).
  pcl::PointCloud<pcl::PointXYZ> ahead, left;
  for (float z = -1.0f; z <= 3.0f; z += 0.1f) {
    for (float s = -8.0f; s <= 8.0f; s += 0.1f) {
      ahead.push_back(pcl::PointXYZ(10.0f, s, z));
      left.push_back(pcl::PointXYZ(s, 12.0f, z));
    }
  }
  VoxelOptions options;
  const VoxelCloud a = makeVoxelCloud(viewOf(ahead), options);
  const VoxelCloud b = makeVoxelCloud(viewOf(left), options);
  ASSERT_GT(a.size(), 50u);
  ASSERT_GT(b.size(), 50u);
  VoxelIndex index;
  for (int round = 0; round < 3; ++round) {
    for (const VoxelCloud* built : {&a, &b}) {
      const VoxelCloud* other = built == &a ? &b : &a;
      index.build(*built);
      std::size_t found = 0, stale = 0;
      for (std::size_t i = 0; i < built->size(); ++i) found += index.at(built->means[i]) == static_cast<int>(i);
      for (const Eigen::Vector3f& m : other->means) stale += index.at(m) >= 0;
      EXPECT_EQ(found, built->size()) << "round " << round;
      EXPECT_EQ(stale, 0u) << "round " << round;
    }
  }
}

TEST(VoxelIndex, OnPlaneFindsAFacadeSampledAtOtherHeightsAndNothingOffIt) {
  // A facade 10 m ahead (x = 10) seen as two scan lines 0.3 m apart near z = 0 ...
  pcl::PointCloud<pcl::PointXYZ> wall;
  for (float z : {0.05f, 0.35f}) {
    for (float y = -8.0f; y <= 8.0f; y += 0.05f) wall.push_back(pcl::PointXYZ(10.0f, y, z));
  }
  VoxelOptions options;
  const VoxelCloud cloud = makeVoxelCloud(viewOf(wall), options);
  VoxelIndex index;
  index.build(cloud);
  const Eigen::Vector3f n(-1.0f, 0.0f, 0.0f);
  // ... agrees with a voxel of the same facade 1.5 m higher (another keyframe's rings), which the
  // nearest-voxel look-up misses,
  const Eigen::Vector3f higher(10.1f, 2.3f, 1.7f);
  EXPECT_LT(index.nearest(higher, 1.0f), 0);
  EXPECT_TRUE(index.onPlane(higher, n, 0.25f, 1.0f, 2.0f));
  // but not with one 0.5 m in front of it, nor one 3 m above its lines, nor beyond its end.
  EXPECT_FALSE(index.onPlane(Eigen::Vector3f(9.5f, 2.3f, 0.5f), n, 0.25f, 1.0f, 2.0f));
  EXPECT_FALSE(index.onPlane(Eigen::Vector3f(10.0f, 2.3f, 3.5f), n, 0.25f, 1.0f, 2.0f));
  EXPECT_FALSE(index.onPlane(Eigen::Vector3f(10.0f, 10.5f, 0.2f), n, 0.25f, 1.0f, 2.0f));
  // A pole (no normal) agrees only with something within the given distance horizontally.
  EXPECT_TRUE(index.onPlane(Eigen::Vector3f(10.2f, 0.5f, 1.5f), Eigen::Vector3f::Zero(), 0.5f, 1.0f, 2.0f));
  EXPECT_FALSE(index.onPlane(Eigen::Vector3f(11.0f, 0.5f, 1.5f), Eigen::Vector3f::Zero(), 0.5f, 1.0f, 2.0f));
}

TEST(VoxelCloud, EveryMemoryLayoutGivesTheSameVoxels) {
  // A real scan, whole (every 3rd point read: over kVoxelCloudMaxPoints) and its first 50,000 points
  // (every point read), in each layout the point kernels read alike, level and turned.
  const auto scan = test::kittiScan("00", 94);
  std::vector<Eigen::Vector3f> whole;
  for (const auto& p : scan) whole.emplace_back(p.x, p.y, p.z);
  ASSERT_GT(whole.size(), 2 * kVoxelCloudMaxPoints);
  const std::vector<Eigen::Vector3f> part(whole.begin(), whole.begin() + 50000);
  const Eigen::Matrix3f turn = Eigen::AngleAxisf(0.05f, Eigen::Vector3f::UnitX()).toRotationMatrix();
  VoxelOptions options;
  options.resolution = 1.0f;
  options.max_range = 40.0f;
  for (const std::vector<Eigen::Vector3f>* points : {static_cast<const std::vector<Eigen::Vector3f>*>(&whole), &part}) {
    for (const Eigen::Matrix3f& rotation : {Eigen::Matrix3f(Eigen::Matrix3f::Identity()), turn}) {
      std::vector<VoxelCloud> clouds;
      for (const auto& [stride, offset] : test::pointLayouts()) {
        std::vector<std::uint8_t> bytes;
        clouds.push_back(makeVoxelCloud(test::inLayout(*points, stride, offset, &bytes), options, rotation));
      }
      ASSERT_GT(clouds[0].size(), 1000u);
      for (std::size_t l = 1; l < clouds.size(); ++l) {
        SCOPED_TRACE("layout " + std::to_string(l) + ", " + std::to_string(points->size()) + " points");
        ASSERT_EQ(clouds[l].size(), clouds[0].size());
        EXPECT_TRUE(clouds[l].means == clouds[0].means);
        EXPECT_TRUE(clouds[l].normals == clouds[0].normals);
      }
    }
  }
}

TEST(Verification, EmptyTinyAndNaNCloudsAreRejectedCleanly) {
  VerificationConfig config;
  const VoxelCloud real = prepared("00", 94, config);
  const VoxelCloud empty;
  pcl::PointCloud<pcl::PointXYZ> few, nan_cloud;
  for (int i = 0; i < 10; ++i) few.push_back(pcl::PointXYZ(i, 0, 0));
  for (int i = 0; i < 1000; ++i) nan_cloud.push_back(pcl::PointXYZ(NAN, 1, 2));
  const VoxelCloud tiny = prepareCloud(viewOf(few), config);
  const VoxelCloud from_nan = prepareCloud(viewOf(nan_cloud), config);
  EXPECT_TRUE(from_nan.empty());
  for (const VoxelCloud* bad : {&empty, &tiny, &from_nan}) {
    const VerificationResult r = verify(real, *bad, priorPose(0.0), config);
    EXPECT_FALSE(r.accepted);
    EXPECT_NE(r.reason.find("too few points"), std::string::npos) << r.reason;
    EXPECT_FALSE(verify(*bad, real, priorPose(0.0), config).accepted);
  }
  EXPECT_FALSE(verify(real, real, Eigen::Isometry3d(Eigen::Matrix4d::Constant(NAN)), config).accepted);
  EXPECT_TRUE(VerificationConfig().validate().empty());
  VerificationConfig broken;
  broken.voxel_leaf = 0;
  broken.min_inlier_ratio = 2;
  EXPECT_EQ(broken.validate().size(), 2u);
}

TEST(Verification, EveryRegistrationMethodRecoversAKnownTransform) {
  for (RegistrationMethod method :
       {RegistrationMethod::kVgicp, RegistrationMethod::kGicp, RegistrationMethod::kIcp, RegistrationMethod::kNdt}) {
    SCOPED_TRACE(registrationMethodName(method));
    VerificationConfig config;
    config.method = method;
    const VoxelCloud query = prepared("00", 198, config);
    const Eigen::Isometry3d truth = planar(-1.0, 1.5, -10.0 * kDeg);
    const VerificationResult r = verify(query, preparedFrom("00", 198, truth, config), priorPose(-12.0 * kDeg), config);
    ASSERT_TRUE(r.accepted) << r.reason;
    expectPose(r, truth, 0.15, 0.5);
    // And each turns down the 58 m pair.
    const VerificationResult far =
        verify(query, prepared("00", 94, config), priorPose(yawPrior("00", 198, 94)), config);
    EXPECT_FALSE(far.accepted) << "inlier ratio " << far.inlier_ratio;
  }
}

TEST(VerifiedDetection, RealPairsThroughTheDetector) {
  Config config;
  config.exclude_recent_frames = 0;
  config.verification.enabled = true;
  config.consistency_min_support = 0;  // single pairs: report each verified loop at once
  LoopDetector detector(config);
  KeyframeInfo info;
  const auto feed = [&](const std::string& sequence, int frame) {
    info.stamp += 1.0;
    return detector.process(viewOf(test::kittiScan(sequence, frame)), info);
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
  EXPECT_GT(reverse.verifications.back().result.inlier_ratio, config.verification.min_inlier_ratio);
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
