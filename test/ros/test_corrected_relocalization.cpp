// rostest: a map saved with the backend's corrections relocalizes in the corrected frame, within 0.3 m / 1 deg
// of the truth. Node a maps two laps around a block: lap 1's odometry is right, lap 2's drifts (0.5% of
// distance and 0.02 deg/m) from lap 1's end, so the uncorrected lap 2 lies metres off. The pose_graph
// backend pulls lap 2 onto lap 1 with a's loops and a learns the corrected poses (corrected_path); its saved
// database holds them. Node b loads that map and relocalizes a second drive along lap 2 a metre to the side
// (its odometry from its own origin): each pose must be the truth, and where the corrected map puts that
// place, and clearly not where the uncorrected one would.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <tf2_eigen/tf2_eigen.h>

#include "harness.h"
#include "topic_watch.h"
#include "scan_context_loop/LoadDatabase.h"
#include "scan_context_loop/Relocalize.h"
#include "scan_context_loop/SaveDatabase.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {
namespace {

struct PoseError {
  double metres = 0.0, degrees = 0.0;
};

PoseError errorOf(const Eigen::Isometry3d& truth, const Eigen::Isometry3d& found) {
  const Eigen::Isometry3d e = truth.inverse() * found;
  return {e.translation().norm(), Eigen::AngleAxisd(e.linear()).angle() * 180.0 / M_PI};
}

/// The keyframes' poses in the saved database at `path` (default settings, as the launch file's), by index;
/// every one must be there, with a pose, and marked corrected.
std::vector<Eigen::Isometry3d> savedPoses(const std::string& path, std::size_t n) {
  PriorSessions sessions;
  std::string error;
  EXPECT_TRUE(readDatabaseFile(path, Config(), &sessions, &error)) << error;
  EXPECT_EQ(sessions.keyframes.size(), n);
  std::vector<Eigen::Isometry3d> poses;
  for (const Keyframe& k : sessions.keyframes) {
    EXPECT_TRUE(k.info.pose.has_value());
    EXPECT_TRUE(k.corrected_pose) << "keyframe " << poses.size();
    poses.push_back(k.info.pose.value_or(Eigen::Isometry3d::Identity()));
  }
  return poses;
}

/// Polls a's diagnostics until `key` satisfies `ready`; returns the last value seen (-1: none).
long waitForValue(const DiagnosticsWatch& diagnostics, const std::string& key, const std::function<bool(long)>& ready) {
  long value = -1;
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(20.0);
  while (ros::ok() && ros::WallTime::now() < end) {
    value = diagnostics.value(key, ros::WallTime::now(), 5.0);
    if (ready(value)) break;
  }
  return value;
}

TEST(CorrectedRelocalization, AMapSavedWithTheCorrectionsRelocalizesInTheCorrectedFrame) {
  ros::NodeHandle a_nh("a"), b_nh("b");
  Harness a(a_nh), b(b_nh);
  Latest<nav_msgs::Path> corrected(a_nh, "corrected_path");
  DiagnosticsWatch diagnostics(a_nh, "a/loop_closure");
  Collected<geometry_msgs::PoseWithCovarianceStamped> relocalizations(b_nh, "relocalization");
  ASSERT_TRUE(a.waitForNode(30.0));
  ASSERT_TRUE(b.waitForNode(30.0));
  ASSERT_TRUE(ros::service::waitForService("a/pose_graph/publish_map", 30000));

  // Two laps around the block, the second 3 m further out. The odometry starts at the first true pose, so
  // the backend, which holds the first keyframe where the odometry put it, corrects into the truth's frame.
  // Lap 1's odometry is right. Over lap 2 it drifts 0.5% of distance and 0.02 deg/m, composed onto lap 1's
  // end (no slip: a single step that is wrong would be spread over lap 1 too), so the uncorrected lap 2 lies
  // metres off; the loops into lap 1 pull each lap-2 keyframe back.
  const Drive drive = blockDrive(false, 5);
  const std::size_t n = drive.truth.size();
  std::size_t lap2 = 1;  // lap 2's first keyframe: the first on its bottom street, 3 m below lap 1's
  while (lap2 < n && drive.truth[lap2].translation().y() > -1.5) ++lap2;
  ASSERT_GT(lap2, n / 3);
  ASSERT_LT(lap2, 2 * n / 3);
  std::vector<Eigen::Isometry3d> odometry(drive.truth.begin(), drive.truth.begin() + lap2);
  sim::DriftOptions lap2_drift;
  lap2_drift.translation_per_metre = 0.005;
  lap2_drift.yaw_per_metre = 0.02;
  lap2_drift.seed = 4;
  const std::vector<Eigen::Isometry3d> lap2_odometry =
      sim::driftedOdometry({drive.truth.begin() + lap2 - 1, drive.truth.end()}, lap2_drift);
  const Eigen::Isometry3d lap1_end = odometry.back() * lap2_odometry.front().inverse();
  for (std::size_t j = 1; j < lap2_odometry.size(); ++j) odometry.push_back(lap1_end * lap2_odometry[j]);
  ASSERT_EQ(odometry.size(), n);
  a.odometry = &odometry;
  a.publish(drive, 0, n, 10.0);
  ASSERT_TRUE(a.waitForKeyframes(n, 60.0));
  a.settle(3.0, 60.0);
  nav_msgs::Path path;
  ASSERT_TRUE(corrected.waitFor([&](const nav_msgs::Path& p) { return p.poses.size() == n; }, 30.0, &path))
      << "no corrected path with every keyframe (" << n << "); the latest has " << path.poses.size();
  EXPECT_EQ(path.header.frame_id, "map");
  EXPECT_EQ(waitForValue(diagnostics, "corrected keyframes", [&](long v) { return v == long(n); }), long(n))
      << "node a did not learn every corrected pose";

  const std::string map = "/tmp/scan_context_loop_corrected_" + std::to_string(getpid()) + ".scdb";
  SaveDatabase save;
  save.request.path = map;
  save.request.include_clouds = true;
  ASSERT_TRUE(ros::service::call("a/loop_closure/save_database", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  ASSERT_TRUE(corrected.waitFor([&](const nav_msgs::Path& p) { return p.poses.size() == n; }, 1.0, &path));

  // The file holds the corrected path's poses, marked corrected; the correction moved them by metres.
  const std::vector<Eigen::Isometry3d> saved = savedPoses(map, n);
  ASSERT_EQ(saved.size(), n);
  double moved = 0.0, residual = 0.0, residual_sq = 0.0, drifted[2] = {0.0, 0.0};
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(path.poses[k].header.stamp, a.base + ros::Duration(drive.times[k]));
    Eigen::Isometry3d pose;
    tf2::fromMsg(path.poses[k].pose, pose);
    EXPECT_LT((saved[k].matrix() - pose.matrix()).cwiseAbs().maxCoeff(), 1e-9) << "keyframe " << k;
    moved = std::max(moved, (saved[k].translation() - odometry[k].translation()).norm());
    const double r = errorOf(drive.truth[k], saved[k]).metres;
    residual = std::max(residual, r);
    residual_sq += r * r;
    double& lap_drift = drifted[k < lap2 ? 0 : 1];
    lap_drift = std::max(lap_drift, errorOf(drive.truth[k], odometry[k]).metres);
  }
  std::printf(
      "%zu keyframes (lap 2 from %zu): odometry off the truth by up to %.2f m on lap 1, %.2f m on lap 2; "
      "corrected poses moved up to %.2f m from the odometry, off the truth by up to %.3f m (RMS %.3f m)\n",
      n, lap2, drifted[0], drifted[1], moved, residual, std::sqrt(residual_sq / n));
  EXPECT_GT(moved, 1.0) << "the correction is too small to show anything";

  // Bad paths reach a's worker, are counted and change nothing (each waits for the last to be counted:
  // a path waiting replaces an earlier one).
  ros::Publisher bad_pub = a_nh.advertise<nav_msgs::Path>("corrected_path", 1);
  const long refused = waitForValue(diagnostics, "corrected path poses refused", [](long v) { return v >= 0; });
  ros::WallDuration(0.5).sleep();  // a connects to the new publisher
  nav_msgs::Path empty, other_frame = path;
  empty.header.frame_id = "map";
  other_frame.header.frame_id = "odom";
  bad_pub.publish(empty);
  EXPECT_EQ(waitForValue(diagnostics, "corrected path poses refused", [&](long v) { return v >= refused + 1; }),
            refused + 1);
  bad_pub.publish(other_frame);
  EXPECT_EQ(waitForValue(diagnostics, "corrected path poses refused", [&](long v) { return v >= refused + 2; }),
            refused + 2);
  EXPECT_EQ(diagnostics.value("corrected keyframes", ros::WallTime::now(), 5.0), long(n));

  LoadDatabase load;
  load.request.path = map;
  ASSERT_TRUE(ros::service::call("b/loop_closure/load_database", load));
  ASSERT_TRUE(load.response.success) << load.response.message;

  // Node b: lap 2 again, a metre to the left (between the laps' lanes), turned 4 deg, so its scans are not
  // the map's; its odometry from its own origin 300 m and 90 deg away.
  Drive other = drive;
  Eigen::Isometry3d lane = Eigen::Isometry3d::Identity();
  lane.translation() = Eigen::Vector3d(0.0, 1.0, 0.0);
  lane.linear() = Eigen::AngleAxisd(4.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (auto& pose : other.truth) pose = pose * lane;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  origin.translation() = Eigen::Vector3d(300.0, -40.0, 0.0);
  b.base = a.base + ros::Duration(drive.times.back() + 100.0);
  std::vector<Eigen::Isometry3d> b_odometry;
  for (const auto& pose : other.truth) b_odometry.push_back(origin * pose);
  b.odometry = &b_odometry;
  b.publish(other, lap2, n, 10.0);
  ASSERT_TRUE(b.waitForKeyframes(n + (n - lap2), 60.0));
  b.settle(3.0, 20.0);

  // Each relocalized pose must be the truth: the corrected frame is the truth's. It must also be where
  // the corrected map puts the query (the matched keyframe's saved pose and the true relative pose match
  // -> query), and the same with the map's uncorrected (odometry) poses must be clearly off for some: the
  // matched lap-2 keyframes' odometry is metres off.
  std::map<ros::Time, std::size_t> match_of;
  for (const auto& loop : b.loops()) {
    const int m = keyframeAt(drive, a.base, loop.match_stamp);
    if (loop.verified && m >= 0) match_of[loop.query_stamp] = static_cast<std::size_t>(m);
  }
  const auto relocalized = relocalizations.messages();
  EXPECT_GE(relocalized.size(), n / 8);
  PoseError worst, uncorrected, absolute, map_residual;
  double absolute_sq = 0.0, odometry_sq = 0.0;
  std::size_t into_lap2 = 0;
  for (const auto& message : relocalized) {
    EXPECT_EQ(message.header.frame_id, "map");
    const int q = keyframeAt(drive, b.base, message.header.stamp);
    ASSERT_GE(q, 0);
    ASSERT_EQ(match_of.count(message.header.stamp), 1u) << "no verified loop for the relocalization of " << q;
    const std::size_t m = match_of[message.header.stamp];
    const Eigen::Isometry3d relative = drive.truth[m].inverse() * other.truth[q];
    Eigen::Isometry3d found;
    tf2::fromMsg(message.pose.pose, found);
    const PoseError t = errorOf(other.truth[q], found), e = errorOf(saved[m] * relative, found),
                    u = errorOf(odometry[m] * relative, found), r = errorOf(drive.truth[m], saved[m]);
    EXPECT_LT(t.metres, 0.3) << "keyframe " << q << " matched map keyframe " << m;
    EXPECT_LT(t.degrees, 1.0) << "keyframe " << q << " matched map keyframe " << m;
    EXPECT_LT(e.metres, 0.3) << "keyframe " << q << " matched map keyframe " << m;
    EXPECT_LT(e.degrees, 1.0) << "keyframe " << q << " matched map keyframe " << m;
    const double o = errorOf(other.truth[q], odometry[m] * relative).metres;
    worst = {std::max(worst.metres, e.metres), std::max(worst.degrees, e.degrees)};
    uncorrected = {std::max(uncorrected.metres, u.metres), std::max(uncorrected.degrees, u.degrees)};
    absolute = {std::max(absolute.metres, t.metres), std::max(absolute.degrees, t.degrees)};
    map_residual = {std::max(map_residual.metres, r.metres), std::max(map_residual.degrees, r.degrees)};
    absolute_sq += t.metres * t.metres;
    odometry_sq += o * o;
    if (m >= lap2) ++into_lap2;
  }
  const double count = std::max<std::size_t>(relocalized.size(), 1);
  std::printf(
      "%zu relocalizations (%zu into lap 2): off the truth by up to %.3f m / %.3f deg (RMS %.3f m; the "
      "uncorrected map's placement: RMS %.3f m); off where the corrected map puts them by up to %.3f m / "
      "%.3f deg, off where the uncorrected map would by up to %.3f m / %.3f deg; the matched keyframes' "
      "corrected poses off the truth by up to %.3f m / %.3f deg\n",
      relocalized.size(), into_lap2, absolute.metres, absolute.degrees, std::sqrt(absolute_sq / count),
      std::sqrt(odometry_sq / count), worst.metres, worst.degrees, uncorrected.metres, uncorrected.degrees,
      map_residual.metres, map_residual.degrees);
  EXPECT_GT(uncorrected.metres, 1.0) << "the uncorrected map puts the relocalized poses where the corrected one does";

  // On request: the same frame, on lap 2.
  const std::size_t asked = lap2 + (n - lap2) / 3;
  Relocalize where;
  where.request.cloud = b.cloud(other, asked);
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", where));
  ASSERT_TRUE(where.response.found) << where.response.message;
  EXPECT_EQ(where.response.pose.header.frame_id, "map");
  ASSERT_LT(where.response.match_id, n);
  Eigen::Isometry3d found;
  tf2::fromMsg(where.response.pose.pose.pose, found);
  const std::size_t m = where.response.match_id;
  const PoseError e = errorOf(saved[m] * drive.truth[m].inverse() * other.truth[asked], found),
                  t = errorOf(other.truth[asked], found);
  EXPECT_LT(e.metres, 0.3);
  EXPECT_LT(e.degrees, 1.0);
  EXPECT_LT(t.metres, 0.3);
  EXPECT_LT(t.degrees, 1.0);
  std::printf("~relocalize of keyframe %zu (matched %zu): off the truth by %.3f m / %.3f deg\n", asked, m, t.metres,
              t.degrees);
  unlink(map.c_str());
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) {
  return scan_context_loop::test::runRosTests(argc, argv, "test_corrected_relocalization");
}
