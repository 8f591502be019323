// The acceptance rule on its own: each test names itself, the value it measured and the limit it broke,
// and a value at its limit passes while the next one beyond it does not.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "scan_context_loop/core/acceptance_rule.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {
namespace {

double above(double x) { return std::nextafter(x, std::numeric_limits<double>::infinity()); }
double below(double x) { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

void expectRejection(const Verdict& v, RejectionTest test, double value, double limit) {
  EXPECT_FALSE(v.accepted());
  EXPECT_EQ(v.test, test) << v.reason;
  EXPECT_EQ(v.value, value) << v.reason;
  EXPECT_EQ(v.limit, limit) << v.reason;
  EXPECT_FALSE(v.reason.empty());
}

/// A registration that passes every test in full with the default limits.
VerificationResult passing() {
  VerificationResult r;
  r.inlier_ratio = r.overlap_query = r.overlap_match = 0.9;
  r.violation = r.violation_query = r.violation_match = 0.1;
  r.fitness = 0.005;
  r.constraint_ratio = 0.5;
  return r;
}

TEST(AcceptanceRule, EveryTestHasItsName) {
  EXPECT_STREQ(rejectionTestName(RejectionTest::kNone), "");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kUnverifiable), "unverifiable");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kStructure), "structure");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kRegistration), "registration");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kOverlap), "overlap");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kFreeSpace), "free_space");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kFitness), "fitness");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kDegenerate), "degenerate");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kOdometryRotation), "odometry_rotation");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kOdometryTranslation), "odometry_translation");
  EXPECT_STREQ(rejectionTestName(RejectionTest::kConsistency), "consistency");
}

TEST(AcceptanceRule, UnverifiableAndRegistrationFailuresHaveNoNumber) {
  expectRejection(unverifiableVerdict(), RejectionTest::kUnverifiable, 0.0, 0.0);
  EXPECT_EQ(unverifiableVerdict().reason,
            "unverifiable: the candidate's cloud was dropped to stay within verify_max_bytes");
  const Verdict failed = registrationFailure("registration diverged");
  expectRejection(failed, RejectionTest::kRegistration, 0.0, 0.0);
  EXPECT_EQ(failed.reason, "registration diverged");
}

TEST(AcceptanceRule, StructureNeedsTheMinimumOnBothSides) {
  VerificationConfig config;
  config.min_structure = 150;
  EXPECT_TRUE(judgeStructure(150, 150, config).accepted());
  expectRejection(judgeStructure(149, 400, config), RejectionTest::kStructure, 149.0, 150.0);
  expectRejection(judgeStructure(400, 149, config), RejectionTest::kStructure, 149.0, 150.0);
  EXPECT_EQ(judgeStructure(149, 400, config).reason,
            "too few points to verify: structure voxels (query 149, candidate 400, need 150)");
}

TEST(AcceptanceRule, RegisteredTiltIsTrustedUpToItsLimit) {
  VerificationConfig config;
  config.registration_max_tilt_deg = 1.0;
  EXPECT_TRUE(trustsRegisteredTilt(1.0, config));
  EXPECT_FALSE(trustsRegisteredTilt(above(1.0), config));
  config.registration_max_tilt_deg = 0.0;  // never trusted
  EXPECT_FALSE(trustsRegisteredTilt(0.01, config));
}

TEST(AcceptanceRule, ColumnOverlapDecidesOnlyBelowTheFullVoxelFloor) {
  VerificationConfig config;
  EXPECT_TRUE(columnOverlapCanDecide(below(config.min_inlier_ratio), config));
  EXPECT_FALSE(columnOverlapCanDecide(config.min_inlier_ratio, config));
  EXPECT_EQ(columnOverlapFloor(config), config.supported_column_overlap);
  config.supported_column_overlap = 1.0;  // not used
  EXPECT_FALSE(columnOverlapCanDecide(0.0, config));
}

TEST(AcceptanceRule, APassingRegistrationIsAccepted) {
  const Verdict v = judgeRegistration(passing(), VerificationConfig());
  EXPECT_TRUE(v.accepted());
  EXPECT_TRUE(v.reason.empty());
  EXPECT_FALSE(v.needs_support);
  EXPECT_EQ(v.value, 0.0);
  EXPECT_EQ(v.limit, 0.0);
}

