// A simulated team: routes that overlap the ways robots meet, each robot's own frame and clock, the team
// file, and each robot's topics and frames in its namespace.
#include <cmath>
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_sim/stack_shape.h"
#include "scan_context_sim/team_drive.h"
#include "scan_context_sim/team_file.h"

namespace scan_context_loop {
namespace sim {
namespace {

std::string teamTemp(const std::string& name) { return testing::TempDir() + "/scl_sim_team_" + name; }

/// Two straight drives along x: `a` over [0, 100] heading east, `b` over [50, 150] at `lateral` (y),
/// heading east or (reverse) west.
std::vector<PathPoint> straight(double from, double to, double y, bool west) {
  std::vector<PathPoint> path;
  for (double x = from; x <= to + 1e-9; x += 0.5) path.push_back({x, y, west ? M_PI : 0.0});
  if (west) std::reverse(path.begin(), path.end());
  return path;
}

TEST(Team, OverlapMeasuresHowTwoDrivesMeet) {
  const std::vector<PathPoint> a = straight(0, 100, 0, false);
  const Overlap same = overlapOf(a, straight(50, 150, 0.2, false));
  EXPECT_NEAR(same.same_lane, 50.0, 1.0);
  // Within reach (4.5 m) counts up to 4.5 m past b's end.
  EXPECT_GE(same.any, 50.0 - 1.0);
  EXPECT_LE(same.any, 50.0 + 4.5 + 1.0);
  EXPECT_EQ(same.reverse, 0.0);
  const Overlap lane = overlapOf(a, straight(50, 150, -3.5, false));
  EXPECT_GE(lane.other_lane, 50.0 - 1.0);
  EXPECT_LE(lane.other_lane, 50.0 + 3.5);  // 4.5 m reach at 3.5 m to the side: 2.8 m past the end
  EXPECT_EQ(lane.same_lane, 0.0);
  const Overlap reverse = overlapOf(a, straight(50, 150, 3.5, true));
  EXPECT_GE(reverse.reverse, 50.0 - 1.0);
  EXPECT_LE(reverse.reverse, 50.0 + 3.5);
  EXPECT_EQ(reverse.same_lane + reverse.other_lane, 0.0);
  EXPECT_EQ(overlapOf(a, straight(50, 150, 20.0, false)).any, 0.0);
}

TEST(Team, RoutesOverlapTheWaysRealTeamsMeet) {
  const std::vector<RobotDrive> team = teamDrives(TeamOptions());
  ASSERT_EQ(team.size(), 3u);
  for (std::size_t r = 0; r < team.size(); ++r) {
    EXPECT_EQ(team[r].id, "robot" + std::to_string(r + 1));
    const std::size_t keyframes = keyframesEvery(team[r].drive.path, 2.0).size();
    EXPECT_GE(keyframes, 150u) << team[r].id;
    EXPECT_LE(keyframes, 250u) << team[r].id;
  }
  // Every pair drives at least 100 m of street together (within 4.5 m), both ways round.
  for (std::size_t a = 0; a < team.size(); ++a) {
    for (std::size_t b = 0; b < team.size(); ++b) {
      if (a == b) continue;
      EXPECT_GE(overlapOf(team[a].drive.path, team[b].drive.path).any, 100.0) << a << " on " << b;
    }
  }
  const Overlap o12 = overlapOf(team[0].drive.path, team[1].drive.path);
  const Overlap o13 = overlapOf(team[0].drive.path, team[2].drive.path);
  const Overlap o23 = overlapOf(team[1].drive.path, team[2].drive.path);
  // robot2 drives beside robot1 a lane over from where both start, then follows robot1's street (same way
  // and lane).
  EXPECT_GE(o12.same_lane, 60.0);
  EXPECT_GE(o12.other_lane, 100.0);
  // robot3 drives robot1's streets the other way.
  EXPECT_GE(o13.reverse, 150.0);
  // robot2 and robot3 meet both ways.
  EXPECT_GE(o23.same_lane, 90.0);
  EXPECT_GE(o23.reverse, 50.0);
  // Stretches only one robot sees: more than 15 m from every other robot's path.
  int robots_alone = 0;
  for (std::size_t r = 0; r < team.size(); ++r) {
    double alone = 0.0;
    const std::vector<PathPoint>& path = team[r].drive.path;
    for (std::size_t k = 1; k < path.size(); ++k) {
      bool seen = false;
      for (std::size_t e = 0; e < team.size() && !seen; ++e) {
        if (e == r) continue;
        for (const PathPoint& q : team[e].drive.path) {
          seen = seen || std::hypot(path[k].x - q.x, path[k].y - q.y) < 15.0;
        }
      }
      if (!seen) alone += std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y);
    }
    if (alone >= 25.0) ++robots_alone;
  }
  EXPECT_GE(robots_alone, 2);
}

TEST(Team, LargerTeamsShareStreetsToo) {
  TeamOptions options;
  options.robots = kMaxTeam;
  const std::vector<RobotDrive> team = teamDrives(options);
  ASSERT_EQ(team.size(), static_cast<std::size_t>(kMaxTeam));
  for (std::size_t a = 0; a < team.size(); ++a) {
    double most = 0.0;
    for (std::size_t b = 0; b < team.size(); ++b) {
      if (a != b) most = std::max(most, overlapOf(team[a].drive.path, team[b].drive.path).same_lane);
    }
    EXPECT_GE(most, 50.0) << team[a].id;
  }
}

TEST(Team, WorldStreetsCoverEveryRouteOnce) {
  const std::vector<RobotDrive> team = teamDrives(TeamOptions());
  const std::vector<std::vector<PathPoint>> streets = teamStreets(team);
  double driven = 0.0, furnished = 0.0;
  for (const RobotDrive& r : team) driven += distanceAlong(r.drive.path).back();
  for (const auto& s : streets) furnished += distanceAlong(s).back();
  // The lanes two robots drive are walked once: less than all the drives together.
  EXPECT_LT(furnished, driven - 150.0);
  // Every point of every drive is on a street the world is built along.
  for (const RobotDrive& r : team) {
    for (const PathPoint& p : r.drive.path) {
      double nearest = 1e9;
      for (const auto& s : streets) {
        for (const PathPoint& q : s) nearest = std::min(nearest, std::hypot(p.x - q.x, p.y - q.y));
      }
      ASSERT_LT(nearest, 1.5) << r.id << " at " << p.x << ", " << p.y;
    }
  }
}

TEST(Team, ChecksItsOptions) {
  TeamOptions options;
  EXPECT_EQ(checkTeam(options), "");
  options.robots = 0;
  EXPECT_NE(checkTeam(options), "");
  options.robots = kMaxTeam + 1;
  EXPECT_NE(checkTeam(options), "");
  options.robots = 3;
  options.start_offsets = {0.0, 60.0};
  EXPECT_NE(checkTeam(options), "");
  options.start_offsets = {0.0, -1.0, 60.0};
  EXPECT_NE(checkTeam(options), "");
  options.start_offsets = {0.0, 0.0, 60.0};
  EXPECT_EQ(checkTeam(options), "");
}

TEST(Team, StartOffsetsAreTheWorldClockOfEachStart) {
  TeamOptions options;
  options.start_offsets = {15.0, 15.0, 75.0};
  const std::vector<RobotDrive> team = teamDrives(options);
  EXPECT_DOUBLE_EQ(team[0].start, 0.0);
  EXPECT_DOUBLE_EQ(team[1].start, 0.0);
  EXPECT_DOUBLE_EQ(team[2].start, 60.0);
  for (const RobotDrive& r : team) EXPECT_DOUBLE_EQ(r.drive.times.front(), 0.0);
}

TEST(Team, TeamFileRoundTripsAndRejectsBadLines) {
  std::vector<TeamMember> team(2);
  team[0] = {"robot1", 0.0, Eigen::Isometry3d::Identity()};
  team[1].id = "robot_2";
  team[1].start_seconds = 60.25;
  team[1].world_from_start =
      Eigen::Translation3d(211.75, -5.25, 1.9) * Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.01, -0.02, 1.0).normalized());
  const std::string path = teamTemp("team.txt");
  std::string error;
  ASSERT_TRUE(writeTeamFile(path, team, &error)) << error;
  std::vector<TeamMember> read;
  ASSERT_TRUE(readTeamFile(path, &read, &error)) << error;
  ASSERT_EQ(read.size(), 2u);
  for (std::size_t r = 0; r < 2; ++r) {
    EXPECT_EQ(read[r].id, team[r].id);
    EXPECT_DOUBLE_EQ(read[r].start_seconds, team[r].start_seconds);
    EXPECT_TRUE(read[r].world_from_start.isApprox(team[r].world_from_start, 1e-8));
  }
  const std::string one = "robot1 0 1 0 0 0 0 1 0 0 0 0 1 0\n";
  for (const std::string& bad :
       {std::string("robot-1 0 1 0 0 0 0 1 0 0 0 0 1 0\n"), one + one,
        std::string("robot1 -1 1 0 0 0 0 1 0 0 0 0 1 0\n"), std::string("robot1 0 1 0 0 0 0 1 0 0 0 0 1\n"),
        std::string("robot1 0 2 0 0 0 0 1 0 0 0 0 1 0\n"), std::string("# none\n")}) {
    std::ofstream(path) << bad;
    EXPECT_FALSE(readTeamFile(path, &read, &error)) << bad;
  }
  std::ofstream(path) << "# comment\n\n" << one;
  EXPECT_TRUE(readTeamFile(path, &read, &error)) << error;
}

