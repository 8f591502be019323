#include "scan_context_loop/config.h"

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

const Named<RingKeyType> kRingKeys[] = {{"mean_height", RingKeyType::kMeanHeight}, {"occupancy", RingKeyType::kOccupancy}};
const Named<RegistrationMethod> kMethods[] = {{"vgicp", RegistrationMethod::kVgicp},
                                              {"gicp", RegistrationMethod::kGicp},
                                              {"icp", RegistrationMethod::kIcp},
                                              {"ndt", RegistrationMethod::kNdt}};
const Named<LevellingMode> kLevelling[] = {{"auto", LevellingMode::kAuto},
                                           {"pose", LevellingMode::kPose},
                                           {"ground", LevellingMode::kGround},
                                           {"off", LevellingMode::kOff}};

}  // namespace

bool parseRingKeyType(const std::string& text, RingKeyType* out) { return parseNamed(kRingKeys, text, out); }
const char* ringKeyTypeName(RingKeyType type) { return nameOf(kRingKeys, type); }
bool parseRegistrationMethod(const std::string& text, RegistrationMethod* out) { return parseNamed(kMethods, text, out); }
const char* registrationMethodName(RegistrationMethod method) { return nameOf(kMethods, method); }
bool parseLevellingMode(const std::string& text, LevellingMode* out) { return parseNamed(kLevelling, text, out); }
const char* levellingModeName(LevellingMode mode) { return nameOf(kLevelling, mode); }

namespace {

template <typename T>
void require(std::vector<std::string>* errors, bool ok, const char* name, T value, const char* rule) {
  if (ok) return;
  std::ostringstream msg;
  msg << name << " = " << value << ": " << rule;
  errors->push_back(msg.str());
}

}  // namespace

