#include "scan_context_sim/sensor.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace scan_context_loop {
namespace sim {

namespace {

std::vector<float> uniformBeams(int n, float top, float bottom) {
  std::vector<float> e(n);
  for (int i = 0; i < n; ++i) e[i] = top + (bottom - top) * i / (n - 1);
  return e;
}

float reflectivity(Material m) {
  switch (m) {
    case Material::kGround:
      return 0.2f;
    case Material::kPavement:
      return 0.28f;
    case Material::kBuilding:
      return 0.32f;
    case Material::kWall:
      return 0.3f;
    case Material::kCar:
      return 0.45f;
    case Material::kTrunk:
      return 0.22f;
    case Material::kFoliage:
      return 0.25f;
    case Material::kPole:
      return 0.5f;
    case Material::kSign:
      return 0.95f;
    case Material::kPerson:
      return 0.3f;
    case Material::kBranch:
      return 0.22f;
    case Material::kContainer:
      return 0.4f;
  }
  return 0.3f;
}

}  // namespace

bool sensorPreset(const std::string& name, SensorModel* model) {
  SensorModel m;
  m.name = name;
  if (name == "hdl64") {
    // Upper block: 32 beams from +2 to -8.33 deg (1/3 deg apart); lower block: 32 beams from -8.83 to
    // -24.9 deg (about 1/2 deg apart), as in the HDL-64E S2 that recorded KITTI.
    m.elevations_deg = uniformBeams(32, 2.0f, -8.33f);
    const auto lower = uniformBeams(32, -8.83f, -24.9f);
    m.elevations_deg.insert(m.elevations_deg.end(), lower.begin(), lower.end());
    m.columns = 2000;  // 0.18 deg at 10 Hz
    m.max_range = 100.0f;
    m.dim_range = 80.0f;
    m.mount_height = 1.73f;
    m.beam_divergence = 0.002f;  // 2.0 mrad
  } else if (name == "vlp16") {
    m.elevations_deg = uniformBeams(16, 15.0f, -15.0f);
    m.columns = 1800;  // 0.2 deg at 10 Hz
    m.max_range = 100.0f;
    m.dim_range = 65.0f;
    m.range_noise = 0.03f;
    m.mount_height = 1.73f;
    m.beam_divergence = 0.003f;  // 3.0 mrad
  } else if (name == "os1-64") {
    m.elevations_deg = uniformBeams(64, 16.6f, -16.6f);
    m.columns = 1024;
    m.max_range = 120.0f;
    m.dim_range = 55.0f;
    m.range_noise = 0.03f;
    m.mount_height = 1.73f;
    m.zeros_for_no_return = true;
  } else if (name == "livox-avia") {
    // 240,000 rays a second (first return) in a 70.4 x 77.2 deg rosette. dim_range 120 m, below the
    // specification's 190 m at 10 % reflectivity (ideal conditions); past Scan Context's 80 m either way.
    m.pattern = ScanPattern::kRosette;
    m.ray_rate = 240000.0;
    m.rays_per_scan = 24000;
    m.fov_horizontal_deg = 70.4f;
    m.fov_top_deg = 38.6f;
    m.fov_bottom_deg = -38.6f;
    // 150 petals a second: a 0.1 s scan covers under a third of the field of view in 1 deg cells, 0.5 s
    // 85 %, 1 s all of it; the pattern repeats only after 1000 s.
    m.pattern_hz[0] = 83.951;
    m.pattern_hz[1] = 66.047;
    m.max_range = 200.0f;
    m.dim_range = 120.0f;
    m.min_range = 1.0f;
  } else if (name == "livox-mid360") {
    // 200,000 rays a second over 360 x -7 to +52 deg; 40 m at 10 % reflectivity, 70 m at 80 %.
    m.pattern = ScanPattern::kSweep360;
    m.ray_rate = 200000.0;
    m.rays_per_scan = 20000;
    m.fov_top_deg = 52.0f;
    m.fov_bottom_deg = -7.0f;
    // Ten turns a second, about 27 elevation sweeps a turn: a 0.1 s scan covers a sixth of the field
    // of view in 1 deg cells, 0.5 s two thirds, 1 s 95 %; the pattern repeats only after 1000 s.
    m.pattern_hz[0] = 10.0;
    m.pattern_hz[1] = 271.317;
    m.max_range = 70.0f;
    m.dim_range = 40.0f;
    m.min_range = 0.1f;
  } else {
    return false;
  }
  *model = m;
  return true;
}

std::string sensorPresetNames() { return "hdl64 | vlp16 | os1-64 | livox-avia | livox-mid360"; }

float fovTopDeg(const SensorModel& sensor) {
  if (sensor.pattern != ScanPattern::kSpinning || sensor.elevations_deg.empty()) return sensor.fov_top_deg;
  return *std::max_element(sensor.elevations_deg.begin(), sensor.elevations_deg.end());
}

float fovBottomDeg(const SensorModel& sensor) {
  if (sensor.pattern != ScanPattern::kSpinning || sensor.elevations_deg.empty()) return sensor.fov_bottom_deg;
  return *std::min_element(sensor.elevations_deg.begin(), sensor.elevations_deg.end());
}

namespace {

/// Beam by beam within each column, as the spinning sensors fire.
std::vector<Eigen::Vector3f> spinningRays(const SensorModel& sensor) {
  std::vector<float> cos_e, sin_e;
  for (float e : sensor.elevations_deg) {
    cos_e.push_back(std::cos(e * static_cast<float>(M_PI) / 180.0f));
    sin_e.push_back(std::sin(e * static_cast<float>(M_PI) / 180.0f));
  }
  std::vector<Eigen::Vector3f> rays;
  rays.reserve(sensor.columns * sensor.elevations_deg.size());
  for (int c = 0; c < sensor.columns; ++c) {
    const float azimuth = 2.0f * static_cast<float>(M_PI) * c / sensor.columns;
    const float ca = std::cos(azimuth), sa = std::sin(azimuth);
    for (std::size_t b = 0; b < cos_e.size(); ++b) rays.emplace_back(cos_e[b] * ca, cos_e[b] * sa, sin_e[b]);
  }
  return rays;
}

/// The azimuth and elevation [deg] of a non-repetitive pattern at time t, from the two phases
/// a = 2 pi pattern_hz[0] t and b = 2 pi pattern_hz[1] t.
Eigen::Vector2d patternAngles(const SensorModel& sensor, double a, double b) {
  const double middle = 0.5 * (sensor.fov_top_deg + sensor.fov_bottom_deg);
  const double half_height = 0.5 * (sensor.fov_top_deg - sensor.fov_bottom_deg);
  if (sensor.pattern == ScanPattern::kRosette) {
    // Two prisms turning opposite ways: the deflection is the mean of two unit phasors, a rosette
    // whose petals run from the centre to the edge while the whole figure turns.
    const double x = 0.5 * (std::cos(a) + std::cos(b)), y = 0.5 * (std::sin(a) - std::sin(b));
    return {0.5 * sensor.fov_horizontal_deg * x, middle + half_height * y};
  }
  return {std::remainder(a * 180.0 / M_PI, 360.0), middle + half_height * std::sin(b)};
}

std::vector<Eigen::Vector3f> nonRepetitiveRays(const SensorModel& sensor, double time) {
  std::vector<Eigen::Vector3f> rays;
  rays.reserve(std::max(0, sensor.rays_per_scan));
  for (int i = 0; i < sensor.rays_per_scan; ++i) {
    const double t = time + i / sensor.ray_rate;
    const auto phase = [t](double hz) { return std::remainder(2.0 * M_PI * hz * t, 2.0 * M_PI); };
    const Eigen::Vector2d angles =
        patternAngles(sensor, phase(sensor.pattern_hz[0]), phase(sensor.pattern_hz[1])) * (M_PI / 180.0);
    rays.emplace_back(static_cast<float>(std::cos(angles.y()) * std::cos(angles.x())),
                      static_cast<float>(std::cos(angles.y()) * std::sin(angles.x())),
                      static_cast<float>(std::sin(angles.y())));
  }
  return rays;
}

}  // namespace

std::vector<Eigen::Vector3f> rayDirections(const SensorModel& sensor, double time) {
  if (sensor.pattern == ScanPattern::kSpinning) return spinningRays(sensor);
  return nonRepetitiveRays(sensor, time);
}

namespace {

/// The measured range of one ray, or 0 when it brings no return: nothing hit, lost (dropout), too dim
/// for its range, or out of the sensor's range.
float returnRange(const World& world, const SensorModel& sensor, const Eigen::Vector3f& origin,
                  const Eigen::Vector3f& direction, double time, std::uint32_t ray, std::vector<std::uint32_t>* visit,
                  Hit* hit, std::mt19937_64& rng, std::normal_distribution<float>& noise,
                  std::uniform_real_distribution<float>& unit) {
  if (!world.cast(origin, direction, sensor.max_range, time, ray, visit, hit)) return 0.0f;
  if (unit(rng) < sensor.dropout) return 0.0f;
  const float incidence = std::fabs(hit->normal.dot(direction));
  float reflectivity_seen = reflectivity(hit->material) * (0.3f + 0.7f * incidence);
  if (hit->material == Material::kBranch && hit->width > 0.0f) {
    // A limb narrower than the beam's footprint reflects only the share of it that it covers. Only
    // branches: the poles and bollards of the worlds before them keep their returns as they were.
    const float footprint = sensor.beam_divergence * hit->range;
    if (footprint > hit->width) reflectivity_seen *= hit->width / footprint;
  }
  if (sensor.dim_range > 0.0f) {
    // Detected with probability 1 / (1 + (range / reach)^8): near certain well inside the reach,
    // half at it, rare beyond.
    const float reach = sensor.dim_range * std::sqrt(reflectivity_seen / 0.1f);
    const float ratio2 = (hit->range / reach) * (hit->range / reach);
    const float ratio8 = ratio2 * ratio2 * ratio2 * ratio2;
    if (unit(rng) * (1.0f + ratio8) > 1.0f) return 0.0f;
  }
  const float range = hit->range + noise(rng);
  if (range < sensor.min_range || range > sensor.max_range) return 0.0f;
  return range;
}

}  // namespace

pcl::PointCloud<pcl::PointXYZI> scan(const World& world, const SensorModel& sensor,
                                     const Eigen::Isometry3d& world_from_sensor, double time, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, sensor.range_noise);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const Eigen::Matrix3f rotation = world_from_sensor.linear().cast<float>();
  const Eigen::Vector3f origin = world_from_sensor.translation().cast<float>();
  std::vector<std::uint32_t> visit(world.size(), 0);
  const std::vector<Eigen::Vector3f> rays = rayDirections(sensor, time);
  pcl::PointCloud<pcl::PointXYZI> cloud;
  cloud.reserve(rays.size());
  std::uint32_t ray = 0;
  Hit hit;
  for (const Eigen::Vector3f& local : rays) {
    const Eigen::Vector3f direction = rotation * local;
    ++ray;
    const float range = returnRange(world, sensor, origin, direction, time, ray, &visit, &hit, rng, noise, unit);
    if (!(range > 0.0f)) {
      if (sensor.zeros_for_no_return) cloud.push_back(pcl::PointXYZI(0.0f));
      continue;
    }
    const float incidence = std::fabs(hit.normal.dot(direction));
    pcl::PointXYZI p;
    p.x = local.x() * range;
    p.y = local.y() * range;
    p.z = local.z() * range;
    // Calibrated intensities depend on the surface more than on the angle.
    p.intensity = std::min(1.0f, reflectivity(hit.material) * (0.6f + 0.4f * incidence) + 0.04f * unit(rng));
    cloud.push_back(p);
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
  return cloud;
}

}  // namespace sim
}  // namespace scan_context_loop