TEST(Team, EachRobotsSequenceComposesWithItsStartToTheWorldTruth) {
  TeamOptions options;
  options.start_offsets = {0.0, 0.0, 60.0};
  const std::vector<RobotDrive> drives = teamDrives(options);
  WorldOptions world_options;
  const World world = generateWorld(teamStreets(drives), world_options);
  SensorModel sensor;
  ASSERT_TRUE(sensorPreset("vlp16", &sensor));
  sensor.columns = 60;  // a coarse scan: this checks frames and clocks, not the clouds
  std::vector<TeamMember> members;
  std::vector<Eigen::Isometry3d> drift_at_end;
  const std::string out = teamTemp("sequence");
  std::string error;
  for (std::size_t r = 0; r < drives.size(); ++r) {
    DriftOptions drift;
    drift.seed = robotSeed(1, static_cast<int>(r));
    const SequenceData data = robotSequence(world, drives[r], sensor.mount_height, 2.0, drift);
    ASSERT_GT(writeSequence(out + "_" + drives[r].id, world, sensor, data, 0.0, drift.seed, 2, &error), 0.0) << error;
    members.push_back({drives[r].id, drives[r].start, data.origin});
  }
  ASSERT_TRUE(writeTeamFile(out + "_team.txt", members, &error)) << error;
  std::vector<TeamMember> team;
  ASSERT_TRUE(readTeamFile(out + "_team.txt", &team, &error)) << error;
  ASSERT_EQ(team.size(), drives.size());
  for (std::size_t r = 0; r < drives.size(); ++r) {
    const std::string dir = out + "_" + team[r].id;
    std::vector<Eigen::Isometry3d> truth, odom;
    std::vector<double> times;
    ASSERT_TRUE(kitti::readPoses(dir + "/poses.txt", &truth, &error)) << error;
    ASSERT_TRUE(kitti::readPoses(dir + "/odom_poses.txt", &odom, &error)) << error;
    ASSERT_TRUE(kitti::readTimes(dir + "/times.txt", &times, &error)) << error;
    const std::vector<std::size_t> keyframes = keyframesEvery(drives[r].drive.path, 2.0);
    ASSERT_EQ(truth.size(), keyframes.size());
    ASSERT_EQ(odom.size(), keyframes.size());
    ASSERT_EQ(times.size(), keyframes.size());
    // Truth and odometry are the identity at the robot's first keyframe: its odometry frame's origin.
    EXPECT_TRUE(truth.front().isApprox(Eigen::Isometry3d::Identity(), 1e-9));
    EXPECT_TRUE(odom.front().isApprox(Eigen::Isometry3d::Identity(), 1e-9));
    EXPECT_EQ(times.front(), 0.0);
    // T_world<-start x poses.txt[k] is the drive's pose there, start + times[k] its world clock.
    EXPECT_DOUBLE_EQ(team[r].start_seconds, r == 2 ? 60.0 : 0.0);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      const PathPoint& p = drives[r].drive.path[keyframes[k]];
      const Eigen::Isometry3d world_pose = team[r].world_from_start * truth[k];
      const Eigen::Isometry3d expected = sensorPose(world, p, sensor.mount_height);
      ASSERT_LT((world_pose.translation() - expected.translation()).norm(), 1e-4) << team[r].id << " keyframe " << k;
      ASSERT_TRUE(world_pose.linear().isApprox(expected.linear(), 1e-6)) << team[r].id << " keyframe " << k;
      // Over the path point (the sensor leans with the 1 % slope: within 2 cm).
      ASSERT_LT(std::hypot(world_pose.translation().x() - p.x, world_pose.translation().y() - p.y), 0.02);
      const Eigen::Vector3d forward = world_pose.linear().col(0);
      ASSERT_NEAR(std::remainder(std::atan2(forward.y(), forward.x()) - p.heading, 2 * M_PI), 0.0, 1e-3);
      ASSERT_NEAR(team[r].start_seconds + times[k], drives[r].start + drives[r].drive.times[keyframes[k]], 1e-5);
    }
    // The odometry drifts away from the truth, each robot its own way.
    drift_at_end.push_back(truth.back().inverse() * odom.back());
    EXPECT_GT(drift_at_end.back().translation().norm(), 0.2) << team[r].id;
  }
  for (std::size_t a = 0; a < drift_at_end.size(); ++a) {
    for (std::size_t b = a + 1; b < drift_at_end.size(); ++b) {
      EXPECT_GT((drift_at_end[a].translation() - drift_at_end[b].translation()).norm(), 0.1) << a << ", " << b;
    }
  }
  // Robots start from one junction (a depot) but each in its own place and heading: their frames differ.
  EXPECT_GT((team[0].world_from_start.translation() - team[1].world_from_start.translation()).norm(), 2.0);
  EXPECT_GT(
      Eigen::AngleAxisd(team[0].world_from_start.linear().transpose() * team[2].world_from_start.linear()).angle(),
      M_PI / 4);
}

