// The corrected map as files: the assembled cloud (PCD), the corrected and the odometry keyframe
// trajectories (TUM, KITTI + times) and the pose graph itself (g2o), written into one directory, each
// file atomically (core/file_io.h: a temporary file, fsync, rename). ROS-free (Eigen, PCL types, std).
//
// Formats (doc/pose_graph.md#saving-the-map says the same, with how to load them):
// - map.pcd: PCL's binary PCD, fields x y z (float32), the points as given (voxel-filtered by the caller).
// - corrected_tum.txt, odometry_tum.txt: `stamp tx ty tz qx qy qz qw` per keyframe (TUM, as evo reads it).
// - corrected_kitti.txt: rows 0-2 of the 4x4 pose, 12 numbers a line; times.txt: its stamps, one a line.
// - pose_graph.g2o: `VERTEX_SE3:QUAT i x y z qx qy qz qw` per keyframe (the corrected estimate), `FIX 0`,
//   then `EDGE_SE3:QUAT a b x y z qx qy qz qw` + the information matrix's 21 upper-triangular entries,
//   row by row, for every factor (g2oInformation converts the covariance).
// Stamps are written with nanosecond digits (%.9f from integer nanoseconds), poses with 17 significant
// digits (a double read back is the one written).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/file_io.h"
#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {

/// What a save writes: one entry per keyframe in stamps, corrected and odometry (same length).
struct MapFiles {
  std::vector<std::int64_t> stamps_ns;  ///< keyframe stamps [ns], increasing
  std::vector<Eigen::Isometry3d> corrected, odometry;  ///< T_world<-keyframe
  std::vector<PoseGraphFactor> factors;
  /// The assembled map (KeyframeMap::assemble); map.pcd is left out when `has_cloud` is false.
  pcl::PointCloud<pcl::PointXYZ> cloud;
  bool has_cloud = false;
  double voxel = 0.0;  ///< the voxel edge the cloud was filtered with [m], for the report
};

/// The pose graph's part of MapFiles (stamps, corrected and odometry poses, factors); the cloud is the
/// caller's.
MapFiles mapFilesOf(const PoseGraph& graph, const std::vector<std::int64_t>& stamps_ns);

/// What a save wrote.
struct MapFilesReport {
  std::string directory;
  std::vector<std::string> files;   ///< full paths, in the order written
  std::vector<std::uint64_t> bytes; ///< each file's size
  std::size_t keyframes = 0, loops = 0, points = 0;
  double voxel = 0.0;
  /// Temporary files of earlier saves that died before their rename, removed before this one (also
  /// reported when this save fails).
  std::vector<AbandonedFile> abandoned;
  /// A save without a cloud removes the map.pcd an earlier save left in the directory (it would not
  /// match the new trajectory): its path, or "".
  std::string removed_stale_cloud;
  /// One line for a log or a service answer: the directory, each file with its size, the points and
  /// the voxel ("map.pcd 1.2 MB (34567 points, voxel-filtered at 0.50 m)"), the stale map.pcd removed.
  std::string summary() const;
};

/// The file names a save writes, in order (map.pcd only when `with_cloud`).
std::vector<std::string> mapFileNames(bool with_cloud);

/// Writes the files into `directory` (created, one level, mode 0755, when missing; its parent must
/// exist). Every file goes to a temporary file first; only when all are written are they flushed and
/// renamed over their targets, one after the other, so a save that fails while writing leaves every
/// file as it was, and no file is ever seen half written. Without a cloud, a map.pcd already in the
/// directory is removed once the other files are in place. False with the reason in *error: a
/// directory that cannot be created or written, stamps or poses of different lengths, stamps not
/// increasing, a factor naming an unknown keyframe; *report then holds the directory and the abandoned
/// temporary files removed, nothing else.
bool writeMapFiles(const std::string& directory, const MapFiles& files, MapFilesReport* report, std::string* error);

/// The information matrix of an EDGE_SE3:QUAT for a factor measuring Z = T_a<-b with `covariance` in
/// this project's order (x y z roll pitch yaw in a's axes; residual [t_ab - t_Z ; 2 vec(q_Z^-1 q_ab)]).
/// g2o's error is [R_Z^T (t_ab - t_Z) ; vec(q_Z^-1 q_ab)] (the translation in Z's axes, half the small
/// angle), i.e. ours = K * g2o's with K = diag(R_Z, 2 I); so Omega_g2o = K^T covariance^-1 K. For a
/// covariance whose translation block is isotropic and uncorrelated with the rotation (the odometry
/// factors) this is D covariance^-1 D with D = diag(1, 1, 1, 2, 2, 2).
Matrix6d g2oInformation(const Eigen::Isometry3d& measurement, const Matrix6d& covariance);

}  // namespace scan_context_loop
