// Reading the x, y, z of a block of points into three arrays, the first step of the point kernels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {
namespace gather {

inline float loadFloat(const std::uint8_t* p) {
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// n points `Step` bytes apart from `first`, x, y, z their first three floats.
template <std::size_t Step>
inline void xyzFirst(const std::uint8_t* first, std::size_t n, float* xs, float* ys, float* zs) {
  for (std::size_t i = 0; i < n; ++i) {
    xs[i] = loadFloat(first + Step * i);
    ys[i] = loadFloat(first + Step * i + 4);
    zs[i] = loadFloat(first + Step * i + 8);
  }
}

}  // namespace gather

/// Copies the x, y, z of n points of `points`, `step` bytes apart from `first`, into xs, ys and zs.
/// With x, y, z first in the point (KITTI's files, PCL's PointXYZ and PointXYZI, most drivers' clouds)
/// and the step one of the common ones (16 or 32 bytes a point, every point or every 2nd or 3rd), the
/// loop has a constant stride and the compiler vectorises it with whole-vector shuffles; read with the
/// stride known only at run time it went point by point, a fifth of a one-view binning's time. Inlined
/// into each of its callers' clones (simd_clones.h).
inline void gatherXyz(const PointView& points, const std::uint8_t* first, std::size_t step, std::size_t n, float* xs,
                      float* ys, float* zs) {
  if (points.offset_x == 0 && points.offset_y == 4 && points.offset_z == 8) {
    switch (step) {
      case 16:
        return gather::xyzFirst<16>(first, n, xs, ys, zs);
      case 32:
        return gather::xyzFirst<32>(first, n, xs, ys, zs);
      case 48:
        return gather::xyzFirst<48>(first, n, xs, ys, zs);
      case 64:
        return gather::xyzFirst<64>(first, n, xs, ys, zs);
      case 96:
        return gather::xyzFirst<96>(first, n, xs, ys, zs);
      default:
        break;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = first + i * step;
    xs[i] = gather::loadFloat(p + points.offset_x);
    ys[i] = gather::loadFloat(p + points.offset_y);
    zs[i] = gather::loadFloat(p + points.offset_z);
  }
}

}  // namespace scan_context_loop
