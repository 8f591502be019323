// rostest: the database services and relocalization. Node a maps a drive, saves its database, is reset
// and loads it back, then closes loops from a second pass into the loaded session; node b loads the saved
// map and relocalizes a second run whose odometry has its own origin, by topic and by service.
#include <unistd.h>

#include <string>
#include <vector>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <gtest/gtest.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>

#include "harness.h"
#include "scan_context_loop/LoadDatabase.h"
#include "scan_context_loop/Relocalize.h"
#include "scan_context_loop/SaveDatabase.h"

namespace scan_context_loop {
namespace test {
namespace {

/// Expects `pose` (T_map<-sensor) to be keyframe k's true pose within 0.3 m and 1 deg.
void expectAt(const Drive& drive, int k, const geometry_msgs::Pose& pose) {
  ASSERT_GE(k, 0);
  Eigen::Isometry3d found;
  tf2::fromMsg(pose, found);
  const Eigen::Isometry3d error = drive.truth[k].inverse() * found;
  EXPECT_LT(error.translation().norm(), 0.3) << "keyframe " << k;
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), M_PI / 180.0) << "keyframe " << k;
}

TEST(Relocalization, SaveResetLoadThenRelocalizeASecondRunInTheSavedMap) {
  ros::NodeHandle a_nh("a"), b_nh("b");
  Harness a(a_nh), b(b_nh);
  ASSERT_TRUE(a.waitForNode(30.0));
  ASSERT_TRUE(b.waitForNode(30.0));
  std::vector<geometry_msgs::PoseWithCovarianceStamped> relocalized;
  std::mutex mutex;
  ros::Subscriber sub = b_nh.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
      "relocalization", 1000, [&](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        relocalized.push_back(*m);
      });

  const Drive drive = blockDrive(true, 7);
  const std::size_t n = drive.truth.size();
  a.publish(drive, 0, n, 15.0);
  ASSERT_TRUE(a.waitForKeyframes(n, 60.0));

  const std::string path = "/tmp/scan_context_loop_relocalization_" + std::to_string(getpid()) + ".scdb";
  SaveDatabase save;
  save.request.path = path;
  save.request.include_clouds = true;
  ASSERT_TRUE(ros::service::call("a/loop_closure/save_database", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  EXPECT_EQ(save.response.keyframes, n);

  // Saving where no file can be written: refused with the reason, nothing written, the database stays.
  SaveDatabase nowhere;
  nowhere.request.path = "/nonexistent_directory_" + std::to_string(getpid()) + "/map.scdb";
  ASSERT_TRUE(ros::service::call("a/loop_closure/save_database", nowhere));
  EXPECT_FALSE(nowhere.response.success);
  EXPECT_FALSE(nowhere.response.message.empty());
  EXPECT_EQ(nowhere.response.keyframes, n);
  EXPECT_NE(access(nowhere.request.path.c_str(), F_OK), 0);
  // A missing file: refused, the database stays.
  LoadDatabase missing;
  missing.request.path = path + ".missing";
  ASSERT_TRUE(ros::service::call("a/loop_closure/load_database", missing));
  EXPECT_FALSE(missing.response.success);
  EXPECT_EQ(missing.response.keyframes, n) << missing.response.message;
  // A file that is no database: refused, and the database stays.
  LoadDatabase bad;
  bad.request.path = "/proc/self/status";
  ASSERT_TRUE(ros::service::call("a/loop_closure/load_database", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_EQ(bad.response.keyframes, n) << bad.response.message;

  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("a/loop_closure/reset", reset));
  EXPECT_TRUE(reset.response.success);
  LoadDatabase load;
  load.request.path = path;
  ASSERT_TRUE(ros::service::call("a/loop_closure/load_database", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  EXPECT_EQ(load.response.keyframes, n);
  LoadDatabase map;
  map.request.path = path;
  ASSERT_TRUE(ros::service::call("b/loop_closure/load_database", map));
  ASSERT_TRUE(map.response.success) << map.response.message;

  // Node a: the drive again, later; every loop of the first pass's places reaches the loaded session.
  const std::size_t before = a.loops().size();
  a.base += ros::Duration(drive.times.back() + 10.0);
  a.publish(drive, 0, n / 2, 15.0);
  ASSERT_TRUE(a.waitForKeyframes(n + n / 2, 60.0));
  a.settle(3.0, 20.0);
  std::size_t into_loaded = 0;
  const auto loops = a.loops();
  for (std::size_t i = before; i < loops.size(); ++i) into_loaded += loops[i].match_session == 0 ? 1 : 0;
  EXPECT_GE(into_loaded, n / 8) << loops.size() - before << " loops after the load";

  // Node b: a second run over lap 1, its odometry starting from its own origin, 300 m and 90 deg away.
  Eigen::Isometry3d other = Eigen::Isometry3d::Identity();
  other.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  other.translation() = Eigen::Vector3d(300.0, -40.0, 0.0);
  ros::WallRate rate(15.0);
  for (std::size_t k = 0; k < n / 2 && ros::ok(); ++k) {
    nav_msgs::Odometry odom = b.odom(drive, k);
    odom.pose.pose = tf2::toMsg(other * drive.truth[k]);
    b.cloud_pub.publish(b.cloud(drive, k));
    b.odom_pub.publish(odom);
    rate.sleep();
  }
  ASSERT_TRUE(b.waitForKeyframes(n + n / 2, 60.0));
  b.settle(3.0, 20.0);
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_GE(relocalized.size(), n / 8);
    for (const auto& pose : relocalized) {
      EXPECT_EQ(pose.header.frame_id, "map");
      expectAt(drive, keyframeAt(drive, b.base, pose.header.stamp), pose.pose.pose);
      EXPECT_GT(pose.pose.covariance[0], 0.0);
    }
  }

  // On request: one cloud, nothing stored.
  Relocalize where;
  where.request.cloud = b.cloud(drive, 40);
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", where));
  ASSERT_TRUE(where.response.found) << where.response.message;
  expectAt(drive, 40, where.response.pose.pose.pose);
  EXPECT_EQ(where.response.match_session, 0u);
  // Clouds the node cannot use: answered, not found, with the reason; the map still answers after them.
  Relocalize no_z, empty;
  no_z.request.cloud = b.cloud(drive, 40);
  no_z.request.cloud.fields.erase(no_z.request.cloud.fields.begin() + 2);
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", no_z));
  EXPECT_FALSE(no_z.response.found);
  EXPECT_NE(no_z.response.message.find("cloud refused"), std::string::npos) << no_z.response.message;
  empty.request.cloud = b.cloud(drive, 40);
  empty.request.cloud.width = 0;
  empty.request.cloud.row_step = 0;
  empty.request.cloud.data.clear();
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", empty));
  EXPECT_FALSE(empty.response.found) << empty.response.message;
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", where));
  EXPECT_TRUE(where.response.found) << where.response.message;
  unlink(path.c_str());
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_relocalization"); }
