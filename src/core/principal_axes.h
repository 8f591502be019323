// The principal axes of many voxels' point spreads at once (the registration data's normals and shapes).
#pragma once

#include <cstddef>

namespace scan_context_loop {

constexpr std::size_t kAxesBlock = 256;

/// Up to kAxesBlock symmetric 3x3 matrices (covariances), one array per entry of the upper triangle.
struct SymmetricBlock {
  float xx[kAxesBlock], xy[kAxesBlock], xz[kAxesBlock], yy[kAxesBlock], yz[kAxesBlock], zz[kAxesBlock];
};

/// Per matrix: its eigenvalues in increasing order, the unit eigenvector of the smallest (a voxel's
/// normal) and the z component of the largest's (a line's direction).
struct AxesBlock {
  float l0[kAxesBlock], l1[kAxesBlock], l2[kAxesBlock];
  float nx[kAxesBlock], ny[kAxesBlock], nz[kAxesBlock];
  float major_z[kAxesBlock];
};

/// The eigen-decomposition of the first n matrices, in float and without branches, so that the
/// compiler vectorises it (Eigen's closed-form solver, one matrix at a time in double, was 8% of a
/// verified keyframe's CPU). The same closed form: the roots of the characteristic cubic by the
/// trigonometric method on the shifted, scaled matrix, each eigenvector the largest cross product of
/// two rows of (A - l I). The eigenvector of the eigenvalue further from the others is solved first;
/// when the other two are numerically equal (a line's cross-section, a plane's in-plane axes), the
/// other eigenvector is a unit vector orthogonal to it. A zero or isotropic matrix gives the axes.
void principalAxes(const SymmetricBlock& m, std::size_t n, AxesBlock* out);

}  // namespace scan_context_loop
