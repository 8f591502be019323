#include "scan_context_loop/core/config.h"

#include "scan_context_loop/core/settings.h"

#include <cmath>
#include <sstream>

namespace scan_context_loop {

namespace {

/// The text names of an enum's values, for parsing and printing.
template <typename E>
struct Named {
  const char* name;
  E value;
};

template <typename E, std::size_t N>
bool parseNamed(const Named<E> (&names)[N], const std::string& text, E* out) {
  for (const auto& n : names) {
    if (text == n.name) {
      *out = n.value;
      return true;
    }
  }
  return false;
}

template <typename E, std::size_t N>
const char* nameOf(const Named<E> (&names)[N], E value) {
  for (const auto& n : names) {
    if (n.value == value) return n.name;
  }
  return names[0].name;
}

const Named<RingKeyType> kRingKeys[] = {{"mean_height", RingKeyType::kMeanHeight},
                                        {"occupancy", RingKeyType::kOccupancy}};
const Named<RegistrationMethod> kMethods[] = {{"vgicp", RegistrationMethod::kVgicp},
                                              {"gicp", RegistrationMethod::kGicp},
                                              {"icp", RegistrationMethod::kIcp},
                                              {"ndt", RegistrationMethod::kNdt}};
const Named<GravityAlignmentMode> kGravityAlignment[] = {{"auto", GravityAlignmentMode::kAuto},
                                                         {"pose", GravityAlignmentMode::kPose},
                                                         {"ground", GravityAlignmentMode::kGround},
                                                         {"off", GravityAlignmentMode::kOff}};

}  // namespace

bool parseRingKeyType(const std::string& text, RingKeyType* out) { return parseNamed(kRingKeys, text, out); }
const char* ringKeyTypeName(RingKeyType type) { return nameOf(kRingKeys, type); }
bool parseRegistrationMethod(const std::string& text, RegistrationMethod* out) {
  return parseNamed(kMethods, text, out);
}
const char* registrationMethodName(RegistrationMethod method) { return nameOf(kMethods, method); }
bool parseGravityAlignmentMode(const std::string& text, GravityAlignmentMode* out) {
  return parseNamed(kGravityAlignment, text, out);
}
const char* gravityAlignmentModeName(GravityAlignmentMode mode) { return nameOf(kGravityAlignment, mode); }

namespace {

/// Rules that tie two verification settings together.
void checkVerificationPairs(const VerificationConfig& v, std::vector<std::string>* e) {
  if (!(v.supported_inlier_ratio <= v.min_inlier_ratio)) {
    e->push_back("verify_supported_inlier_ratio must not exceed verify_min_inlier_ratio");
  }
  if (!(v.supported_column_overlap <= v.min_column_overlap)) {
    e->push_back("verify_supported_column_overlap must not exceed verify_min_column_overlap");
  }
  if (!(v.supported_max_violation >= v.max_violation)) {
    e->push_back("verify_supported_max_violation must not be below verify_max_violation");
  }
}

/// The verification internals that have no key.
void checkVerificationInternals(const VerificationConfig& v, std::vector<std::string>* e) {
  const auto positive = [&](double x, const char* name) {
    if (!(std::isfinite(x) && x > 0.0)) e->push_back(std::string(name) + " must be a positive number");
  };
  positive(v.search_cell, "search_cell");
  positive(v.coarse_correspondence, "coarse_correspondence");
  positive(v.fine_correspondence, "fine_correspondence");
  positive(v.inlier_distance, "inlier_distance");
  positive(v.inlier_plane_distance, "inlier_plane_distance");
  positive(v.ndt_resolution, "ndt_resolution");
  positive(v.min_translation_variance, "min_translation_variance");
  positive(v.min_rotation_variance, "min_rotation_variance");
  if (!(std::isfinite(v.search_radius) && v.search_radius >= 0.0)) e->push_back("search_radius must be >= 0");
  if (v.min_structure < 3) e->push_back("min_structure must be >= 3");
  if (v.max_iterations < 1) e->push_back("max_iterations must be >= 1");
  if (v.max_hypotheses < 1) e->push_back("max_hypotheses must be >= 1");
  if (v.max_source_voxels < 10) e->push_back("max_source_voxels must be >= 10");
  if (!(v.hypothesis_ratio >= 0.0 && v.hypothesis_ratio <= 1.0)) e->push_back("hypothesis_ratio must be in [0, 1]");
  if (!(v.min_constraint_ratio >= 0.0 && v.min_constraint_ratio <= 1.0)) {
    e->push_back("min_constraint_ratio must be in [0, 1]");
  }
}

}  // namespace

std::vector<std::string> VerificationConfig::validate() const {
  // The keyed settings through the table (the verify_* rows), then the pairs and the internals.
  Config holder;
  holder.verification = *this;
  std::vector<std::string> e;
  for (const auto& s : configSettings()) {
    if (s.key.rfind("verify", 0) != 0) continue;
    const std::string rule = s.check(holder);
    if (!rule.empty()) e.push_back(s.key + " = " + s.get(holder) + ": " + rule);
  }
  checkVerificationPairs(*this, &e);
  checkVerificationInternals(*this, &e);
  return e;
}

std::vector<std::string> Config::validate() const {
  std::vector<std::string> e = checkSettings(configSettings(), *this);
  if (std::isfinite(min_range) && std::isfinite(max_radius) && !(min_range < max_radius)) {
    e.push_back("min_range must be below max_radius");
  }
  if (lateral_offset_step > max_radius) e.push_back("lateral_offset_step must not exceed max_radius");
  checkVerificationPairs(verification, &e);
  checkVerificationInternals(verification, &e);
  return e;
}

const std::vector<std::string>& configKeys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k;
    for (const auto& s : configSettings()) k.push_back(s.key);
    return k;
  }();
  return keys;
}

bool setConfigValue(Config* config, const std::string& key, const std::string& value, std::string* error,
                    std::string* warning) {
  const Setting<Config>* setting = findSetting(configSettings(), key, warning);
  if (setting == nullptr) {
    if (error) *error = "unknown configuration key '" + key + "'";
    return false;
  }
  Config c = *config;
  if (!setting->set(&c, value)) {
    if (error) *error = key + ": cannot read '" + value + "' as " + settingTypeName(setting->type, setting->choices);
    return false;
  }
  *config = c;
  return true;
}

int Config::searchHalfWidth() const {
  if (search_ratio >= 1.0) return num_sectors / 2;
  return static_cast<int>(std::lround(search_ratio * 0.5 * num_sectors));
}

}  // namespace scan_context_loop
