#include "scan_context_loop/core/acceptance_rule.h"

#include <algorithm>
#include <sstream>
#include <utility>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {

const char* const kRejectionTests[10] = {"unverifiable",         "structure",  "registration", "overlap",
                                         "free_space",           "fitness",    "degenerate",   "odometry_rotation",
                                         "odometry_translation", "consistency"};

const char* rejectionTestName(RejectionTest test) {
  return test == RejectionTest::kNone ? "" : kRejectionTests[static_cast<int>(test) - 1];
}

namespace {

Verdict rejection(RejectionTest test, double value, double limit, std::string reason) {
  Verdict v;
  v.test = test;
  v.value = value;
  v.limit = limit;
  v.reason = std::move(reason);
  return v;
}

}  // namespace

Verdict unverifiableVerdict() {
  return rejection(RejectionTest::kUnverifiable, 0.0, 0.0,
                   "unverifiable: the candidate's cloud was dropped to stay within verify_max_bytes");
}

Verdict judgeStructure(std::size_t query_voxels, std::size_t match_voxels, const VerificationConfig& config) {
  const auto need = static_cast<std::size_t>(config.min_structure);
  if (query_voxels >= need && match_voxels >= need) return Verdict();
  std::ostringstream why;
  why << "too few points to verify: structure voxels (query " << query_voxels << ", candidate " << match_voxels
      << ", need " << config.min_structure << ")";
  return rejection(RejectionTest::kStructure, static_cast<double>(std::min(query_voxels, match_voxels)),
                   config.min_structure, why.str());
}

Verdict registrationFailure(const std::string& why) { return rejection(RejectionTest::kRegistration, 0.0, 0.0, why); }

bool trustsRegisteredTilt(double tilt_deg, const VerificationConfig& config) {
  return !(tilt_deg > config.registration_max_tilt_deg);
}

bool columnOverlapCanDecide(double inlier_ratio, const VerificationConfig& config) {
  return inlier_ratio < config.min_inlier_ratio && config.supported_column_overlap < 1.0;
}

double columnOverlapFloor(const VerificationConfig& config) { return config.supported_column_overlap; }

Verdict judgeRegistration(const VerificationResult& r, const VerificationConfig& config) {
  Verdict v;
  std::ostringstream why;
  const auto reject = [&v, &why](RejectionTest test, double value, double limit) {
    v.test = test;
    v.value = value;
    v.limit = limit;
    return &why;
  };
  // The overlap passes when either the voxel overlap or the column overlap (where used) reaches its floor.
  const auto reaches = [&r](double voxel_floor, double column_floor) {
    return r.inlier_ratio >= voxel_floor || (column_floor < 1.0 && r.column_overlap >= column_floor);
  };
  if (!reaches(config.supported_inlier_ratio, config.supported_column_overlap)) {
    *reject(RejectionTest::kOverlap, r.inlier_ratio, config.supported_inlier_ratio)
        << "inlier ratio (structure overlap) " << r.inlier_ratio << " below " << config.supported_inlier_ratio
        << " (query " << r.overlap_query << ", candidate " << r.overlap_match << ") and column overlap "
        << r.column_overlap << " below " << config.supported_column_overlap;
  } else if (r.violation > config.supported_max_violation) {
    *reject(RejectionTest::kFreeSpace, r.violation, config.supported_max_violation)
        << "free-space violation " << r.violation << " above " << config.supported_max_violation << " (query "
        << r.violation_query << ", candidate " << r.violation_match << ")";
  } else if (!(r.fitness <= config.max_fitness)) {
    *reject(RejectionTest::kFitness, r.fitness, config.max_fitness)
        << "fitness " << r.fitness << " m^2 above " << config.max_fitness;
  } else if (!config.allow_degenerate && r.constraint_ratio < config.min_constraint_ratio) {
    *reject(RejectionTest::kDegenerate, r.constraint_ratio, config.min_constraint_ratio)
        << "degenerate: the position along one horizontal direction is unconstrained (ratio " << r.constraint_ratio
        << " below " << config.min_constraint_ratio << ")";
  } else if (!reaches(config.min_inlier_ratio, config.min_column_overlap)) {
    v.needs_support = true;
    *reject(RejectionTest::kOverlap, r.inlier_ratio, config.min_inlier_ratio)
        << "needs support: inlier ratio (structure overlap) " << r.inlier_ratio << " below " << config.min_inlier_ratio
        << " (query " << r.overlap_query << ", candidate " << r.overlap_match << ") and column overlap "
        << r.column_overlap << " below " << config.min_column_overlap;
  } else if (r.violation > config.max_violation) {
    v.needs_support = true;
    *reject(RejectionTest::kFreeSpace, r.violation, config.max_violation)
        << "needs support: free-space violation " << r.violation << " above " << config.max_violation << " (query "
        << r.violation_query << ", candidate " << r.violation_match << ")";
  }
  v.reason = why.str();
  return v;
}

