// Several robots over ROS (test/ros/team.test): three robots' loop-closure nodes in their own namespaces on
// one master, fed a simulated team's bag, exchange only topics and services. One node starts 30 s late,
// one is restarted while the bag plays. Checked: the loops between robots are verified and true, none is
// reported twice, the late and the restarted node close loops into the others' keyframes, and, with the
// backend, each robot's frame in the shared map. The bytes the team exchanged are measured and printed.
#include <atomic>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <ros/master.h>
#include <ros/network.h>
#include <tf2_eigen/tf2_eigen.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include "harness.h"
#include "scan_context_loop/KeyframeRecord.h"
#include "scan_context_loop/LoopClosure.h"
#include "scan_context_sim/team_file.h"
#include "topic_watch.h"

namespace scan_context_loop {
namespace test {
namespace {

using Loops = Collected<scan_context_loop::LoopClosure>;
using Odometry = Collected<nav_msgs::Odometry>;

/// Stops node `name` as rosnode kill does (its master API's shutdown); roslaunch respawns it.
bool killNode(const std::string& name) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = name;
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return false;
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue call, answer;
  call[0] = ros::this_node::getName();
  call[1] = "the test restarts it";
  return client.execute("shutdown", call, answer);
}

/// A robot's poses by stamp (its ground truth or its odometry), in its own odometry frame.
std::map<ros::Time, Eigen::Isometry3d> byStamp(const Odometry& topic) {
  std::map<ros::Time, Eigen::Isometry3d> poses;
  for (const auto& m : topic.messages()) {
    Eigen::Isometry3d pose;
    tf2::fromMsg(m.pose.pose, pose);
    poses[m.header.stamp] = pose;
  }
  return poses;
}

double degrees(const Eigen::Matrix3d& rotation) { return Eigen::AngleAxisd(rotation).angle() * 180.0 / M_PI; }

/// The latest value of `key` in the diagnostics of each node whose status name contains `node` part.
double diagnosticSum(const std::vector<diagnostic_msgs::DiagnosticArray>& messages, const std::string& key) {
  std::map<std::string, double> latest;  // by status name
  for (const auto& array : messages) {
    for (const auto& status : array.status) {
      for (const auto& kv : status.values) {
        if (kv.key == key) latest[status.name + "@" + status.hardware_id] = std::stod(kv.value);
      }
    }
  }
  double sum = 0.0;
  for (const auto& [name, value] : latest) sum += value;
  return sum;
}

TEST(Team, ThreeRobotsCloseTrueLoopsIntoEachOthersKeyframes) {
  ros::NodeHandle nh, pnh("~");
  std::vector<sim::TeamMember> team;
  std::string error;
  ASSERT_TRUE(sim::readTeamFile(pnh.param("team_file", std::string()), &team, &error)) << error;
  const std::string late = pnh.param("late_robot", std::string());
  const std::string restarted = pnh.param("restarted_robot", std::string());
  const double restart_at = pnh.param("restart_at", 20.0);  // bag seconds
  const bool backend = pnh.param("backend", false);
  const ros::Time base(pnh.param("bag_start", 1.6e9));

  std::map<std::string, std::unique_ptr<Loops>> loops;
  std::map<std::string, std::unique_ptr<Odometry>> truth, odometry;
  std::map<std::string, std::unique_ptr<Latest<nav_msgs::Path>>> corrected;
  std::map<std::string, Eigen::Isometry3d> start;
  double late_start = 0.0;  // the late robot's first keyframe [bag seconds]
  for (const auto& member : team) {
    if (member.id == late) late_start = member.start_seconds;
    const std::string& r = member.id;
    start[r] = member.world_from_start;
    loops[r] = std::make_unique<Loops>(nh, "/" + r + "/loop_closures");
    truth[r] = std::make_unique<Odometry>(nh, "/" + r + "/ground_truth");
    odometry[r] = std::make_unique<Odometry>(nh, "/" + r + "/keyframe_odom");
    if (backend) corrected[r] = std::make_unique<Latest<nav_msgs::Path>>(nh, "/" + r + "/corrected_path");
  }
  Collected<scan_context_loop::KeyframeRecord> records(nh, "/team/keyframe_records");
  // What each robot sends when a base station does the work: its keyframe clouds and their odometry.
  std::atomic<std::size_t> input_bytes{0};
  std::vector<ros::Subscriber> inputs;
  for (const auto& member : team) {
    inputs.push_back(nh.subscribe<sensor_msgs::PointCloud2>(
        "/" + member.id + "/keyframe_cloud", 100, [&input_bytes](const sensor_msgs::PointCloud2ConstPtr& m) {
          input_bytes += ros::serialization::serializationLength(*m);
        }));
  }
  Collected<diagnostic_msgs::DiagnosticArray> diagnostics(nh, "/diagnostics");

  // The bag plays once every topic has a subscriber (ours included); it is over when no ground truth has
  // come for a while after some did.
  const ros::WallTime limit = ros::WallTime::now() + ros::WallDuration(pnh.param("time_limit", 400.0));
  bool killed = false;
  ros::Time killed_at;
  std::size_t heard = 0;
  ros::WallTime last_news = ros::WallTime::now();
  while (ros::ok() && ros::WallTime::now() < limit) {
    std::size_t now = 0;
    bool every_robot = true;  // a late robot's drive begins after the others' may have ended
    for (const auto& [r, t] : truth) {
      now += t->count();
      every_robot = every_robot && t->count() > 0;
    }
    if (now != heard) {
      heard = now;
      last_news = ros::WallTime::now();
    }
    if (every_robot && (ros::WallTime::now() - last_news).toSec() > 8.0) break;
    if (!killed && !restarted.empty() && truth[restarted]->count() > 0 &&
        truth[restarted]->messages().back().header.stamp > base + ros::Duration(restart_at)) {
      ASSERT_TRUE(killNode("/" + restarted + "/loop_closure")) << "could not stop " << restarted << "'s node";
      killed = true;
      killed_at = truth[restarted]->messages().back().header.stamp;
    }
    ros::WallDuration(0.2).sleep();
  }
  ASSERT_GT(heard, 0u) << "the bag was not played";
  ros::WallDuration(10.0).sleep();  // the last keyframes' matches
  if (!restarted.empty()) ASSERT_TRUE(killed) << restarted << "'s node was never restarted";

  std::map<std::string, std::map<ros::Time, Eigen::Isometry3d>> truth_at, odometry_at;
  for (const auto& [r, t] : truth) truth_at[r] = byStamp(*t);
  for (const auto& [r, o] : odometry) odometry_at[r] = byStamp(*o);
  const auto world = [&](const std::string& r, const ros::Time& stamp, Eigen::Isometry3d* pose) {
    const auto it = truth_at[r].find(stamp);
    if (it == truth_at[r].end()) return false;
    *pose = start[r] * it->second;
    return true;
  };

  std::map<std::pair<std::string, std::string>, int> between;  // inter-robot loops per (query, match) robot
  std::set<std::tuple<std::string, ros::Time, std::string, ros::Time>> seen;
  int duplicates = 0, late_into_earlier = 0, after_restart = 0, intra = 0;
  double worst_m = 0.0, worst_deg = 0.0;
  for (const auto& [robot, topic] : loops) {
    for (const auto& loop : topic->messages()) {
      EXPECT_EQ(loop.query_robot, robot) << "a loop on " << robot << "'s topic from another robot's keyframe";
      // Either direction of one pair of keyframes counts once.
      const auto key = loop.query_robot < loop.match_robot ||
                               (loop.query_robot == loop.match_robot && loop.query_stamp < loop.match_stamp)
                           ? std::make_tuple(loop.query_robot, loop.query_stamp, loop.match_robot, loop.match_stamp)
                           : std::make_tuple(loop.match_robot, loop.match_stamp, loop.query_robot, loop.query_stamp);
      if (!seen.insert(key).second) ++duplicates;
      if (loop.match_robot == loop.query_robot) {
        ++intra;
        continue;
      }
      SCOPED_TRACE(loop.query_robot + " " + std::to_string(loop.query_stamp.toSec()) + " -> " + loop.match_robot + " " +
                   std::to_string(loop.match_stamp.toSec()));
      EXPECT_TRUE(loop.verified);
      Eigen::Isometry3d query, match, measured;
      ASSERT_TRUE(world(loop.query_robot, loop.query_stamp, &query)) << "no keyframe of the bag at the query stamp";
      ASSERT_TRUE(world(loop.match_robot, loop.match_stamp, &match)) << "no keyframe of the bag at the match stamp";
      tf2::fromMsg(loop.relative_pose, measured);
      const Eigen::Isometry3d error = (query.inverse() * match).inverse() * measured;
      worst_m = std::max(worst_m, error.translation().norm());
      worst_deg = std::max(worst_deg, degrees(error.linear()));
      EXPECT_LT(error.translation().norm(), 1.0);
      EXPECT_LT(degrees(error.linear()), 2.0);
      ++between[{loop.query_robot, loop.match_robot}];
      if (loop.query_robot == late && loop.match_stamp < base + ros::Duration(late_start)) {
        ++late_into_earlier;  // a keyframe stored before the late robot's node ran: fetched when it joined
      }
      if (killed && loop.query_robot == restarted && loop.query_stamp > killed_at) ++after_restart;
    }
  }
  std::ostringstream report;
  report << "inter-robot loops:";
  for (const auto& [pair, n] : between) report << " " << pair.first << "->" << pair.second << " " << n;
  report << "; intra-robot " << intra << "; worst error " << worst_m << " m, " << worst_deg << " deg; late robot into "
         << "earlier keyframes " << late_into_earlier << ", restarted robot after its restart " << after_restart;
  EXPECT_EQ(duplicates, 0);
  // Every pair of robots that shares streets closes loops (in either direction).
  for (std::size_t a = 0; a < team.size(); ++a) {
    for (std::size_t b = a + 1; b < team.size(); ++b) {
      const int n = between[{team[a].id, team[b].id}] + between[{team[b].id, team[a].id}];
      EXPECT_GE(n, 3) << team[a].id << " and " << team[b].id << ": " << report.str();
    }
  }
  if (!late.empty()) EXPECT_GE(late_into_earlier, 3) << late << " found no loop into what was mapped before it came";
  if (!restarted.empty()) EXPECT_GE(after_restart, 3) << restarted << "'s restarted node closed no loop";

  // What the team exchanged: records on the topic, and everything the nodes counted (the restarted node's
  // first run is lost from its counters).
  std::size_t record_bytes = 0;
  for (const auto& r : records.messages()) record_bytes += ros::serialization::serializationLength(r);
  const std::size_t shared = std::max<std::size_t>(1, records.count());
  const auto status = diagnostics.messages();
  const double sent = diagnosticSum(status, "team bytes sent"),
               fetched = diagnosticSum(status, "team registration data fetched");
  std::size_t keyframes = 0;
  for (const auto& [r, o] : odometry) keyframes += o->count();
  report << "; records " << records.count() << " on the topic, " << record_bytes / shared << " bytes each; "
         << "registration data fetched " << fetched << "; bytes sent by the nodes " << sent << " ("
         << sent / std::max<std::size_t>(1, keyframes) << " per keyframe)";
  std::size_t odometry_bytes = 0;
  for (const auto& [r, o] : odometry) {
    for (const auto& m : o->messages()) odometry_bytes += ros::serialization::serializationLength(m);
  }
  for (auto& input : inputs) input.shutdown();
  report << "; a robot's keyframe cloud and odometry "
         << (input_bytes + odometry_bytes) / std::max<std::size_t>(1, keyframes) << " bytes per keyframe";
  if (pnh.param("records_expected", true)) {
    EXPECT_GT(records.count(), 0u);
    EXPECT_LT(record_bytes / shared, 8000u) << "a record is a descriptor, a few kilobytes";
  }

  if (backend) {
    const std::string anchor = team.front().id;
    for (const auto& member : team) {
      const std::string& r = member.id;
      nav_msgs::Path path;
      ASSERT_TRUE(corrected[r]->waitFor([](const nav_msgs::Path& p) { return !p.poses.empty(); }, 10.0, &path))
          << "no corrected path of " << r;
      // The robot's frame in the map (the anchor's odometry frame) from its first keyframe's corrected pose
      // (its odometry is the identity there), against the truth.
      Eigen::Isometry3d first;
      tf2::fromMsg(path.poses.front().pose, first);
      const Eigen::Isometry3d truth_frame = start[anchor].inverse() * start[r];
      const Eigen::Isometry3d frame_error = truth_frame.inverse() * first;
      report << "; " << r << " frame error " << frame_error.translation().norm() << " m "
             << degrees(frame_error.linear()) << " deg";
      EXPECT_LT(frame_error.translation().norm(), 0.5) << r;
      EXPECT_LT(degrees(frame_error.linear()), 1.0) << r;
      // The merged map's trajectory error against the robot's odometry alone (placed at its true start).
      double corrected_sq = 0.0, odometry_sq = 0.0;
      std::size_t n = 0;
      for (const auto& pose : path.poses) {
        const auto t = truth_at[r].find(pose.header.stamp);
        const auto o = odometry_at[r].find(pose.header.stamp);
        if (t == truth_at[r].end() || o == odometry_at[r].end()) continue;
        Eigen::Isometry3d c;
        tf2::fromMsg(pose.pose, c);
        const Eigen::Isometry3d in_map = truth_frame * t->second;
        corrected_sq += (c.translation() - in_map.translation()).squaredNorm();
        odometry_sq += ((truth_frame * o->second).translation() - in_map.translation()).squaredNorm();
        ++n;
      }
      ASSERT_GT(n, 0u);
      report << ", ATE " << std::sqrt(corrected_sq / n) << " m merged vs " << std::sqrt(odometry_sq / n)
             << " m odometry alone";
    }
  }
  std::cout << "[team] " << report.str() << std::endl;
  RecordProperty("team", report.str());
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_team"); }
