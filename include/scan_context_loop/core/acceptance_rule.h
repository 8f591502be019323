// The acceptance rule: every test that accepts or turns down a loop candidate, in one place.
//
// The stages before it measure: registration (verification.h) refines the pose and measures the
// overlap, the free-space violation, the fitness and how well the scene constrains the pose; the detector
// measures how far the registered loop is from what the odometry predicts (odometry_trust.h); the
// consistency check (consistency.h) counts the loops that agree with it. The rule compares those
// measurements with the configured limits and gives a Verdict: accepted, or the test that failed with the
// value it measured and the limit that value broke. The verdict is recorded in the candidate's
// VerificationResult (VerificationResult::record), which the evaluation and the LoopClosure message copy
// as they are: nothing downstream works a rejection out again.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace scan_context_loop {

struct Config;
struct VerificationConfig;
struct VerificationResult;

/// The tests, in the order they run: no registration data, too little structure, registration failed
/// (no number), the overlap, the free-space violation, the fitness, a degenerate constraint, the rotation
/// and the translation against the odometry, and after verification the consistency check.
enum class RejectionTest {
  kNone,  ///< accepted
  kUnverifiable,
  kStructure,
  kRegistration,
  kOverlap,
  kFreeSpace,
  kFitness,
  kDegenerate,
  kOdometryRotation,
  kOdometryTranslation,
  kConsistency,
};

/// The tests' names (VerificationResult::rejected_by, the LoopClosure message's rejected_by, the
/// evaluation's counts), in RejectionTest's order without kNone.
extern const char* const kRejectionTests[10];
/// The name of `test`; "" for kNone.
const char* rejectionTestName(RejectionTest test);

/// What the rule decided of a candidate.
struct Verdict {
  RejectionTest test = RejectionTest::kNone;
  /// The value the failed test measured and the limit it broke (both 0 for a test without a number).
  double value = 0.0, limit = 0.0;
  /// Why it was turned down, for people; "" when accepted.
  std::string reason;
  /// Turned down, but only by the overlap or the free-space test within their support floors: a
  /// confirmed loop that passed in full may still confirm it (ConsistencyFilter).
  bool needs_support = false;
  /// Turned down by the odometry checks only, after passing every other test in full: the odometry may
  /// have broken down, so the consistency check may still confirm it with one support more.
  bool odometry_contradicted = false;

  bool accepted() const { return test == RejectionTest::kNone; }
};

// ---- before and during registration ----------------------------------------------------------------

/// The candidate's registration data were dropped (CloudStore) to stay within verify_max_bytes.
Verdict unverifiableVerdict();
/// Both keyframes need at least VerificationConfig::min_structure vertical-structure voxels.
Verdict judgeStructure(std::size_t query_voxels, std::size_t match_voxels, const VerificationConfig& config);
/// Registration itself failed (`why`: no correspondences, diverged, ...): a rejection without a number.
Verdict registrationFailure(const std::string& why);
/// Whether the registered roll and pitch are kept: a tilt between the two gravity-aligned frames above
/// VerificationConfig::registration_max_tilt_deg is not trusted (the registration then holds roll and pitch
/// at the gravity alignment's).
bool trustsRegisteredTilt(double tilt_deg, const VerificationConfig& config);
/// Whether the column overlap can change the verdict of a registration with this voxel overlap (it is
/// measured only then): the voxel overlap falls short of its full floor and the column overlap is used.
bool columnOverlapCanDecide(double inlier_ratio, const VerificationConfig& config);
/// The column overlap below which it decides nothing (its support floor): measuring may stop once the
/// overlap can no longer reach it, and the second direction is measured only when the first reaches it.
double columnOverlapFloor(const VerificationConfig& config);

// ---- after registration ------------------------------------------------------------------------------

/// The registration's measurements (overlaps, violations, fitness, constraint ratio of `measured`)
/// against the limits, in this order: overlap and free space at their support floors, fitness,
/// degeneracy, then overlap and free space at their full floors (failing only those needs support).
Verdict judgeRegistration(const VerificationResult& measured, const VerificationConfig& config);

/// How a registered loop compares with what the odometry predicts of it (LoopDetector::checkOdometry).
struct OdometryDisagreement {
  double rotation_deg = 0.0;   ///< angle between the registered and the predicted rotation
  double translation_m = 0.0;  ///< distance between the registered and the predicted translation
  double path = 0.0;           ///< odometry path the prediction relies on [m]
  bool anchored = false;       ///< predicted through a confirmed loop (OdometryPrediction::anchored)
  /// Translation drift per metre of path the odometry is allowed (allowedDriftRate, odometry_trust.h).
  double drift_rate = 0.0;
};

/// The rotation disagreement allowed over `path` metres of odometry [deg]: odometry_rotation plus
/// odometry_rotation_drift per metre.
double rotationAllowance(const VerificationConfig& config, double path);
/// How far a registered loop may place the candidate from where the odometry, relied on from a
/// confirmed loop over `path` metres, puts it [m]: consistency_translation plus `drift_rate` per metre.
double anchoredTranslationAllowance(const Config& config, double drift_rate, double path);
/// The largest rotation disagreement [deg] an odometry failure plausibly explains over `path` metres of
/// odometry: a jump of kPlausibleJumpDeg plus kPlausibleTurnRate per metre (A-LOAM's heading broke by
/// 0.1-0.25 deg/m). A registration that disagrees by more is a wrong one: just after a confirmed loop,
/// a run of loops 180 degrees off is not an odometry that broke.
constexpr double kPlausibleJumpDeg = 45.0;
constexpr double kPlausibleTurnRate = 0.25;
inline double plausibleRotationBreak(double path) { return kPlausibleJumpDeg + kPlausibleTurnRate * path; }

/// The odometry checks' largest disagreement over what they allow (below 1: they pass; 0: none runs).
/// The rotation is checked when VerificationConfig::odometry_rotation > 0, the translation when the
/// prediction is anchored and Config::gate_odometry_distance > 0.
double odometryExcess(const OdometryDisagreement& d, const Config& config);
/// The odometry checks of a loop registration accepted or found to need support (`passed_in_full`: it
/// was accepted): nothing when they pass, else a rejection by the rotation (checked first) or the
/// translation. One that passed in full and whose disagreement an odometry failure explains keeps a way
/// back (Verdict::odometry_contradicted) while the consistency check is on.
std::optional<Verdict> judgeOdometry(const OdometryDisagreement& d, bool passed_in_full, const Config& config);

// ---- consistency -------------------------------------------------------------------------------------

/// The agreeing loops a loop needs to be confirmed: Config::consistency_min_support, one more for one the
/// odometry contradicted (Verdict::odometry_contradicted).
int requiredSupport(bool odometry_contradicted, const Config& config);
/// The verdict on a loop whose consistency_window ended before it was confirmed, with the support it had.
Verdict unsupportedVerdict(int support, bool odometry_contradicted, const Config& config);

}  // namespace scan_context_loop