double rotationAllowance(const VerificationConfig& config, double path) {
  return config.odometry_rotation + config.odometry_rotation_drift * path;
}

double anchoredTranslationAllowance(const Config& config, double drift_rate, double path) {
  return config.consistency_translation + drift_rate * path;
}

namespace {

bool checksRotation(const Config& config) { return config.verification.odometry_rotation > 0.0; }
// Only from a confirmed loop does the odometry place the candidate well (the candidate gate allows for
// the direct odometry's drift): a registration off by a building's length in a street of identical
// houses is caught there.
bool checksTranslation(const OdometryDisagreement& d, const Config& config) {
  return d.anchored && config.gate_odometry_distance > 0.0;
}

}  // namespace

double odometryExcess(const OdometryDisagreement& d, const Config& config) {
  const double rotation_allowed = rotationAllowance(config.verification, d.path);
  const double translation_allowed = anchoredTranslationAllowance(config, d.drift_rate, d.path);
  return std::max(checksRotation(config) ? d.rotation_deg / rotation_allowed : 0.0,
                  checksTranslation(d, config) ? d.translation_m / translation_allowed : 0.0);
}

std::optional<Verdict> judgeOdometry(const OdometryDisagreement& d, bool passed_in_full, const Config& config) {
  const double rotation_allowed = rotationAllowance(config.verification, d.path);
  const double translation_allowed = anchoredTranslationAllowance(config, d.drift_rate, d.path);
  Verdict v;
  if (checksRotation(config) && d.rotation_deg > rotation_allowed) {
    v = rejection(RejectionTest::kOdometryRotation, d.rotation_deg, rotation_allowed,
                  "rotation disagrees with the odometry by " + std::to_string(d.rotation_deg) + " deg");
  } else if (checksTranslation(d, config) && d.translation_m > translation_allowed) {
    v = rejection(RejectionTest::kOdometryTranslation, d.translation_m, translation_allowed,
                  "translation disagrees with the odometry by " + std::to_string(d.translation_m) + " m");
  } else {
    return std::nullopt;
  }
  v.reason += " (allowed " + std::to_string(v.limit) + " over " + std::to_string(d.path) + " m of odometry" +
              (d.anchored ? " from a confirmed loop" : "") + ")";
  // A registration that passed every test in full may be a true loop of an odometry that broke down:
  // the consistency check can still confirm it, with one support more than usual. One that needed
  // support already is rejected, and so is one turned further than a failure explains over the path.
  const bool plausible = v.test != RejectionTest::kOdometryRotation || d.rotation_deg <= plausibleRotationBreak(d.path);
  v.odometry_contradicted = passed_in_full && config.consistency_min_support > 0 && plausible;
  return v;
}

int requiredSupport(bool odometry_contradicted, const Config& config) {
  return config.consistency_min_support + (odometry_contradicted ? 1 : 0);
}

Verdict unsupportedVerdict(int support, bool odometry_contradicted, const Config& config) {
  return rejection(RejectionTest::kConsistency, support, requiredSupport(odometry_contradicted, config),
                   "no consistent loop within consistency_window keyframes");
}

}  // namespace scan_context_loop
