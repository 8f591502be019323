#include "fuzz_input.h"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace scan_context_loop::fuzz {

double FuzzBytes::number() {
  const std::uint8_t selector = take<std::uint8_t>();
  switch (selector % 3) {
    case 0:
      return take<double>();
    case 1:
      return take<std::int16_t>() / 256.0;
    default: {
      constexpr double kSpecial[] = {0.0,
                                     std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::max(),
                                     std::numeric_limits<double>::denorm_min(),
                                     1e300};
      return kSpecial[take<std::uint8_t>() % (sizeof(kSpecial) / sizeof(kSpecial[0]))];
    }
  }
}

std::vector<std::uint8_t> FuzzBytes::rest() {
  const std::size_t n = in_.remaining();
  const std::uint8_t* p = in_.take(n);
  return p ? std::vector<std::uint8_t>(p, p + n) : std::vector<std::uint8_t>();
}

Config smallConfig(std::uint8_t choice) {
  Config config;
  config.num_rings = 5;
  config.num_sectors = 12;
  config.max_radius = 20.0;
  config.exclude_recent_frames = 0;
  config.verification.voxel_leaf = 2.0;
  config.verification.max_range = 10.0;
  // The grid of 2 m voxels within 10 m has room for a few dozen structure voxels, not the default 150:
  // with this floor the fixed cloud (and clouds like it) reach the registration and its acceptance tests.
  config.verification.min_structure = 12;
  config.cloud_in_world_frame = (choice & 1) != 0;
  constexpr GravityAlignmentMode kModes[] = {GravityAlignmentMode::kAuto, GravityAlignmentMode::kPose,
                                             GravityAlignmentMode::kGround, GravityAlignmentMode::kOff};
  config.gravity_alignment = kModes[(choice >> 1) & 3];
  config.verification.enabled = (choice & 8) != 0;
  if (choice & 16) {
    config.accumulate_seconds = 2.0;
    config.accumulate_distance = 5.0;
  }
  if (choice & 32) {
    config.keyframe_min_distance = 0.5;
    config.keyframe_min_angle = 5.0;
  }
  if (choice & 64) config.voxel_leaf = 0.5;
  if (choice & 128) config.ring_key = RingKeyType::kOccupancy;
  // A harness whose configuration is refused tests nothing: stop at once.
  if (!config.validate().empty()) std::abort();
  return config;
}

PointView fixedCloud() {
  // Three walls (y = 6, x = -7, y = -5 over half its length) 3 m high, a point every 0.5 m, and a
  // wavy ground: enough vertical structure in 2 m voxels for verification to register it.
  static const std::vector<float> points = [] {
    std::vector<float> p;
    for (int i = 0; i < 32; ++i) {
      const float t = 0.5f * static_cast<float>(i) - 8.0f;
      for (int k = 0; k < 7; ++k) {
        const float z = 0.5f * static_cast<float>(k) - 1.5f;
        p.insert(p.end(), {t, 6.0f, z});
        p.insert(p.end(), {-7.0f, t, z});
        if (t > 0.0f) p.insert(p.end(), {t, -5.0f, z});
      }
      p.insert(p.end(), {t, 0.0f, -1.8f + 0.1f * std::sin(t)});
    }
    return p;
  }();
  PointView view;
  view.data = reinterpret_cast<const std::uint8_t*>(points.data());
  view.count = points.size() / 3;
  view.stride = 3 * sizeof(float);
  return view;
}

}  // namespace scan_context_loop::fuzz