TEST(Team, EachRobotsTopicsAndFramesInItsNamespace) {
  const StackShape robot = forRobot(StackShape(), "robot2");
  EXPECT_EQ(robot.cloud_topic, "/robot2/keyframe_cloud");
  EXPECT_EQ(robot.odom_topic, "/robot2/keyframe_odom");
  EXPECT_EQ(robotTopic("robot2", "ground_truth"), "/robot2/ground_truth");
  EXPECT_EQ(robot.odom_frame, "robot2/odom");
  EXPECT_EQ(robot.cloud_frame, "robot2/velodyne");
  EXPECT_EQ(robot.child_frame, "robot2/velodyne");
  // tf1's leading '/' goes; the stack's fixed transforms are the robot's own.
  const StackShape lego = forRobot(*findStackShape("lego_loam"), "robot1");
  EXPECT_EQ(lego.odom_frame, "robot1/camera_init");
  for (const FixedTransform& f : fixedTransforms(lego)) {
    EXPECT_EQ(f.parent.rfind("robot1/", 0), 0u) << f.parent;
    EXPECT_EQ(f.child.rfind("robot1/", 0), 0u) << f.child;
  }
  // One robot alone: the shape as it is.
  EXPECT_EQ(forRobot(StackShape(), "").cloud_topic, "keyframe_cloud");
  EXPECT_EQ(forRobot(StackShape(), "").odom_frame, "odom");
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