TEST(AcceptanceRule, OverlapAtEachFloor) {
  const VerificationConfig config;
  VerificationResult r = passing();
  r.inlier_ratio = config.min_inlier_ratio;
  EXPECT_TRUE(judgeRegistration(r, config).accepted());
  // Below the full floor, at the support floor: needs support.
  r.inlier_ratio = below(config.min_inlier_ratio);
  Verdict v = judgeRegistration(r, config);
  expectRejection(v, RejectionTest::kOverlap, r.inlier_ratio, config.min_inlier_ratio);
  EXPECT_TRUE(v.needs_support);
  EXPECT_EQ(v.reason.rfind("needs support: inlier ratio", 0), 0u) << v.reason;
  r.inlier_ratio = config.supported_inlier_ratio;
  EXPECT_TRUE(judgeRegistration(r, config).needs_support);
  // Below the support floor: rejected outright.
  r.inlier_ratio = below(config.supported_inlier_ratio);
  v = judgeRegistration(r, config);
  expectRejection(v, RejectionTest::kOverlap, r.inlier_ratio, config.supported_inlier_ratio);
  EXPECT_FALSE(v.needs_support);
  // The column overlap reaching a floor passes that floor instead.
  r.column_overlap = config.supported_column_overlap;
  v = judgeRegistration(r, config);
  EXPECT_TRUE(v.needs_support);
  EXPECT_EQ(v.limit, config.min_inlier_ratio);
  r.column_overlap = config.min_column_overlap;
  EXPECT_TRUE(judgeRegistration(r, config).accepted());
  r.column_overlap = below(config.supported_column_overlap);
  EXPECT_EQ(judgeRegistration(r, config).limit, config.supported_inlier_ratio);
}

TEST(AcceptanceRule, FreeSpaceAtEachFloor) {
  const VerificationConfig config;
  VerificationResult r = passing();
  r.violation = config.max_violation;
  EXPECT_TRUE(judgeRegistration(r, config).accepted());
  r.violation = above(config.max_violation);
  Verdict v = judgeRegistration(r, config);
  expectRejection(v, RejectionTest::kFreeSpace, r.violation, config.max_violation);
  EXPECT_TRUE(v.needs_support);
  r.violation = config.supported_max_violation;
  EXPECT_TRUE(judgeRegistration(r, config).needs_support);
  r.violation = above(config.supported_max_violation);
  v = judgeRegistration(r, config);
  expectRejection(v, RejectionTest::kFreeSpace, r.violation, config.supported_max_violation);
  EXPECT_FALSE(v.needs_support);
}

TEST(AcceptanceRule, Fitness) {
  const VerificationConfig config;
  VerificationResult r = passing();
  r.fitness = config.max_fitness;
  EXPECT_TRUE(judgeRegistration(r, config).accepted());
  r.fitness = above(config.max_fitness);
  expectRejection(judgeRegistration(r, config), RejectionTest::kFitness, r.fitness, config.max_fitness);
  r.fitness = std::numeric_limits<double>::infinity();  // nothing agreed
  EXPECT_EQ(judgeRegistration(r, config).test, RejectionTest::kFitness);
  // Checked before the overlap's full floor: a loop that would need support is rejected by it.
  r.inlier_ratio = below(config.min_inlier_ratio);
  EXPECT_FALSE(judgeRegistration(r, config).needs_support);
}

TEST(AcceptanceRule, Degenerate) {
  VerificationConfig config;
  VerificationResult r = passing();
  r.constraint_ratio = config.min_constraint_ratio;
  EXPECT_TRUE(judgeRegistration(r, config).accepted());
  r.constraint_ratio = below(config.min_constraint_ratio);
  const Verdict v = judgeRegistration(r, config);
  expectRejection(v, RejectionTest::kDegenerate, r.constraint_ratio, config.min_constraint_ratio);
  EXPECT_EQ(v.reason.rfind("degenerate", 0), 0u) << v.reason;
  config.allow_degenerate = true;
  EXPECT_TRUE(judgeRegistration(r, config).accepted());
}

OdometryDisagreement disagreement(double rotation_deg, double translation_m, bool anchored) {
  OdometryDisagreement d;
  d.rotation_deg = rotation_deg;
  d.translation_m = translation_m;
  d.path = 100.0;
  d.anchored = anchored;
  d.drift_rate = 0.1;
  return d;
}

