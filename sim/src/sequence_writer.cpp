#include "scan_context_sim/sequence_writer.h"

#include <atomic>
#include <fstream>
#include <mutex>
#include <thread>

#include <pcl/filters/voxel_grid.h>
#include <sys/stat.h>

#include "scan_context_loop/eval/kitti_io.h"

namespace scan_context_loop {
namespace sim {

namespace {

pcl::PointCloud<pcl::PointXYZI> downsample(const pcl::PointCloud<pcl::PointXYZI>& cloud, double leaf) {
  if (leaf <= 0.0) return cloud;
  pcl::PointCloud<pcl::PointXYZI> out;
  pcl::VoxelGrid<pcl::PointXYZI> grid;
  grid.setLeafSize(static_cast<float>(leaf), static_cast<float>(leaf), static_cast<float>(leaf));
  grid.setInputCloud(cloud.makeShared());
  grid.filter(out);
  return out;
}

}  // namespace

double writeSequence(const std::string& dir, const World& world, const SensorModel& sensor, const SequenceData& data,
                     double voxel, std::uint32_t seed, int threads, std::string* error) {
  if (mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST) {
    *error = "cannot create " + dir;
    return -1.0;
  }
  mkdir((dir + "/velodyne").c_str(), 0755);
  std::atomic<std::size_t> next(0), points(0);
  std::mutex error_mutex;  // guards *error
  bool failed = false;
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) {
    pool.emplace_back([&] {
      std::string local;
      for (std::size_t k = next++; k < data.truth.size(); k = next++) {
        const double time = data.world_clock + data.times[k];
        const std::uint64_t noise_seed = (static_cast<std::uint64_t>(seed) << 32) ^ k;
        const auto cloud = downsample(scan(world, sensor, data.origin * data.truth[k], time, noise_seed), voxel);
        points += cloud.size();
        if (!kitti::writeScan(kitti::scanPath(dir, static_cast<int>(k)), cloud, &local)) {
          std::lock_guard<std::mutex> lock(error_mutex);
          failed = true;
          *error = local;
        }
      }
    });
  }
  for (auto& t : pool) t.join();
  if (failed) return -1.0;
  std::ofstream(dir + "/calib.txt") << "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  std::ofstream times(dir + "/times.txt");
  times.precision(6);
  for (double t : data.times) times << std::fixed << t << "\n";
  if (!kitti::writePoses(dir + "/poses.txt", data.truth, error) ||
      !kitti::writePoses(dir + "/odom_poses.txt", data.odometry, error)) {
    return -1.0;
  }
  return data.truth.empty() ? 0.0 : static_cast<double>(points.load()) / data.truth.size();
}

}  // namespace sim
}  // namespace scan_context_loop
