// --save-map: the evaluator's corrected map written as the pose_graph node writes it.
#include <cmath>

#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_loop/eval/trajectory_correction.h"
#include "scan_context_loop/graph/keyframe_map.h"
#include "scan_context_loop/graph/map_files.h"

namespace scan_context_loop {
namespace eval {

bool saveCorrectedMap(const std::string& directory, const Sequence& s, const TrajectoryCorrection& c,
                      std::string* summary, std::string* error) {
  if (!c.computed) {
    *error = "no corrected map: " + c.note;
    return false;
  }
  MapFiles files;
  KeyframeMap map;  // the node's map defaults (map_voxel, map_max_range, map_keyframe_stride)
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    pcl::PointCloud<pcl::PointXYZI> scan;
    if (!kitti::readScan(kitti::scanPath(s.dir, s.frames[k]), &scan, error)) return false;
    std::vector<Eigen::Vector3f> points;
    points.reserve(scan.size());
    for (const auto& p : scan) points.emplace_back(p.x, p.y, p.z);
    map.add(k, points);
    files.stamps_ns.push_back(std::llround(s.stamps[k] * 1e9));
  }
  files.corrected = c.corrected_poses;
  files.odometry = s.odometry;
  files.factors = c.corrected_factors;
  files.cloud = map.assemble(c.corrected_poses);
  files.has_cloud = true;
  files.voxel = map.config().voxel;
  MapFilesReport report;
  if (!writeMapFiles(directory, files, &report, error)) return false;
  *summary = report.summary();
  return true;
}

}  // namespace eval
}  // namespace scan_context_loop
