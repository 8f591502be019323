// The corrected map as files: the assembled cloud (PCD), the corrected and the odometry keyframe
// trajectories (TUM, KITTI + times) and the pose graph itself (g2o), written into one directory, each
// file atomically (core/file_io.h: a temporary file, fsync, rename). ROS-free (Eigen, PCL types, std).
//
// Formats (doc/pose_graph.md#saving-the-map says the same, with how to load them):
// - map.pcd: PCL's binary PCD, fields x y z (float32), the points as given (voxel-filtered by the caller).
// - corrected_tum.txt, odometry_tum.txt: `stamp tx ty tz qx qy qz qw` per keyframe (TUM, as evo reads it).
// - corrected_kitti.txt: rows 0-2 of the 4x4 pose, 12 numbers a line; times.txt: its stamps, one a line.
// - pose_graph.g2o: `VERTEX_SE3:QUAT i x y z qx qy qz qw` per keyframe (the corrected estimate), `FIX` and
//   the keyframes held (the graph's gauges: `FIX 0` for one robot),
//   then `EDGE_SE3:QUAT a b x y z qx qy qz qw` + the information matrix's 21 upper-triangular entries,
//   row by row, for every factor (g2oInformation converts the covariance).
// Several robots (MapFiles::robots): the trajectory files per robot, named with its id
// (corrected_tum_<robot>.txt, odometry_tum_<robot>.txt, corrected_kitti_<robot>.txt, times_<robot>.txt), each
// in the anchor's map frame for a joined robot and in its own group's frame for one not joined yet; and
// frames.txt: `<robot> <joined 0|1> <12 numbers: T_map<-odom, rows 0-2 of the 4x4>` per robot (team.txt's
// layout). map.pcd and pose_graph.g2o hold every robot's keyframes.
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

/// One robot of a team's map: its keyframes and its estimated odometry frame.
struct MapRobot {
  std::string id;                                           ///< robot id ([A-Za-z0-9_]+), names its files
  std::vector<std::size_t> keyframes;                       ///< its keyframes' indices in MapFiles, in stamp order
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  ///< T_map<-odom (PoseGraph::frame)
  bool joined = false;                                      ///< in the anchor's group (PoseGraph::joined)
};

/// What a save writes: one entry per keyframe in stamps, corrected and odometry (same length).
struct MapFiles {
  /// Keyframe stamps [ns]: increasing (with robots: each robot's, over its keyframes).
  std::vector<std::int64_t> stamps_ns;
  std::vector<Eigen::Isometry3d> corrected, odometry;  ///< T_world<-keyframe
  std::vector<PoseGraphFactor> factors;
  /// The keyframes held (the g2o file's FIX line; empty: keyframe 0).
  std::vector<std::size_t> held;
  /// Several robots: their files instead of the single trajectory files (empty: one robot).
  std::vector<MapRobot> robots;
  /// The assembled map (KeyframeMap::assemble); map.pcd is left out when `has_cloud` is false.
  pcl::PointCloud<pcl::PointXYZ> cloud;
  bool has_cloud = false;
  double voxel = 0.0;  ///< the voxel edge the cloud was filtered with [m], for the report
};

/// The pose graph's part of MapFiles (stamps, corrected and odometry poses, factors, the keyframes held);
/// the cloud is the caller's. With `robots` (robot id by chain number; empty: one robot) the robots'
/// entries too, robot c being the graph's chain c.
MapFiles mapFilesOf(const PoseGraph& graph, const std::vector<std::int64_t>& stamps_ns,
                    const std::vector<std::string>& robots = {});

/// What a save wrote.
struct MapFilesReport {
  std::string directory;
  std::vector<std::string> files;    ///< full paths, in the order written
  std::vector<std::uint64_t> bytes;  ///< each file's size
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

/// The file names a save writes, in order (map.pcd only when `with_cloud`; with `robots`, their files
/// and frames.txt instead of the single trajectory files).
std::vector<std::string> mapFileNames(bool with_cloud, const std::vector<std::string>& robots = {});

/// Writes the files into `directory` (created, one level, mode 0755, when missing; its parent must
/// exist). Every file goes to a temporary file first; only when all are written are they flushed and
/// renamed over their targets, one after the other, so a save that fails while writing leaves every
/// file as it was, and no file is ever seen half written. Without a cloud, a map.pcd already in the
/// directory is removed once the other files are in place. False with the reason in *error: a
/// directory that cannot be created or written, stamps or poses of different lengths, stamps not
/// increasing (a robot's, with robots), a factor or a robot naming an unknown keyframe, a robot id that is
/// not [A-Za-z0-9_]+; *report then holds the directory and the abandoned
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
