#include "scan_context_loop/eval/sequence.h"

#include <algorithm>
#include <sys/stat.h>

#include "scan_context_loop/eval/kitti_io.h"

namespace scan_context_loop {
namespace eval {

namespace {

bool exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

/// The camera poses of `dir`/`file` as LiDAR poses (calib.txt's Tr).
bool readLidarPoses(const std::string& dir, const std::string& file, std::vector<Eigen::Isometry3d>* lidar,
                    std::string* error) {
  std::vector<Eigen::Isometry3d> camera;
  Eigen::Isometry3d tr;
  if (!kitti::readPoses(dir + "/" + file, &camera, error)) return false;
  if (!kitti::readCalibTr(dir + "/calib.txt", &tr, error)) return false;
  *lidar = kitti::lidarPoses(camera, tr);
  return true;
}

/// "<dir>/<file> has <count> <what>, poses.txt <poses> poses".
std::string countMismatch(const std::string& dir, const std::string& file, std::size_t count, const std::string& what,
                          std::size_t poses) {
  return dir + "/" + file + " has " + std::to_string(count) + " " + what + ", poses.txt " + std::to_string(poses) +
         " poses";
}

}  // namespace

bool readTruePoses(const std::string& dir, std::vector<Eigen::Isometry3d>* truth, std::string* error) {
  return readLidarPoses(dir, "poses.txt", truth, error);
}

bool loadSequence(const std::string& dir, const SequenceOptions& options, Sequence* s, std::string* error) {
  s->dir = dir;
  std::vector<Eigen::Isometry3d> truth;
  if (!readTruePoses(dir, &truth, error)) return false;
  std::vector<double> times;
  if (exists(dir + "/times.txt")) {
    if (!kitti::readTimes(dir + "/times.txt", &times, error)) return false;
    // A stamp for every pose: made-up stamps for the rest would go backwards and reject their frames.
    if (times.size() < truth.size()) {
      *error = countMismatch(dir, "times.txt", times.size(), "stamps", truth.size());
      return false;
    }
  }
  std::vector<Eigen::Isometry3d> odom = truth;
  s->odometry_from_file = false;
  if (options.use_odometry_file && exists(dir + "/odom_poses.txt")) {
    if (!readLidarPoses(dir, "odom_poses.txt", &odom, error)) return false;
    if (odom.size() != truth.size()) {
      *error = countMismatch(dir, "odom_poses.txt", odom.size(), "poses", truth.size());
      return false;
    }
    s->odometry_from_file = true;
  }
  const int n = static_cast<int>(truth.size());
  const int first = std::max(0, options.first);
  const int last = options.last < 0 ? n - 1 : std::min(options.last, n - 1);
  double travelled = 0.0;
  int previous = -1;
  for (int f = first; f <= last; ++f) {
    if (f > first) travelled += (truth[f].translation() - truth[f - 1].translation()).norm();
    if (previous >= 0 && travelled < options.keyframe_spacing) continue;
    if (!exists(kitti::scanPath(dir, f))) {
      ++s->missing_scans;
      continue;
    }
    s->frames.push_back(f);
    s->truth.push_back(truth[f]);
    s->odometry.push_back(odom[f]);
    s->stamps.push_back(times.empty() ? 0.1 * f : times[f]);
    travelled = 0.0;
    previous = f;
  }
  if (s->frames.empty()) {
    *error = dir + ": no scan found in velodyne/ for the selected frames";
    return false;
  }
  return true;
}

}  // namespace eval
}  // namespace scan_context_loop
