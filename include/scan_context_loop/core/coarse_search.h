// Coarse pose search on the bird's-eye view of vertical structure, for verification: the descriptor
// gives a few yaw hypotheses but no translation, and GICP only converges from within about a voxel or
// two. Facades, poles and trunks projected on the ground plane are what survives a changed world
// (parked cars aside), so the candidate's structure columns are slid over the query's structure map,
// for every hypothesis, a few yaw steps around it and every translation within a window, and the
// placements that put most columns on structure seed the registration.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {

/// Structure map of a keyframe: cells of `cell` metres over [-radius, radius]^2 holding 1 where a
/// vertical-structure voxel stands, 0.5 next to one (a placement a cell off still scores), else 0.
struct StructureMap {
  float cell = 1.0f;
  float radius = 40.0f;
  int size = 0;
  std::vector<float> value;
  std::size_t columns = 0;  ///< cells holding structure

  float at(float x, float y) const {
    const int ix = static_cast<int>(std::floor((x + radius) / cell));
    const int iy = static_cast<int>(std::floor((y + radius) / cell));
    if (ix < 0 || iy < 0 || ix >= size || iy >= size) return 0.0f;
    return value[static_cast<std::size_t>(iy) * size + ix];
  }
};

StructureMap structureMap(const VoxelCloud& cloud, float cell);

/// The distinct cell centres of a cloud's vertical-structure voxels (x, y), in its own frame; an even
/// share of at most 600 of them.
std::vector<Eigen::Vector2f> structureColumns(const VoxelCloud& cloud, float cell);

struct CoarseHit {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< T_query<-match
  double score = 0.0;                                      ///< mean map value under the moved columns, in [0, 1]
  int hypothesis = 0;                                      ///< which of the given hypotheses it refines
};

/// For each hypothesis (T_query<-match guesses), the best placement over yaw offsets of
/// -yaw_step, 0, +yaw_step [rad] and translations within +-radius [m] on the map's grid; best first.
std::vector<CoarseHit> coarseSearch(const StructureMap& query, const std::vector<Eigen::Vector2f>& match_columns,
                                    const std::vector<Eigen::Isometry3d>& hypotheses, double radius, double yaw_step);

}  // namespace scan_context_loop
