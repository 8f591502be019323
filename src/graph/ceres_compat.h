// The one place the Ceres versions differ for the pose graph: the quaternion's local parameterisation.
// Ceres 1.14 (Ubuntu 20.04) and 2.0 (22.04) have only LocalParameterization, 2.1 (Debian 12) has both,
// 2.2 (24.04) only Manifold. A private header of the graph library (it includes Ceres).
#pragma once

#include <ceres/ceres.h>
#include <ceres/version.h>

#if CERES_VERSION_MAJOR > 2 || (CERES_VERSION_MAJOR == 2 && CERES_VERSION_MINOR >= 1)
#define SCL_CERES_HAS_MANIFOLD 1
#else
#define SCL_CERES_HAS_MANIFOLD 0
#endif

namespace scan_context_loop {
namespace ceres_compat {

#if SCL_CERES_HAS_MANIFOLD
/// The unit quaternion in Eigen's coefficient order (x, y, z, w).
using EigenQuaternion = ceres::EigenQuaternionManifold;

/// The problem does not delete the quaternion's parameterisation (its owner does).
inline void keepQuaternionOwnership(ceres::Problem::Options* options) {
  options->manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
}
#else
using EigenQuaternion = ceres::EigenQuaternionParameterization;

inline void keepQuaternionOwnership(ceres::Problem::Options* options) {
  options->local_parameterization_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
}
#endif

}  // namespace ceres_compat
}  // namespace scan_context_loop
