// Grid cells of coordinates that may lie anywhere: the voxel grids of registration and the coarse search.
#pragma once

#include <cmath>

namespace scan_context_loop {

/// floor(scaled) as an int, clamped to +-2^20 cells (NaN to the lower end): far beyond any grid of this
/// library, so a coordinate far outside (a corrupt or hostile file's voxel mean of 1e30) lands outside the
/// grid instead of overflowing the conversion.
inline int gridCell(float scaled) {
  constexpr float kFar = 1048576.0f;
  float f = std::floor(scaled);
  if (!(f > -kFar)) f = -kFar;
  if (f > kFar) f = kFar;
  return static_cast<int>(f);
}

}  // namespace scan_context_loop
