// Corrected keyframe poses: a pose-graph backend's optimised sensor poses for some keyframes of a database,
// kept beside the keyframes (a stored keyframe never changes), and the poses a save writes from them so
// that every session holding a correction lies wholly in the corrected frame.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/database.h"

namespace scan_context_loop {

/// Corrected sensor poses by keyframe index (database order), all in one frame (the backend's map frame).
using PoseCorrections = std::map<std::size_t, Eigen::Isometry3d>;

/// The pose a save writes for each of `keyframes` (database order, each session a run of them), or none
/// where the stored pose stays. In a session holding a correction: a corrected keyframe gets its
/// correction; another keyframe with an odometry pose O_i gets the newest correction before it applied to
/// that pose, C_j O_j^-1 O_i (j the newest corrected keyframe with an odometry pose before i), and a keyframe
/// before the first such j the first one's; a keyframe without a pose stays without. Sessions without a
/// correction keep their poses; corrections at indices past the keyframes are ignored.
std::vector<std::optional<Eigen::Isometry3d>> correctedSessionPoses(const std::vector<const Keyframe*>& keyframes,
                                                                    const PoseCorrections& corrections);

}  // namespace scan_context_loop
