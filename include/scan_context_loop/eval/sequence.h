// A KITTI-format sequence as the evaluator reads it: its keyframes' frame numbers, poses and stamps.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace eval {

struct SequenceOptions {
  double keyframe_spacing = 0.0;  ///< metres of true travel between keyframes; 0 = every frame
  int first = 0, last = -1;       ///< frame window (last < 0: to the end)
  bool use_odometry_file = true;  ///< feed odom_poses.txt to the detector when the sequence has one
};

/// The keyframes of a sequence: frame numbers, true and odometry LiDAR poses, stamps.
struct Sequence {
  std::string dir;
  std::vector<int> frames;
  std::vector<Eigen::Isometry3d> truth, odometry;
  std::vector<double> stamps;
  std::size_t missing_scans = 0;  ///< frames of the window skipped because their .bin is absent
  bool odometry_from_file = false;
};

/// Reads poses.txt, calib.txt, times.txt (optional; without it frame f is at 0.1 f s) and odom_poses.txt
/// (optional), then selects the keyframes among the frames whose scan exists. Returns false with the
/// reason on a malformed line, or when times.txt has fewer stamps or odom_poses.txt another number of
/// poses than poses.txt.
bool loadSequence(const std::string& dir, const SequenceOptions& options, Sequence* sequence, std::string* error);

/// The true LiDAR pose of every frame of the sequence in `dir` (poses.txt through calib.txt's Tr), whether
/// or not its scan exists.
bool readTruePoses(const std::string& dir, std::vector<Eigen::Isometry3d>* truth, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