TEST(AcceptanceRule, OdometryRotation) {
  Config config;
  const double allowed = config.verification.odometry_rotation + config.verification.odometry_rotation_drift * 100.0;
  EXPECT_DOUBLE_EQ(rotationAllowance(config.verification, 100.0), allowed);
  EXPECT_FALSE(judgeOdometry(disagreement(allowed, 0.0, false), true, config));
  const auto v = judgeOdometry(disagreement(above(allowed), 0.0, false), true, config);
  ASSERT_TRUE(v);
  expectRejection(*v, RejectionTest::kOdometryRotation, above(allowed), allowed);
  EXPECT_EQ(v->reason, "rotation disagrees with the odometry by " + std::to_string(above(allowed)) + " deg (allowed " +
                           std::to_string(allowed) + " over 100.000000 m of odometry)");
  // Passed in full and within what a broken odometry explains: the consistency check may confirm it.
  EXPECT_TRUE(v->odometry_contradicted);
  EXPECT_FALSE(v->needs_support);
  EXPECT_FALSE(judgeOdometry(disagreement(above(allowed), 0.0, false), false, config)->odometry_contradicted);
  const double plausible = plausibleRotationBreak(100.0);
  EXPECT_TRUE(judgeOdometry(disagreement(plausible, 0.0, false), true, config)->odometry_contradicted);
  EXPECT_FALSE(judgeOdometry(disagreement(above(plausible), 0.0, false), true, config)->odometry_contradicted);
  config.consistency_min_support = 0;  // nothing could confirm it
  EXPECT_FALSE(judgeOdometry(disagreement(above(allowed), 0.0, false), true, config)->odometry_contradicted);
  config.verification.odometry_rotation = 0.0;  // off
  EXPECT_FALSE(judgeOdometry(disagreement(180.0, 0.0, false), true, config));
}

TEST(AcceptanceRule, OdometryTranslationOnlyFromAConfirmedLoop) {
  const Config config;
  const double allowed = config.consistency_translation + 0.1 * 100.0;
  EXPECT_DOUBLE_EQ(anchoredTranslationAllowance(config, 0.1, 100.0), allowed);
  EXPECT_FALSE(judgeOdometry(disagreement(0.0, allowed, true), true, config));
  EXPECT_FALSE(judgeOdometry(disagreement(0.0, 1000.0, false), true, config)) << "the direct odometry places nothing";
  const auto v = judgeOdometry(disagreement(0.0, above(allowed), true), true, config);
  ASSERT_TRUE(v);
  expectRejection(*v, RejectionTest::kOdometryTranslation, above(allowed), allowed);
  EXPECT_NE(v->reason.find(" m of odometry from a confirmed loop)"), std::string::npos) << v->reason;
  EXPECT_TRUE(v->odometry_contradicted);
  // Both beyond their allowance: the rotation is named.
  EXPECT_EQ(judgeOdometry(disagreement(90.0, 1000.0, true), true, config)->test, RejectionTest::kOdometryRotation);
}

TEST(AcceptanceRule, OdometryExcessIsTheLargerShareOfAnAllowance) {
  Config config;
  const double rotation_allowed = rotationAllowance(config.verification, 100.0);
  const double translation_allowed = anchoredTranslationAllowance(config, 0.1, 100.0);
  EXPECT_DOUBLE_EQ(odometryExcess(disagreement(rotation_allowed / 2, 0.0, false), config), 0.5);
  EXPECT_DOUBLE_EQ(odometryExcess(disagreement(rotation_allowed / 2, 3 * translation_allowed, true), config), 3.0);
  EXPECT_DOUBLE_EQ(odometryExcess(disagreement(rotation_allowed / 2, 3 * translation_allowed, false), config), 0.5);
  config.verification.odometry_rotation = 0.0;
  EXPECT_EQ(odometryExcess(disagreement(90.0, 0.0, false), config), 0.0) << "no check runs";
}

TEST(AcceptanceRule, ConsistencyNeedsOneSupportMoreForAContradictedLoop) {
  Config config;
  config.consistency_min_support = 2;
  EXPECT_EQ(requiredSupport(false, config), 2);
  EXPECT_EQ(requiredSupport(true, config), 3);
  const Verdict v = unsupportedVerdict(1, true, config);
  expectRejection(v, RejectionTest::kConsistency, 1.0, 3.0);
  EXPECT_EQ(v.reason, "no consistent loop within consistency_window keyframes");
  EXPECT_FALSE(v.needs_support || v.odometry_contradicted) << "nothing can confirm it any more";
}

TEST(AcceptanceRule, AVerdictIsRecordedInTheResultAsItIs) {
  VerificationResult r = passing();
  r.record(judgeOdometry(disagreement(30.0, 0.0, false), true, Config()).value());
  EXPECT_FALSE(r.accepted);
  EXPECT_TRUE(r.odometry_contradicted);
  EXPECT_EQ(r.rejected_by, "odometry_rotation");
  EXPECT_EQ(r.rejection_value, 30.0);
  EXPECT_EQ(r.rejection_limit, 12.0);
  EXPECT_NE(r.reason.find("rotation disagrees"), std::string::npos);
  r.record(Verdict());
  EXPECT_TRUE(r.accepted);
  EXPECT_TRUE(r.reason.empty() && r.rejected_by.empty());
  EXPECT_FALSE(r.odometry_contradicted || r.needs_support);
  EXPECT_EQ(r.rejection_value, 0.0);
  EXPECT_EQ(r.rejection_limit, 0.0);
}

}  // namespace
}  // namespace scan_context_loop
