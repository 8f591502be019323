// Free space seen by a keyframe, for verification: what stands closer to the sensor than the nearest
// structure it saw in a direction would have been seen. A candidate registered onto the wrong place puts
// its walls where the query saw through to something farther; a changed world only does that with what
// moved (cars, fences), a small share of the structure, while anything the query could not see (behind
// its own walls) never counts against a loop.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {

/// Per azimuth bin, the horizontal range of the nearest vertical structure a keyframe saw within the
/// elevation band that counts (see FreeSpace::counts), or its crop range where it saw none.
struct FreeSpace {
  std::vector<float> nearest;
  float max_range = 40.0f;
  float bin = 0.0f;  ///< bin width [rad]

  /// Slope (z over horizontal range) of the lowest direction that counts: 20 deg below the horizon, or
  /// 1 deg above the lowest the keyframe's own returns reach when its sensor looks less far down (a
  /// VLP-16's lowest beam is at -15 deg).
  float min_slope = -0.364f;
  /// Only structure between min_slope and 1 deg above the sensor's horizon counts, on both sides: every
  /// common spinning LiDAR sees that band (an HDL-64E's top beam is at +2 deg, a VLP-16's at +15), so
  /// what lies there and is not seen was not there.
  bool counts(const Eigen::Vector3f& p) const;
};

FreeSpace freeSpace(const VoxelCloud& cloud, int bins = 720);

struct FreeSpaceCheck {
  std::size_t covered = 0;    ///< structure voxels moved into the keyframe's range and band
  std::size_t violating = 0;  ///< of those, standing in space it saw through
  double ratio() const { return covered > 0 ? static_cast<double>(violating) / covered : 0.0; }
};

/// Moves `from`'s structure voxels by T_to<-from and counts, within 25 m of `to`'s sensor, those that stand closer than
/// `to`'s nearest structure in their direction by more than margin + margin_ratio * range.
FreeSpaceCheck checkFreeSpace(const VoxelCloud& from, const FreeSpace& to, const Eigen::Isometry3d& to_from,
                              float margin = 1.0f, float margin_ratio = 0.05f);

}  // namespace scan_context_loop
