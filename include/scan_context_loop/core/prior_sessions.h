// Keyframes recorded in earlier runs, with what verification needs of them, ready to join a detector.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {

/// What a saved database holds (database_file.h) and LoopDetector::appendSessions takes.
struct PriorSessions {
  /// In database order, sessions numbered 0, 1, ... (Database::appendSessions).
  std::vector<Keyframe> keyframes;
  /// L_R_sensor of each keyframe (the gravity alignment its descriptor and registration data were made in), or
  /// empty for identity throughout.
  std::vector<Eigen::Matrix3f> gravity_alignment;
  /// The registration data of each keyframe (null where none was kept), or empty for none at all.
  std::vector<std::unique_ptr<VoxelCloud>> clouds;
  /// Set by readDatabase only: every descriptor has passed descriptorImplausibility for the grid of the
  /// configuration the file was read with, so appendSessions checks their grid sizes but not their
  /// values again. Keyframes from anywhere else leave it false and are checked in full.
  bool descriptors_checked = false;
};

}  // namespace scan_context_loop
