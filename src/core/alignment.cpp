#include "scan_context_loop/core/alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "fast_math.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace scan_context_loop {

namespace {

inline int wrapIndex(int i, int n) {
  i %= n;
  return i < 0 ? i + n : i;
}

/// The dot product of two int8 arrays of at most kDotBlock entries, summed in int32: at most
/// kDotBlock * 128^2 = 2^30, whatever the arrays hold.
constexpr int kDotBlock = 1 << 16;
inline std::int32_t dotInt8Block(const std::int8_t* a, const std::int8_t* b, int n) {
  std::int32_t sum = 0;
  int i = 0;
#if defined(__SSE2__)
  // 16 entries a step: each half sign-extended to int16 (the byte unpacked into both halves of a word,
  // then shifted down) and multiplied pairwise into int32 lanes (pmaddwd). The compiler's own
  // vectorisation of the scalar loop takes about twice the instructions.
  const auto widen_low = [](__m128i v) { return _mm_srai_epi16(_mm_unpacklo_epi8(v, v), 8); };
  const auto widen_high = [](__m128i v) { return _mm_srai_epi16(_mm_unpackhi_epi8(v, v), 8); };
  __m128i low = _mm_setzero_si128(), high = _mm_setzero_si128();
  for (; i + 16 <= n; i += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i));
    const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + i));
    low = _mm_add_epi32(low, _mm_madd_epi16(widen_low(x), widen_low(y)));
    high = _mm_add_epi32(high, _mm_madd_epi16(widen_high(x), widen_high(y)));
  }
  alignas(16) std::int32_t lanes[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), _mm_add_epi32(low, high));
  sum = lanes[0] + lanes[1] + lanes[2] + lanes[3];
#endif
  for (; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

/// The dot product of two int8 arrays: blocks summed in int32, added up in int64.
inline std::int64_t dotInt8(const std::int8_t* a, const std::int8_t* b, int n) {
  std::int64_t total = 0;
  for (int i0 = 0; i0 < n; i0 += kDotBlock) total += dotInt8Block(a + i0, b + i0, std::min(kDotBlock, n - i0));
  return total;
}

bool compatible(const Descriptor& a, const Descriptor& b) {
  return a.num_rings == b.num_rings && a.num_sectors == b.num_sectors && a.num_sectors > 0 && a.num_rings > 0;
}

}  // namespace

double wrapAngle(double radians) {
  if (!std::isfinite(radians)) return 0.0;
  double a = std::fmod(radians, kTwoPi);  // (-2 pi, 2 pi)
  if (a <= -M_PI) a += kTwoPi;
  if (a > M_PI) a -= kTwoPi;
  return a;
}

double distanceAtShift(const Descriptor& query, const Descriptor& match, int shift, int* shared_columns) {
  if (shared_columns) *shared_columns = 0;
  if (!compatible(query, match)) return 1.0;
  const int sectors = query.num_sectors;
  const int rings = query.num_rings;
  shift = wrapIndex(shift, sectors);
  const std::int8_t* q = query.unit_columns.data();
  const std::int8_t* m = match.unit_columns.data();
  const std::uint8_t* qo = query.column_occupied.data();
  const std::uint8_t* mo = match.column_occupied.data();
  std::int64_t similarity = 0;  // in units of kUnitColumnScale^2
  int shared = 0;
  // Empty columns are zero vectors, so their dot products vanish on their own: no branch needed, and
  // the two contiguous runs of the shifted match (no modulo inside) vectorise as one long dot product.
  const auto run = [&](int j0, int j1, int k0) {
    const std::int8_t* a = q + static_cast<std::size_t>(j0) * rings;
    const std::int8_t* b = m + static_cast<std::size_t>(k0) * rings;
    const int length = (j1 - j0) * rings;
    similarity += dotInt8(a, b, length);
    for (int j = j0; j < j1; ++j) shared += qo[j] & mo[j - j0 + k0];
  };
  run(shift, sectors, 0);  // query columns shift.. against match columns 0..
  run(0, shift, sectors - shift);
  if (shared_columns) *shared_columns = shared;
  if (shared == 0) return 1.0;
  constexpr double kScale2 = double(kUnitColumnScale) * kUnitColumnScale;
  return 1.0 - static_cast<double>(similarity) / (kScale2 * shared);
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

namespace {

/// Yaw of a shift with the sub-sector refinement: the vertex of the parabola through the distances at
/// the shift and its two neighbours.
double refinedYaw(const Descriptor& query, const Descriptor& match, int shift, double at_shift) {
  const int sectors = query.num_sectors;
  double offset = 0.0;
  const double before = distanceAtShift(query, match, shift - 1);
  const double after = distanceAtShift(query, match, shift + 1);
  const double curvature = before - 2.0 * at_shift + after;
  if (curvature > 1e-9) offset = std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5);
  return wrapAngle((shift + offset) * kTwoPi / sectors);
}

}  // namespace

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

  result.distance = best;
  result.shift = best_shift > sectors / 2 ? best_shift - sectors : best_shift;
  result.yaw = refinedYaw(query, match, best_shift, best);
  result.shared_columns = best_shared;
  return result;
}

}  // namespace scan_context_loop

namespace scan_context_loop {

std::vector<Alignment> alignHypotheses(const Descriptor& query, const Descriptor& match, int max_count,
                                       int min_separation) {
  std::vector<Alignment> out;
  if (!compatible(query, match) || query.empty() || match.empty() || max_count < 1) return out;
  const int sectors = query.num_sectors;
  std::vector<double> d(sectors);
  std::vector<int> shared(sectors);
  for (int s = 0; s < sectors; ++s) d[s] = distanceAtShift(query, match, s, &shared[s]);
  std::vector<int> minima;
  for (int s = 0; s < sectors; ++s) {
    if (d[s] <= d[wrapIndex(s - 1, sectors)] && d[s] <= d[wrapIndex(s + 1, sectors)]) minima.push_back(s);
  }
  std::sort(minima.begin(), minima.end(), [&](int a, int b) { return d[a] < d[b]; });
  for (int s : minima) {
    if (static_cast<int>(out.size()) >= max_count) break;
    const bool near = std::any_of(out.begin(), out.end(), [&](const Alignment& a) {
      const int gap = std::abs(wrapIndex(s - a.shift, sectors));
      return std::min(gap, sectors - gap) < min_separation;
    });
    if (near) continue;
    Alignment a;
    a.distance = d[s];
    a.shift = s > sectors / 2 ? s - sectors : s;
    a.yaw = refinedYaw(query, match, s, d[s]);
    a.shared_columns = shared[s];
    out.push_back(a);
  }
  return out;
}

Eigen::Isometry3d priorPose(double yaw, const Eigen::Vector2d& viewpoint) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() << viewpoint.x(), viewpoint.y(), 0.0;
  return pose;
}

}  // namespace scan_context_loop
