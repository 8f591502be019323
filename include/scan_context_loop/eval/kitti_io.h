// Reading and writing the KITTI odometry layout: velodyne/%06d.bin, poses.txt, calib.txt, times.txt.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {
namespace kitti {

/// Reads a .bin scan (float32 x, y, z, intensity per point). Returns false with a reason when the file
/// is missing or its size is not a multiple of 16 bytes.
bool readScan(const std::string& path, pcl::PointCloud<pcl::PointXYZI>* cloud, std::string* error);
/// The same, into `buffer` (four floats a point; reuse it from scan to scan, so its memory is touched
/// once, not per scan) with `view` set to its points: no point cloud is built.
bool readScan(const std::string& path, std::vector<float>* buffer, PointView* view, std::string* error);
bool writeScan(const std::string& path, const pcl::PointCloud<pcl::PointXYZI>& cloud, std::string* error);

/// Exactly 12 finite numbers, the 3 x 4 matrix row by row, and nothing else (white space aside).
bool parsePoseRow(const std::string& text, Eigen::Isometry3d* pose);

/// Reads 3x4 row-major pose rows, one per line. Returns false, naming the file and line, on a line that
/// is not exactly 12 finite numbers (blank lines are skipped).
bool readPoses(const std::string& path, std::vector<Eigen::Isometry3d>* poses, std::string* error);
bool writePoses(const std::string& path, const std::vector<Eigen::Isometry3d>& poses, std::string* error);

/// Reads the `Tr:` line (camera <- velodyne) of calib.txt: exactly 12 finite numbers.
bool readCalibTr(const std::string& path, Eigen::Isometry3d* tr, std::string* error);

/// Reads one timestamp per line (one finite number; blank lines are skipped).
bool readTimes(const std::string& path, std::vector<double>* times, std::string* error);

/// Camera-frame poses to LiDAR poses in a LiDAR-centred world: inv(Tr) * T_cam * Tr.
std::vector<Eigen::Isometry3d> lidarPoses(const std::vector<Eigen::Isometry3d>& camera_poses,
                                          const Eigen::Isometry3d& tr);

/// "<dir>/velodyne/%06d.bin"
std::string scanPath(const std::string& sequence_dir, int frame);

}  // namespace kitti
}  // namespace scan_context_loop
