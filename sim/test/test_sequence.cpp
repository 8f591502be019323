// Writing sequences: read back with kitti_io.h, identical for a seed whatever the threads.
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {
namespace {

std::string sequenceTemp(const std::string& name) { return testing::TempDir() + "/scl_sim_" + name; }

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The first 60 m of the procedural drive, a keyframe every 5 m, a coarse VLP-16.
struct SmallDrive {
  World world;
  SensorModel sensor;
  SequenceData data;
};

SmallDrive smallDrive(std::uint32_t seed) {
  SmallDrive d;
  std::vector<PathPoint> path = proceduralPath();
  path.resize(120);
  WorldOptions options;
  options.seed = seed;
  d.world = generateWorld(path, options);
  EXPECT_TRUE(sensorPreset("vlp16", &d.sensor));
  d.sensor.columns = 360;
  for (std::size_t k : keyframesEvery(path, 5.0)) {
    d.data.truth.push_back(sensorPose(d.world, path[k], d.sensor.mount_height));
    d.data.times.push_back(0.5 * d.data.times.size());
  }
  DriftOptions drift;
  drift.seed = seed;
  d.data.odometry = driftedOdometry(d.data.truth, drift);
  return d;
}

TEST(Sequence, WrittenFilesReadBackWithKittiIo) {
  const SmallDrive d = smallDrive(1);
  const std::string dir = sequenceTemp("written");
  std::string error;
  const double mean_points = writeSequence(dir, d.world, d.sensor, d.data, 0.0, 1, 2, &error);
  ASSERT_GT(mean_points, 1000.0) << error;

  std::vector<Eigen::Isometry3d> truth, odom;
  ASSERT_TRUE(kitti::readPoses(dir + "/poses.txt", &truth, &error)) << error;
  ASSERT_TRUE(kitti::readPoses(dir + "/odom_poses.txt", &odom, &error)) << error;
  Eigen::Isometry3d tr;
  ASSERT_TRUE(kitti::readCalibTr(dir + "/calib.txt", &tr, &error)) << error;
  EXPECT_TRUE(tr.isApprox(Eigen::Isometry3d::Identity()));
  std::vector<double> times;
  ASSERT_TRUE(kitti::readTimes(dir + "/times.txt", &times, &error)) << error;
  ASSERT_EQ(truth.size(), d.data.truth.size());
  ASSERT_EQ(odom.size(), d.data.truth.size());
  ASSERT_EQ(times.size(), d.data.truth.size());
  // Readers take LiDAR poses as inv(Tr) * P * Tr: with the identity Tr, the poses as simulated.
  const auto lidar = kitti::lidarPoses(truth, tr);
  double points = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_TRUE(lidar[k].isApprox(d.data.truth[k], 1e-6)) << k;
    EXPECT_TRUE(odom[k].isApprox(d.data.odometry[k], 1e-6)) << k;
    EXPECT_NEAR(times[k], d.data.times[k], 1e-6);
    pcl::PointCloud<pcl::PointXYZI> cloud;
    ASSERT_TRUE(kitti::readScan(kitti::scanPath(dir, static_cast<int>(k)), &cloud, &error)) << error;
    points += cloud.size();
    // The same scan as ray-cast directly with the writer's seed for keyframe k.
    const auto direct = scan(d.world, d.sensor, d.data.truth[k], d.data.times[k], (std::uint64_t{1} << 32) ^ k);
    ASSERT_EQ(cloud.size(), direct.size());
    for (std::size_t i = 0; i < cloud.size(); i += 97) {
      EXPECT_EQ(cloud[i].x, direct[i].x);
      EXPECT_EQ(cloud[i].intensity, direct[i].intensity);
    }
  }
  EXPECT_DOUBLE_EQ(points / truth.size(), mean_points);
}

TEST(Sequence, SameSeedSameFilesWhateverTheThreadsOtherSeedOtherWorld) {
  std::string error;
  const SmallDrive a = smallDrive(5);
  ASSERT_GT(writeSequence(sequenceTemp("seed5_1"), a.world, a.sensor, a.data, 0.0, 5, 1, &error), 0.0) << error;
  const SmallDrive again = smallDrive(5);
  ASSERT_GT(writeSequence(sequenceTemp("seed5_3"), again.world, again.sensor, again.data, 0.0, 5, 3, &error), 0.0) << error;
  const SmallDrive b = smallDrive(6);
  ASSERT_GT(writeSequence(sequenceTemp("seed6"), b.world, b.sensor, b.data, 0.0, 6, 2, &error), 0.0) << error;
  int same_as_other_seed = 0;
  for (std::size_t k = 0; k < a.data.truth.size(); ++k) {
    const std::string scan = "/velodyne/" + std::string(6 - std::to_string(k).size(), '0') + std::to_string(k) + ".bin";
    ASSERT_EQ(bytesOf(sequenceTemp("seed5_1") + scan), bytesOf(sequenceTemp("seed5_3") + scan)) << k;
    same_as_other_seed += bytesOf(sequenceTemp("seed5_1") + scan) == bytesOf(sequenceTemp("seed6") + scan);
  }
  EXPECT_EQ(same_as_other_seed, 0);
  EXPECT_EQ(bytesOf(sequenceTemp("seed5_1") + "/odom_poses.txt"), bytesOf(sequenceTemp("seed5_3") + "/odom_poses.txt"));
  EXPECT_NE(bytesOf(sequenceTemp("seed5_1") + "/odom_poses.txt"), bytesOf(sequenceTemp("seed6") + "/odom_poses.txt"));
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
