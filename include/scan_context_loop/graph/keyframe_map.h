// Keyframe clouds kept for a map: each thinned on arrival (a voxel grid, a range limit), then placed at
// whatever poses the pose graph holds and thinned again into one cloud. ROS-free (Eigen, PCL, std).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace scan_context_loop {

struct KeyframeMapConfig {
  /// Voxel edge of the stored clouds and of the assembled map [m].
  double voxel = 0.5;
  /// Points beyond this horizontal range from the sensor are not kept [m] (far points are sparse and
  /// smear most under a pose error).
  double max_range = 50.0;
  /// Keep the cloud of every n-th keyframe only (1: all). The map of a long drive stays small.
  int keyframe_stride = 1;

  /// Problems with the values, one line each (empty when usable).
  std::vector<std::string> validate() const;
};

class KeyframeMap {
 public:
  explicit KeyframeMap(const KeyframeMapConfig& config = KeyframeMapConfig());

  /// Keeps keyframe `index`'s points (sensor frame; NaN/Inf skipped) if the stride selects it: it counts
  /// `ordinal` (the keyframe's number in its own robot's sequence, with several robots), or `index`
  /// when `ordinal` is negative. Returns the number of points kept.
  std::size_t add(std::size_t index, const std::vector<Eigen::Vector3f>& points, long ordinal = -1);
  /// The kept clouds moved by `poses` (T_world<-keyframe by keyframe index) into one cloud in the world
  /// frame, thinned by the voxel grid. Keyframes beyond `poses`, and keyframe i when `leave_out[i]`, are
  /// left out.
  pcl::PointCloud<pcl::PointXYZ> assemble(const std::vector<Eigen::Isometry3d>& poses,
                                          const std::vector<bool>& leave_out = {}) const;

  std::size_t keyframes() const { return clouds_.size(); }
  std::size_t points() const { return points_; }
  const KeyframeMapConfig& config() const { return config_; }

 private:
  struct Stored {
    std::size_t index;
    std::vector<Eigen::Vector3f> points;
  };
  KeyframeMapConfig config_;
  std::vector<Stored> clouds_;
  std::size_t points_ = 0;
};

}  // namespace scan_context_loop
