// What the benchmarks feed the core: six real KITTI scans, and a stream of keyframe grids made from
// them (synthetic, but with the real scans' structure).
#pragma once

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {
namespace bench {

/// The scans: a reverse revisit (08 720 / 1500), consecutive scans (00 94 / 95, 198 / 199), 58 m apart
/// (00 94 / 198).
struct Scan {
  std::string sequence;
  int frame;
};
inline const std::vector<Scan>& scans() {
  static const std::vector<Scan> list = {{"00", 94}, {"00", 95}, {"00", 198}, {"00", 199}, {"08", 720}, {"08", 1500}};
  return list;
}

/// Reads scans() from DATA_DIR/kitti/<sequence>; prints the problem and returns false when one is missing.
inline bool readScans(const std::string& data, std::vector<pcl::PointCloud<pcl::PointXYZI>>* clouds) {
  for (const Scan& s : scans()) {
    pcl::PointCloud<pcl::PointXYZI> cloud;
    std::string error;
    if (!kitti::readScan(kitti::scanPath(data + "/kitti/" + s.sequence, s.frame), &cloud, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return false;
    }
    clouds->push_back(std::move(cloud));
  }
  return true;
}

/// A stream of plausible keyframe grids: real scans' grids, rotated, with height noise and bins that
/// come and go, drifting from one real place to the next every few hundred keyframes.
class GridStream {
 public:
  GridStream(std::vector<HeightGrid> bases, std::uint32_t seed) : bases_(std::move(bases)), rng_(seed) {}
  HeightGrid next() {
    const HeightGrid& base = bases_[(count_++ / 300) % bases_.size()];
    HeightGrid g = base;
    std::normal_distribution<float> noise(0.0f, 0.3f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const int roll = static_cast<int>(unit(rng_) * g.heights.cols());
    for (int s = 0; s < g.heights.cols(); ++s) {
      const int from = (s + roll) % g.heights.cols();
      for (int r = 0; r < g.heights.rows(); ++r) {
        const bool occupied = base.occupied(r, from) && unit(rng_) > 0.1f;
        g.occupied(r, s) = occupied;
        g.heights(r, s) = occupied ? base.heights(r, from) + noise(rng_) : 0.0f;
      }
    }
    return g;
  }

 private:
  std::vector<HeightGrid> bases_;
  std::mt19937 rng_;
  std::size_t count_ = 0;
};

/// `count` keyframes in one session: synthetic descriptors, stamps 0.1 s apart, poses 1 m apart along a
/// gently winding path; with `clouds`, each keyframe gets one of them in turn. `seed` draws the grids.
inline PriorSessions makeKeyframes(std::size_t count, const std::vector<HeightGrid>& grids,
                                   const std::vector<VoxelCloud>& clouds, const Config& config,
                                   std::uint32_t seed = 7) {
  PriorSessions sessions;
  GridStream stream(grids, seed);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < count; ++i) {
    Keyframe k;
    k.info.stamp = 0.1 * static_cast<double>(i);
    k.info.tag = static_cast<std::int64_t>(i);
    k.info.pose = pose;
    k.path_length = static_cast<double>(i);
    k.descriptor = makeDescriptor(stream.next(), config);
    sessions.keyframes.push_back(std::move(k));
    pose = pose * Eigen::Translation3d(1.0, 0.0, 0.0) *
           Eigen::AngleAxisd(0.01 * std::sin(0.001 * i), Eigen::Vector3d::UnitZ());
    if (!clouds.empty()) {
      sessions.gravity_alignment.push_back(Eigen::Matrix3f::Identity());
      sessions.clouds.push_back(std::make_unique<VoxelCloud>(clouds[i % clouds.size()]));
    }
  }
  return sessions;
}

}  // namespace bench
}  // namespace scan_context_loop
