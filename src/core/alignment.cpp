#include "scan_context_loop/alignment.h"

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace scan_context_loop {

namespace {

constexpr double kTwoPi = 6.28318530717958647692;

inline int wrapIndex(int i, int n) {
  i %= n;
  return i < 0 ? i + n : i;
}

bool compatible(const Descriptor& a, const Descriptor& b) {
  return a.num_rings == b.num_rings && a.num_sectors == b.num_sectors && a.num_sectors > 0 &&
         a.num_rings > 0;
}

}  // namespace

double wrapAngle(double radians) {
  if (!std::isfinite(radians)) return 0.0;
  double a = std::fmod(radians, kTwoPi);  // (-2 pi, 2 pi)
  if (a <= -M_PI) a += kTwoPi;
  if (a > M_PI) a -= kTwoPi;
  return a;
}

double distanceAtShift(const Descriptor& query, const Descriptor& match, int shift,
                       int* shared_columns) {
  if (shared_columns) *shared_columns = 0;
  if (!compatible(query, match)) return 1.0;
  const int sectors = query.num_sectors;
  const int rings = query.num_rings;
  shift = wrapIndex(shift, sectors);
  const float* q = query.unit_columns.data();
  const float* m = match.unit_columns.data();
  const std::uint8_t* qo = query.column_occupied.data();
  const std::uint8_t* mo = match.column_occupied.data();
  float similarity = 0.0f;
  int shared = 0;
  // Empty columns are zero vectors, so their dot products vanish on their own: no branch needed, and
  // the two contiguous runs of the shifted match (no modulo inside) vectorise as one long dot product.
  const auto run = [&](int j0, int j1, int k0) {
    const float* a = q + static_cast<std::size_t>(j0) * rings;
    const float* b = m + static_cast<std::size_t>(k0) * rings;
    const int length = (j1 - j0) * rings;
    similarity += Eigen::Map<const Eigen::VectorXf>(a, length).dot(Eigen::Map<const Eigen::VectorXf>(b, length));
    for (int j = j0; j < j1; ++j) shared += qo[j] & mo[j - j0 + k0];
  };
  run(shift, sectors, 0);  // query columns shift.. against match columns 0..
  run(0, shift, sectors - shift);
  if (shared_columns) *shared_columns = shared;
  if (shared == 0) return 1.0;
  return 1.0 - static_cast<double>(similarity) / shared;
}

int coarseShift(const Descriptor& query, const Descriptor& match) {
  if (!compatible(query, match)) return 0;
  const int sectors = query.num_sectors;
  const float* q = query.sector_key.data();
  const float* m = match.sector_key.data();
  int best_shift = 0;
  float best = std::numeric_limits<float>::infinity();
  for (int shift = 0; shift < sectors; ++shift) {
    float sum = 0.0f;
    // Query column j against match column j - shift, split so no modulo sits in the inner loop.
    for (int j = shift; j < sectors; ++j) {
      const float d = q[j] - m[j - shift];
      sum += d * d;
    }
    for (int j = 0; j < shift; ++j) {
      const float d = q[j] - m[j - shift + sectors];
      sum += d * d;
    }
    if (sum < best) {
      best = sum;
      best_shift = shift;
    }
  }
  return best_shift;
}

Alignment align(const Descriptor& query, const Descriptor& match, const Config& config) {
  Alignment result;
  if (!compatible(query, match) || query.empty() || match.empty()) return result;
  const int sectors = query.num_sectors;
  const int half = config.searchHalfWidth();
  const bool exhaustive = 2 * half + 1 >= sectors;
  const int center = exhaustive ? 0 : coarseShift(query, match);
  const int first = exhaustive ? 0 : center - half;
  const int count = exhaustive ? sectors : 2 * half + 1;

  double best = std::numeric_limits<double>::infinity();
  int best_shift = 0;
  int best_shared = 0;
  for (int i = 0; i < count; ++i) {
    const int shift = wrapIndex(first + i, sectors);
    int shared = 0;
    const double d = distanceAtShift(query, match, shift, &shared);
    if (d < best) {
      best = d;
      best_shift = shift;
      best_shared = shared;
    }
  }

  // Sub-sector refinement: vertex of the parabola through the best shift and its neighbours.
  double offset = 0.0;
  const double before = distanceAtShift(query, match, best_shift - 1);
  const double after = distanceAtShift(query, match, best_shift + 1);
  const double curvature = before - 2.0 * best + after;
  if (curvature > 1e-9) {
    offset = 0.5 * (before - after) / curvature;
    if (offset > 0.5) offset = 0.5;
    if (offset < -0.5) offset = -0.5;
  }

  result.distance = best;
  result.shift = best_shift > sectors / 2 ? best_shift - sectors : best_shift;
  result.yaw = wrapAngle((best_shift + offset) * kTwoPi / sectors);
  result.shared_columns = best_shared;
  return result;
}

}  // namespace scan_context_loop