std::vector<std::string> Config::validate() const {
  std::vector<std::string> e;
  require(&e, num_rings >= 1 && num_rings <= 1000, "num_rings", num_rings, "must be in [1, 1000]");
  require(&e, num_sectors >= 3 && num_sectors <= 3600, "num_sectors", num_sectors,
          "must be in [3, 3600]");
  require(&e, std::isfinite(max_radius) && max_radius > 0.0, "max_radius", max_radius,
          "must be a finite positive range in metres");
  require(&e, std::isfinite(min_range) && min_range >= 0.0 && min_range < max_radius, "min_range",
          min_range, "must be finite, >= 0 and below max_radius");
  require(&e, std::isfinite(lidar_height), "lidar_height", lidar_height, "must be finite");
  require(&e, std::isfinite(levelling_max_tilt) && levelling_max_tilt >= 0.0 && levelling_max_tilt <= 90.0,
          "levelling_max_tilt", levelling_max_tilt, "must be in [0, 90] degrees");
  require(&e, num_candidates >= 1 && num_candidates <= 10000, "num_candidates", num_candidates,
          "must be in [1, 10000]");
  require(&e, std::isfinite(search_ratio) && search_ratio >= 0.0 && search_ratio <= 1.0,
          "search_ratio", search_ratio, "must be in [0, 1]");
  require(&e, std::isfinite(distance_threshold) && distance_threshold > 0.0 && distance_threshold <= 2.0,
          "distance_threshold", distance_threshold, "must be in (0, 2]");
  require(&e, std::isfinite(lateral_offset_step) && lateral_offset_step >= 0.0 && lateral_offset_step <= max_radius,
          "lateral_offset_step", lateral_offset_step, "must be in [0, max_radius] (0 disables)");
  require(&e, lateral_offset_count >= 1 && lateral_offset_count <= 10, "lateral_offset_count", lateral_offset_count,
          "must be in [1, 10]");
  require(&e, exclude_recent_frames >= 0, "exclude_recent_frames", exclude_recent_frames,
          "must be >= 0 (0 disables)");
  require(&e, std::isfinite(exclude_recent_seconds) && exclude_recent_seconds >= 0.0,
          "exclude_recent_seconds", exclude_recent_seconds, "must be finite and >= 0 (0 disables)");
  require(&e, std::isfinite(exclude_recent_distance) && exclude_recent_distance >= 0.0,
          "exclude_recent_distance", exclude_recent_distance, "must be finite and >= 0 (0 disables)");
  require(&e, std::isfinite(gate_odometry_distance) && gate_odometry_distance >= 0.0, "gate_odometry_distance",
          gate_odometry_distance, "must be finite and >= 0 (0 disables)");
  require(&e, std::isfinite(gate_odometry_drift) && gate_odometry_drift >= 0.0, "gate_odometry_drift",
          gate_odometry_drift, "must be finite and >= 0 (0 disables)");
  require(&e, std::isfinite(verify_threshold) && verify_threshold > 0.0 && verify_threshold <= 2.0,
          "verify_threshold", verify_threshold, "must be in (0, 2]");
  require(&e, verify_max_candidates >= 1 && verify_max_candidates <= 100, "verify_max_candidates",
          verify_max_candidates, "must be in [1, 100]");
  require(&e, std::isfinite(verify_max_bytes) && verify_max_bytes >= 1e6, "verify_max_bytes", verify_max_bytes,
          "must be at least 1e6 bytes");
  require(&e, std::isfinite(verify_voxel_leaf) && verify_voxel_leaf > 0.0, "verify_voxel_leaf", verify_voxel_leaf,
          "must be positive");
  require(&e, std::isfinite(verify_max_range) && verify_max_range > 0.0, "verify_max_range", verify_max_range,
          "must be positive");
  require(&e, verify_min_inlier_ratio >= 0.0 && verify_min_inlier_ratio <= 1.0, "verify_min_inlier_ratio",
          verify_min_inlier_ratio, "must be in [0, 1]");
  require(&e, verify_supported_inlier_ratio >= 0.0 && verify_supported_inlier_ratio <= verify_min_inlier_ratio,
          "verify_supported_inlier_ratio", verify_supported_inlier_ratio, "must be in [0, verify_min_inlier_ratio]");
  require(&e, std::isfinite(verify_max_fitness) && verify_max_fitness > 0.0, "verify_max_fitness",
          verify_max_fitness, "must be positive");
  require(&e, std::isfinite(verify_odometry_rotation) && verify_odometry_rotation >= 0.0, "verify_odometry_rotation",
          verify_odometry_rotation, "must be >= 0 degrees (0 disables)");
  require(&e, std::isfinite(verify_odometry_rotation_drift) && verify_odometry_rotation_drift >= 0.0,
          "verify_odometry_rotation_drift", verify_odometry_rotation_drift, "must be >= 0 degrees per metre");
  require(&e, verify_submap >= 0 && verify_submap <= 20, "verify_submap", verify_submap, "must be in [0, 20]");
  require(&e, verify_max_violation >= 0.0 && verify_max_violation <= 1.0, "verify_max_violation",
          verify_max_violation, "must be in [0, 1]");
  require(&e, verify_supported_max_violation >= verify_max_violation && verify_supported_max_violation <= 1.0,
          "verify_supported_max_violation", verify_supported_max_violation, "must be in [verify_max_violation, 1]");
  require(&e, consistency_min_support >= 0 && consistency_min_support <= 100, "consistency_min_support",
          consistency_min_support, "must be in [0, 100] (0 disables)");
  require(&e, consistency_window >= 1 && consistency_window <= 100000, "consistency_window", consistency_window,
          "must be in [1, 100000]");
  require(&e, std::isfinite(consistency_translation) && consistency_translation > 0.0, "consistency_translation",
          consistency_translation, "must be positive");
  require(&e, std::isfinite(consistency_rotation) && consistency_rotation > 0.0, "consistency_rotation",
          consistency_rotation, "must be positive");
  require(&e, std::isfinite(consistency_drift) && consistency_drift >= 0.0, "consistency_drift", consistency_drift,
          "must be >= 0");
  return e;
}

namespace {

bool parseBool(const std::string& text, bool* out) {
  if (text == "true" || text == "1") {
    *out = true;
    return true;
  }
  if (text == "false" || text == "0") {
    *out = false;
    return true;
  }
  return false;
}

bool parseInt(const std::string& text, int* out) {
  std::istringstream in(text);
  long long v;
  char extra;
  if (!(in >> v) || (in >> extra) || v < -2147483647LL || v > 2147483647LL) return false;
  *out = static_cast<int>(v);
  return true;
}

bool parseDouble(const std::string& text, double* out) {
  std::istringstream in(text);
  double v;
  char extra;
  if (!(in >> v) || (in >> extra)) return false;
  *out = v;
  return true;
}

}  // namespace

const std::vector<std::string>& configKeys() {
  static const std::vector<std::string> keys = {
      "num_rings",      "num_sectors",        "max_radius",           "min_range",
      "lidar_height",   "ring_key", "levelling", "levelling_max_tilt",           "num_candidates",       "search_ratio",
      "distance_threshold", "lateral_offset_step", "lateral_offset_count", "exclude_recent_frames", "exclude_recent_seconds", "exclude_recent_distance",
      "gate_odometry_distance", "gate_odometry_drift", "verify", "verify_threshold",   "verify_max_candidates", "verify_max_bytes",
      "verify_voxel_leaf", "verify_max_range", "verify_min_inlier_ratio", "verify_supported_inlier_ratio", "verify_max_fitness", "verify_max_violation", "verify_supported_max_violation",
      "verify_method", "verify_odometry_rotation", "verify_odometry_rotation_drift", "verify_submap", "verify_allow_degenerate", "consistency_min_support", "consistency_window", "consistency_translation",
      "consistency_rotation", "consistency_drift"};
  return keys;
}

