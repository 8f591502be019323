#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/kitti_io.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

std::string tempPath(const std::string& name) { return testing::TempDir() + "/scl_kitti_io_" + name; }

TEST(KittiIo, ScanRoundTripAndCorruptFiles) {
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (int i = 0; i < 10; ++i) {
    pcl::PointXYZI p;
    p.x = i;
    p.y = -i;
    p.z = 0.5f * i;
    p.intensity = 0.1f * i;
    cloud.push_back(p);
  }
  std::string error;
  const std::string path = tempPath("scan.bin");
  ASSERT_TRUE(kitti::writeScan(path, cloud, &error)) << error;
  pcl::PointCloud<pcl::PointXYZI> back;
  ASSERT_TRUE(kitti::readScan(path, &back, &error)) << error;
  ASSERT_EQ(back.size(), 10u);
  EXPECT_EQ(back[7].y, -7.0f);
  EXPECT_FLOAT_EQ(back[7].intensity, 0.7f);

  std::ofstream(path, std::ios::binary | std::ios::app) << "xyz";  // 3 stray bytes
  EXPECT_FALSE(kitti::readScan(path, &back, &error));
  EXPECT_NE(error.find("multiple of 16"), std::string::npos) << error;
  EXPECT_FALSE(kitti::readScan(tempPath("missing.bin"), &back, &error));
}

TEST(KittiIo, PosesCalibAndTimes) {
  std::string error;
  std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  poses[1].translation() << 1.5, -2.0, 0.25;
  poses[1].linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::string path = tempPath("poses.txt");
  ASSERT_TRUE(kitti::writePoses(path, poses, &error)) << error;
  std::vector<Eigen::Isometry3d> back;
  ASSERT_TRUE(kitti::readPoses(path, &back, &error)) << error;
  ASSERT_EQ(back.size(), 2u);
  EXPECT_TRUE(back[1].matrix().isApprox(poses[1].matrix(), 1e-8));

  std::ofstream(tempPath("bad_poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1\n";  // 11 numbers
  EXPECT_FALSE(kitti::readPoses(tempPath("bad_poses.txt"), &back, &error));
  EXPECT_NE(error.find(":1:"), std::string::npos) << error;

  Eigen::Isometry3d tr;
  std::ofstream(tempPath("calib.txt")) << "P0: 1 2 3\nTr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n";
  ASSERT_TRUE(kitti::readCalibTr(tempPath("calib.txt"), &tr, &error)) << error;
  EXPECT_DOUBLE_EQ(tr(1, 3), 0.2);
  std::ofstream(tempPath("nocalib.txt")) << "P0: 1 2 3\n";
  EXPECT_FALSE(kitti::readCalibTr(tempPath("nocalib.txt"), &tr, &error));

  std::vector<double> times;
  std::ofstream(tempPath("times.txt")) << "0.0\n0.1\n\n0.2\n";
  ASSERT_TRUE(kitti::readTimes(tempPath("times.txt"), &times, &error)) << error;
  EXPECT_EQ(times.size(), 3u);
  std::ofstream(tempPath("bad_times.txt")) << "0.0\nnan\n";
  EXPECT_FALSE(kitti::readTimes(tempPath("bad_times.txt"), &times, &error));
}

TEST(KittiIo, APoseLineHoldsExactlyTwelveNumbers) {
  std::string error;
  std::vector<Eigen::Isometry3d> back;
  std::ofstream(tempPath("long_poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 0 7\n";
  EXPECT_FALSE(kitti::readPoses(tempPath("long_poses.txt"), &back, &error));
  EXPECT_NE(error.find(tempPath("long_poses.txt") + ":2:"), std::string::npos) << error;
  EXPECT_NE(error.find("12"), std::string::npos) << error;
  std::ofstream(tempPath("junk_poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0 x\n";
  EXPECT_FALSE(kitti::readPoses(tempPath("junk_poses.txt"), &back, &error));
  std::ofstream(tempPath("spaced_poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0 \t\r\n";
  EXPECT_TRUE(kitti::readPoses(tempPath("spaced_poses.txt"), &back, &error)) << error;
  Eigen::Isometry3d tr;
  std::ofstream(tempPath("long_calib.txt")) << "Tr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3 4\n";
  EXPECT_FALSE(kitti::readCalibTr(tempPath("long_calib.txt"), &tr, &error));
}

TEST(KittiIo, RealSequenceLidarPosesMatchTheReadme) {
  const std::string dir = test::sharedData() + "/kitti/08";
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Isometry3d tr;
  std::string error;
  ASSERT_TRUE(kitti::readPoses(dir + "/poses.txt", &poses, &error)) << error;
  ASSERT_TRUE(kitti::readCalibTr(dir + "/calib.txt", &tr, &error)) << error;
  EXPECT_EQ(poses.size(), 4071u);
  const auto lidar = kitti::lidarPoses(poses, tr);
  const Eigen::Vector3d t = (lidar[720].inverse() * lidar[1500]).translation();
  EXPECT_NEAR(t.x(), -2.08, 0.01);
  EXPECT_NEAR(t.y(), -2.03, 0.01);
  EXPECT_NEAR(t.z(), -1.06, 0.01);
}

}  // namespace
}  // namespace scan_context_loop
