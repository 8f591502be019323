// Column-shift cosine distance between two descriptors and the yaw prior it implies.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {

/// Result of aligning a match descriptor to a query descriptor.
///
/// Convention: query column j lines up with match column (j - shift) mod num_sectors, so the match's
/// scene appears rotated by +shift sectors in the query. `yaw` is the yaw of the match keyframe's sensor
/// frame expressed in the query keyframe's frame, i.e. the z-rotation of T_query<-match, in radians
/// wrapped to (-pi, pi]: shift * 2 pi / num_sectors plus the sub-sector refinement.
struct Alignment {
  /// Mean over shared occupied columns of (1 - cosine similarity), in [0, 2] (typically [0, 1]);
  /// 1.0 when the descriptors share no occupied column (including empty against anything).
  double distance = 1.0;
  int shift = 0;
  double yaw = 0.0;
  /// Shared occupied columns at the best shift.
  int shared_columns = 0;
};

/// Distance at one given shift (same convention as Alignment::shift).
double distanceAtShift(const Descriptor& query, const Descriptor& match, int shift, int* shared_columns = nullptr);

/// Best shift by the sector keys (exhaustive over all shifts, L2 between the keys).
int coarseShift(const Descriptor& query, const Descriptor& match);

/// Coarse shift from the sector keys, local search of +-Config::searchHalfWidth() columns around it
/// (every shift when search_ratio >= 1), then a parabola through the distances at the best shift and
/// its two neighbours for the sub-sector yaw. Descriptors of different grid sizes give distance 1.
Alignment align(const Descriptor& query, const Descriptor& match, const Config& config);

/// Yaw hypotheses for verification: the distance at every column shift, then its local minima, best
/// first, at most `max_count`, each at least `min_separation` columns from the ones before it, each with
/// its sub-sector refinement. The sector keys' coarse shift can pick the wrong column (a tilted sensor,
/// a changed scene); registering the few best distinct shifts recovers it. Empty for incompatible or
/// empty descriptors.
std::vector<Alignment> alignHypotheses(const Descriptor& query, const Descriptor& match, int max_count,
                                       int min_separation);

/// Wraps an angle to (-pi, pi].
double wrapAngle(double radians);

/// The pose a descriptor match implies, T_query<-match: the match's sensor stands at `viewpoint` (the
/// virtual viewpoint it was found from, zero for the real one) in the query's frame, turned by `yaw`.
/// Registration starts from it; a loop without registration is reported with it.
Eigen::Isometry3d priorPose(double yaw, const Eigen::Vector2d& viewpoint = Eigen::Vector2d::Zero());

}  // namespace scan_context_loop
