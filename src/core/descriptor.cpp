#include "scan_context_loop/descriptor.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace scan_context_loop {

namespace {

constexpr float kTwoPi = 6.28318530717958647692f;
constexpr float kPi = 3.14159265358979323846f;
constexpr float kHalfPi = 1.57079632679489661923f;

/// atan2(y, x) mapped to [0, 2 pi), max error about 1e-5 rad (a minimax polynomial for atan on [0, 1]),
/// several times faster than std::atan2; 1e-5 rad is far below a sector (0.1 rad at 60 sectors).
inline float azimuth(float x, float y) {
  const float ax = std::fabs(x);
  const float ay = std::fabs(y);
  const float hi = ax > ay ? ax : ay;
  const float lo = ax > ay ? ay : ax;
  const float t = hi > 0.0f ? lo / hi : 0.0f;
  const float t2 = t * t;
  float a = t * (0.99997726f +
                 t2 * (-0.33262347f + t2 * (0.19354346f + t2 * (-0.11643287f +
                                                                t2 * (0.05265332f + t2 * -0.01172120f)))));
  if (ay > ax) a = kHalfPi - a;
  if (x < 0.0f) a = kPi - a;
  if (y < 0.0f) a = kTwoPi - a;
  return a;
}

inline float loadFloat(const std::uint8_t* p) {
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

HeightGrid makeHeightGrid(const PointView& points, const Config& config) {
  const int rings = config.num_rings;
  const int sectors = config.num_sectors;
  const float min2 = static_cast<float>(config.min_range * config.min_range);
  const float max_r = static_cast<float>(config.max_radius);
  const float max2 = max_r * max_r;
  const float ring_scale = static_cast<float>(rings) / max_r;
  const float sector_scale = static_cast<float>(sectors) / kTwoPi;
  const float h0 = static_cast<float>(config.lidar_height);
  constexpr float kEmpty = -std::numeric_limits<float>::infinity();

  // Row-major scratch (ring, sector) so that one ring's sectors are contiguous while binning.
  std::vector<float> best(static_cast<std::size_t>(rings) * sectors, kEmpty);
  std::size_t used = 0;
  const std::uint8_t* base = points.data;
  for (std::size_t i = 0; i < points.count && base != nullptr; ++i) {
    const std::uint8_t* p = base + i * points.stride;
    const float x = loadFloat(p + points.offset_x);
    const float y = loadFloat(p + points.offset_y);
    const float z = loadFloat(p + points.offset_z);
    const float r2 = x * x + y * y;
    // NaN compares false, Inf exceeds max2: both fall out here.
    if (!(r2 >= min2 && r2 <= max2) || !std::isfinite(z)) continue;
    int ring = static_cast<int>(std::sqrt(r2) * ring_scale);
    if (ring >= rings) ring = rings - 1;
    int sector = static_cast<int>(azimuth(x, y) * sector_scale);
    if (sector >= sectors) sector = sectors - 1;
    float& cell = best[static_cast<std::size_t>(ring) * sectors + sector];
    const float h = z + h0;
    if (h > cell) cell = h;
    ++used;
  }

  HeightGrid grid;
  grid.heights.setZero(rings, sectors);
  grid.occupied.setZero(rings, sectors);
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < sectors; ++s) {
      const float v = best[static_cast<std::size_t>(r) * sectors + s];
      if (v != kEmpty) {
        grid.heights(r, s) = v;
        grid.occupied(r, s) = 1;
      }
    }
  }
  grid.points_used = used;
  grid.points_skipped = points.count - used;
  return grid;
}

Descriptor makeDescriptor(const HeightGrid& grid, const Config& config) {
  const int rings = static_cast<int>(grid.heights.rows());
  const int sectors = static_cast<int>(grid.heights.cols());
  Descriptor d;
  d.num_rings = rings;
  d.num_sectors = sectors;
  d.unit_columns.assign(static_cast<std::size_t>(rings) * sectors, 0.0f);
  d.column_occupied.assign(sectors, 0);
  d.ring_key.assign(rings, 0.0f);
  d.sector_key.assign(sectors, 0.0f);
  if (rings == 0 || sectors == 0) return d;

  for (int s = 0; s < sectors; ++s) {
    const bool occupied = grid.occupied.col(s).any();
    d.column_occupied[s] = occupied ? 1 : 0;
    d.occupied_columns += occupied ? 1 : 0;
    const float norm = grid.heights.col(s).norm();
    d.sector_key[s] = grid.heights.col(s).mean();
    if (!occupied || !(norm > 0.0f)) continue;
    float* column = &d.unit_columns[static_cast<std::size_t>(s) * rings];
    for (int r = 0; r < rings; ++r) column[r] = grid.heights(r, s) / norm;
  }
  for (int r = 0; r < rings; ++r) {
    d.ring_key[r] = config.ring_key == RingKeyType::kOccupancy
                        ? static_cast<float>(grid.occupied.row(r).cast<int>().sum()) / sectors
                        : grid.heights.row(r).mean();
  }
  return d;
}

Descriptor makeDescriptor(const PointView& points, const Config& config) {
  return makeDescriptor(makeHeightGrid(points, config), config);
}

std::size_t Descriptor::bytes() const {
  return unit_columns.capacity() * sizeof(float) + column_occupied.capacity() +
         ring_key.capacity() * sizeof(float) + sector_key.capacity() * sizeof(float);
}

}  // namespace scan_context_loop
