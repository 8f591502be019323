// Branch-free approximations of the angle functions, for loops the compiler vectorises.
#pragma once

#include <cmath>

namespace scan_context_loop {

constexpr double kTwoPi = 6.28318530717958647692;
constexpr float kTwoPiF = static_cast<float>(kTwoPi);
constexpr float kPiF = static_cast<float>(kTwoPi / 2.0);

/// atan2(y, x) mapped to [0, 2 pi), max error about 1e-5 rad (a minimax polynomial for atan on [0, 1]),
/// far below a sector (0.1 rad at 60 sectors). Written with selects, not branches: the quadrant of
/// consecutive points is unpredictable, and the binning loop vectorises only without branches.
inline float azimuth(float x, float y) {
  constexpr float kHalfPi = 1.57079632679489661923f;
  const float ax = std::fabs(x);
  const float ay = std::fabs(y);
  const bool steep = ay > ax;
  const float hi = steep ? ay : ax;
  const float lo = steep ? ax : ay;
  const float t = lo / (hi > 0.0f ? hi : 1.0f);
  const float t2 = t * t;
  float a =
      t * (0.99997726f +
           t2 * (-0.33262347f + t2 * (0.19354346f + t2 * (-0.11643287f + t2 * (0.05265332f + t2 * -0.01172120f)))));
  a = steep ? kHalfPi - a : a;
  a = x < 0.0f ? kPiF - a : a;
  a = y < 0.0f ? kTwoPiF - a : a;
  return a;
}

/// sin and cos of an angle in [0, 1.1] rad, by their Taylor series to the 9th and 10th power (error
/// below 1e-7 there).
inline void smallSinCos(float a, float* s, float* c) {
  const float a2 = a * a;
  *s = a * (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 + a2 * (1.0f / 362880)))));
  *c = 1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 + a2 * (1.0f / 40320 + a2 * (-1.0f / 3628800)))));
}

}  // namespace scan_context_loop
