// PCL's registrations (GICP, ICP, NDT) as the fine stage of verification, over voxel means. Slower
// than the built-in voxel GICP; kept so that verify_method can compare them on the same data.
#pragma once

#include <Eigen/Geometry>

#include "scan_context_loop/core/registration.h"
#include "scan_context_loop/core/verification.h"

namespace scan_context_loop {

/// Refines `pose` (T_query<-match) with config.method; false when PCL reports no convergence.
bool refineWithPcl(const VoxelCloud& query, const VoxelCloud& match, const VerificationConfig& config,
                   Eigen::Isometry3d* pose);

}  // namespace scan_context_loop
