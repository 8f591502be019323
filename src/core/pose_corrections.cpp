#include "scan_context_loop/core/pose_corrections.h"

namespace scan_context_loop {

std::vector<std::optional<Eigen::Isometry3d>> correctedSessionPoses(const std::vector<const Keyframe*>& keyframes,
                                                                    const PoseCorrections& corrections) {
  std::vector<std::optional<Eigen::Isometry3d>> poses(keyframes.size());
  std::size_t begin = 0;
  while (begin < keyframes.size()) {
    std::size_t end = begin + 1;
    while (end < keyframes.size() && keyframes[end]->session == keyframes[begin]->session) ++end;
    const auto first = corrections.lower_bound(begin), last = corrections.lower_bound(end);
    // The correction that carries odometry poses into the corrected frame: the first one's until the
    // walk reaches a corrected keyframe, then the newest one's.
    std::optional<Eigen::Isometry3d> offset;
    for (auto it = first; it != last && !offset; ++it) {
      if (keyframes[it->first]->info.pose) offset = it->second * keyframes[it->first]->info.pose->inverse();
    }
    auto next = first;
    for (std::size_t i = begin; first != last && i < end; ++i) {
      const std::optional<Eigen::Isometry3d>& odometry = keyframes[i]->info.pose;
      if (next != last && next->first == i) {
        poses[i] = next->second;
        if (odometry) offset = next->second * odometry->inverse();
        ++next;
      } else if (odometry && offset) {
        poses[i] = *offset * *odometry;
      }
    }
    begin = end;
  }
  return poses;
}

}  // namespace scan_context_loop
