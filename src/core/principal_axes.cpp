#include "principal_axes.h"

#include <algorithm>
#include <cmath>

#include "fast_math.h"
#include "simd_clones.h"

namespace scan_context_loop {

namespace {

struct V3 {
  float x, y, z;
};

inline V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float norm2(const V3& a) { return a.x * a.x + a.y * a.y + a.z * a.z; }
inline V3 pick(bool first, const V3& a, const V3& b) {
  return {first ? a.x : b.x, first ? a.y : b.y, first ? a.z : b.z};
}

/// The kernel of the symmetric matrix with rows r0, r1, r2 (rank 2 when l is a simple eigenvalue): the
/// largest of the rows' cross products, and its squared length (0: the rank is lower).
inline V3 kernel(const V3& r0, const V3& r1, const V3& r2, float* length2) {
  const V3 c01 = cross(r0, r1), c02 = cross(r0, r2), c12 = cross(r1, r2);
  const float n01 = norm2(c01), n02 = norm2(c02), n12 = norm2(c12);
  const V3 best = pick(n01 >= n02, c01, c02);
  const float best_n = std::max(n01, n02);
  *length2 = std::max(best_n, n12);
  return pick(best_n >= n12, best, c12);
}

inline V3 normalised(const V3& v, float length2) {
  const float inv = length2 > 0.0f ? 1.0f / std::sqrt(length2) : 0.0f;
  return {v.x * inv, v.y * inv, v.z * inv};
}

/// A unit vector orthogonal to the unit vector v (as Eigen's unitOrthogonal picks it).
inline V3 unitOrthogonal(const V3& v) {
  const bool flat = std::fabs(v.x) > 1e-4f * std::fabs(v.z) || std::fabs(v.y) > 1e-4f * std::fabs(v.z);
  const float nxy = v.x * v.x + v.y * v.y, nyz = v.y * v.y + v.z * v.z;
  const float ixy = nxy > 0.0f ? 1.0f / std::sqrt(nxy) : 0.0f, iyz = nyz > 0.0f ? 1.0f / std::sqrt(nyz) : 0.0f;
  return pick(flat, V3{-v.y * ixy, v.x * ixy, 0.0f}, V3{0.0f, -v.z * iyz, v.y * iyz});
}

}  // namespace

SCL_CLONES void principalAxes(const SymmetricBlock& m, std::size_t n, AxesBlock* out) {
  constexpr float kSqrt3 = 1.73205080756887729353f;
  // Two eigenvalues closer than this (relative to the spread of all three) are taken as equal.
  constexpr float kEqual = 1e-5f;
  n = std::min(n, kAxesBlock);
  for (std::size_t i = 0; i < n; ++i) {
    float a00 = m.xx[i], a01 = m.xy[i], a02 = m.xz[i], a11 = m.yy[i], a12 = m.yz[i], a22 = m.zz[i];
    const float scale =
        std::max(std::max(std::max(std::fabs(a00), std::fabs(a01)), std::max(std::fabs(a02), std::fabs(a11))),
                 std::max(std::fabs(a12), std::fabs(a22)));
    const float inv = scale > 0.0f ? 1.0f / scale : 0.0f;
    a00 *= inv, a01 *= inv, a02 *= inv, a11 *= inv, a12 *= inv, a22 *= inv;
    const float shift = (a00 + a11 + a22) * (1.0f / 3.0f);
    a00 -= shift, a11 -= shift, a22 -= shift;
    // The characteristic polynomial x^3 - c2 x^2 + c1 x - c0 and its roots.
    const float c0 = a00 * a11 * a22 + 2.0f * a01 * a02 * a12 - a00 * a12 * a12 - a11 * a02 * a02 - a22 * a01 * a01;
    const float c1 = a00 * a11 - a01 * a01 + a00 * a22 - a02 * a02 + a11 * a22 - a12 * a12;
    const float c2_3 = (a00 + a11 + a22) * (1.0f / 3.0f);
    const float a_3 = std::max((c2_3 * 3.0f * c2_3 - c1) * (1.0f / 3.0f), 0.0f);
    const float half_b = 0.5f * (c0 + c2_3 * (2.0f * c2_3 * c2_3 - c1));
    const float q = std::max(a_3 * a_3 * a_3 - half_b * half_b, 0.0f);
    const float rho = std::sqrt(a_3);
    // atan2(sqrt(q), half_b), in [0, pi] as sqrt(q) >= 0, a third of it in [0, pi/3].
    const float theta = azimuth(half_b, std::sqrt(q)) * (1.0f / 3.0f);
    float sn, cs;
    smallSinCos(theta, &sn, &cs);
    // The angle's polynomial leaves the roots about 1e-6 off; a Newton step on the cubic takes them to
    // float precision (a step that is not small, near a double root, is not taken).
    const float c2 = 3.0f * c2_3;
    const auto polish = [&](float x) {
      const float p = ((x - c2) * x + c1) * x - c0;
      const float slope = (3.0f * x - 2.0f * c2) * x + c1;
      const float step = p / (slope != 0.0f ? slope : 1.0f);
      return std::fabs(step) < 1e-4f * rho ? x - step : x;
    };
    const float r0 = polish(c2_3 - rho * (cs + kSqrt3 * sn));
    const float r2 = polish(c2_3 + 2.0f * rho * cs);
    const float r1 = std::min(std::max(c2 - r0 - r2, r0), r2);  // the three sum to the trace

    float k0 = 0.0f, k2 = 0.0f;
    const V3 w0 = kernel({a00 - r0, a01, a02}, {a01, a11 - r0, a12}, {a02, a12, a22 - r0}, &k0);
    const V3 w2 = kernel({a00 - r2, a01, a02}, {a01, a11 - r2, a12}, {a02, a12, a22 - r2}, &k2);
    const V3 v0 = normalised(w0, k0), v2 = normalised(w2, k2);
    const float spread = r2 - r0;
    const bool isotropic = !(spread > kEqual);
    const bool low_pair = r1 - r0 <= kEqual * spread;   // l0 = l1: v0 is any normal of v2
    const bool high_pair = r2 - r1 <= kEqual * spread;  // l1 = l2: v2 is any normal of v0
    // The eigenvector of the eigenvalue further from the others is the better conditioned one.
    const bool top_first = r2 - r1 > r1 - r0;
    const V3 normal = pick(k0 > 0.0f && !(top_first && low_pair), v0, unitOrthogonal(v2));
    const V3 major = pick(k2 > 0.0f && !(!top_first && high_pair), v2, unitOrthogonal(v0));
    out->l0[i] = isotropic ? (shift + c2_3) * scale : (r0 + shift) * scale;
    out->l1[i] = isotropic ? (shift + c2_3) * scale : (r1 + shift) * scale;
    out->l2[i] = isotropic ? (shift + c2_3) * scale : (r2 + shift) * scale;
    out->nx[i] = isotropic ? 1.0f : normal.x;
    out->ny[i] = isotropic ? 0.0f : normal.y;
    out->nz[i] = isotropic ? 0.0f : normal.z;
    out->major_z[i] = isotropic ? 1.0f : major.z;
  }
}

}  // namespace scan_context_loop