bool setConfigValue(Config* config, const std::string& key, const std::string& value, std::string* error) {
  bool ok = true;
  Config c = *config;
  if (key == "num_rings") ok = parseInt(value, &c.num_rings);
  else if (key == "num_sectors") ok = parseInt(value, &c.num_sectors);
  else if (key == "max_radius") ok = parseDouble(value, &c.max_radius);
  else if (key == "min_range") ok = parseDouble(value, &c.min_range);
  else if (key == "lidar_height") ok = parseDouble(value, &c.lidar_height);
  else if (key == "ring_key") ok = parseRingKeyType(value, &c.ring_key);
  else if (key == "levelling") ok = parseLevellingMode(value, &c.levelling);
  else if (key == "levelling_max_tilt") ok = parseDouble(value, &c.levelling_max_tilt);
  else if (key == "num_candidates") ok = parseInt(value, &c.num_candidates);
  else if (key == "search_ratio") ok = parseDouble(value, &c.search_ratio);
  else if (key == "distance_threshold") ok = parseDouble(value, &c.distance_threshold);
  else if (key == "lateral_offset_step") ok = parseDouble(value, &c.lateral_offset_step);
  else if (key == "lateral_offset_count") ok = parseInt(value, &c.lateral_offset_count);
  else if (key == "exclude_recent_frames") ok = parseInt(value, &c.exclude_recent_frames);
  else if (key == "exclude_recent_seconds") ok = parseDouble(value, &c.exclude_recent_seconds);
  else if (key == "exclude_recent_distance") ok = parseDouble(value, &c.exclude_recent_distance);
  else if (key == "gate_odometry_distance") ok = parseDouble(value, &c.gate_odometry_distance);
  else if (key == "gate_odometry_drift") ok = parseDouble(value, &c.gate_odometry_drift);
  else if (key == "verify") ok = parseBool(value, &c.verify);
  else if (key == "verify_threshold") ok = parseDouble(value, &c.verify_threshold);
  else if (key == "verify_max_candidates") ok = parseInt(value, &c.verify_max_candidates);
  else if (key == "verify_max_bytes") ok = parseDouble(value, &c.verify_max_bytes);
  else if (key == "verify_voxel_leaf") ok = parseDouble(value, &c.verify_voxel_leaf);
  else if (key == "verify_max_range") ok = parseDouble(value, &c.verify_max_range);
  else if (key == "verify_supported_max_violation") ok = parseDouble(value, &c.verify_supported_max_violation);
  else if (key == "verify_min_inlier_ratio") ok = parseDouble(value, &c.verify_min_inlier_ratio);
  else if (key == "verify_supported_inlier_ratio") ok = parseDouble(value, &c.verify_supported_inlier_ratio);
  else if (key == "verify_max_fitness") ok = parseDouble(value, &c.verify_max_fitness);
  else if (key == "verify_max_violation") ok = parseDouble(value, &c.verify_max_violation);
  else if (key == "verify_method") ok = parseRegistrationMethod(value, &c.verify_method);
  else if (key == "verify_odometry_rotation") ok = parseDouble(value, &c.verify_odometry_rotation);
  else if (key == "verify_odometry_rotation_drift") ok = parseDouble(value, &c.verify_odometry_rotation_drift);
  else if (key == "verify_submap") ok = parseInt(value, &c.verify_submap);
  else if (key == "verify_allow_degenerate") ok = parseBool(value, &c.verify_allow_degenerate);
  else if (key == "consistency_min_support") ok = parseInt(value, &c.consistency_min_support);
  else if (key == "consistency_window") ok = parseInt(value, &c.consistency_window);
  else if (key == "consistency_translation") ok = parseDouble(value, &c.consistency_translation);
  else if (key == "consistency_rotation") ok = parseDouble(value, &c.consistency_rotation);
  else if (key == "consistency_drift") ok = parseDouble(value, &c.consistency_drift);
  else {
    if (error) *error = "unknown configuration key '" + key + "'";
    return false;
  }
  if (!ok) {
    if (error) *error = key + ": cannot read '" + value + "' as its value";
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
