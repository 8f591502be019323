// The corrected poses a backend publishes (corrected_path): each path corrects one session this node
// recorded, matched by the keyframes' exact stamps (the newest session holding them: a replay's); bad
// input is counted and skipped, and loaded sessions are never corrected.
#include <cmath>
#include <limits>

#include <boost/make_shared.hpp>
#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "loop_closure/corrected_poses.h"
#include "shared/stored_keyframe.h"

namespace scan_context_loop {
namespace {

ros::Time stampOf(int k) { return ros::Time(100u, static_cast<std::uint32_t>(k) * 100000000u + 7u); }

/// Sessions 0 and 1 (a replay): keyframes 0-4 and 5-9 at the same stamps; session 2 (keyframes 10-12),
/// treated as loaded from a file, at stamps of its own.
class CorrectedPosesTest : public ::testing::Test {
 protected:
  CorrectedPosesTest() : detector_(config()), corrected_("corrected_test", &counters_) {
    ros::Time::init();  // the throttled logs read the time
    pcl::PointCloud<pcl::PointXYZ> cloud;
    for (int i = 0; i < 3600; ++i) {
      const double a = i * 2.0 * M_PI / 3600.0, r = 10.0 + 5.0 * std::sin(3.0 * a);
      cloud.push_back(pcl::PointXYZ(r * std::cos(a), r * std::sin(a), (i % 7) * 0.3));
    }
    for (int session = 0; session < 3; ++session) {
      for (int k = 0; k < (session < 2 ? 5 : 3); ++k) {
        KeyframeInfo info;
        setKeyframeStamp(session < 2 ? stampOf(k) : ros::Time(500.0 + k), &info);
        info.pose = Eigen::Isometry3d(Eigen::Translation3d(2.0 * k, 0.0, 0.0));
        EXPECT_TRUE(detector_.process(viewOf(cloud), info).accepted);
      }
      detector_.startSession();
    }
    corrected_.loaded(detector_.database(), 10);
  }
  static Config config() {
    Config c;
    c.verification.enabled = false;
    return c;
  }

  /// A path in `frame` with a pose at each of keyframes `ks`' stamps (x = 100 + k).
  static nav_msgs::Path path(const std::vector<int>& ks, const std::string& frame = "map") {
    nav_msgs::Path p;
    p.header.frame_id = frame;
    for (int k : ks) {
      geometry_msgs::PoseStamped pose;
      pose.header.stamp = stampOf(k);
      pose.pose.position.x = 100.0 + k;
      pose.pose.orientation.w = 1.0;
      p.poses.push_back(pose);
    }
    return p;
  }

  void apply(const nav_msgs::Path& p) {
    ASSERT_TRUE(corrected_.offer(boost::make_shared<nav_msgs::Path>(p)));
    corrected_.applyNewest(detector_.database());
  }

  /// The corrected keyframes and their x.
  std::map<std::size_t, double> table() const {
    std::map<std::size_t, double> out;
    if (const auto c = corrected_.corrections()) {
      for (const auto& [i, pose] : *c) out[i] = pose.translation().x();
    }
    return out;
  }

  LoopDetector detector_;
  NodeCounters counters_;
  CorrectedPoses corrected_;
};

TEST_F(CorrectedPosesTest, APathCorrectsTheNewestRecordedSessionAtItsStamps) {
  apply(path({0, 1, 2, 3}));
  EXPECT_EQ(table(), (std::map<std::size_t, double>{{5, 100}, {6, 101}, {7, 102}, {8, 103}})) << "the replay's";
  EXPECT_EQ(counters_.corrected_keyframes.load(), 4u);
  EXPECT_EQ(counters_.corrections_refused.load(), 0u);
  EXPECT_EQ(corrected_.frame(), "map");
  EXPECT_EQ(corrected_.version(), 1u);
  // The next path replaces the session's corrections; its bad poses are counted and skipped.
  nav_msgs::Path next = path({0, 1, 2, 3, 4});
  next.poses[2].pose.position.y = std::numeric_limits<double>::quiet_NaN();
  next.poses[3].pose.orientation.w = 2.0;
  next.poses.push_back(next.poses[0]);
  next.poses.back().header.stamp = ros::Time(300.0);  // no keyframe
  apply(next);
  EXPECT_EQ(table(), (std::map<std::size_t, double>{{5, 100}, {6, 101}, {9, 104}}));
  EXPECT_EQ(counters_.corrections_refused.load(), 2u);
  EXPECT_EQ(counters_.corrections_unknown.load(), 1u);
  EXPECT_EQ(counters_.corrected_keyframes.load(), 3u);
}

TEST_F(CorrectedPosesTest, PathsThatCannotApplyChangeNothing) {
  apply(path({0, 1}));
  const auto before = table();
  apply(path({0, 1, 2}, "odom"));  // another frame than before
  apply(path({}));                 // empty
  apply(path({0, 1}, ""));         // no frame
  nav_msgs::Path loaded = path({});
  loaded.header.frame_id = "map";
  for (int k = 0; k < 3; ++k) {
    geometry_msgs::PoseStamped pose;
    pose.header.stamp = ros::Time(500.0 + k);  // session 2's, loaded: never corrected
    pose.pose.orientation.w = 1.0;
    loaded.poses.push_back(pose);
  }
  apply(loaded);
  EXPECT_EQ(table(), before);
  EXPECT_EQ(counters_.corrections_refused.load(), 1u + 1u + 1u);
  EXPECT_EQ(counters_.corrections_unknown.load(), 3u) << "a loaded session's stamps name no recorded keyframe";
  EXPECT_EQ(corrected_.version(), 1u);
  corrected_.reset();
  EXPECT_FALSE(corrected_.corrections());
  EXPECT_EQ(counters_.corrected_keyframes.load(), 0u);
  EXPECT_TRUE(corrected_.frame().empty());
}

TEST_F(CorrectedPosesTest, AfterAResetTheBackendsOldKeyframesAreUnknownNotRefused) {
  apply(path({0, 1, 2}));
  corrected_.reset();
  // The node's ~reset emptied its database; the backend, not reset, still publishes the old keyframes.
  const LoopDetector emptied(config());
  ASSERT_TRUE(corrected_.offer(boost::make_shared<nav_msgs::Path>(path({0, 1, 2}))));
  corrected_.applyNewest(emptied.database());
  EXPECT_FALSE(corrected_.corrections());
  EXPECT_EQ(counters_.corrections_unknown.load(), 3u);
  EXPECT_EQ(counters_.corrections_refused.load(), 0u);
  EXPECT_EQ(counters_.corrected_keyframes.load(), 0u);
}

TEST_F(CorrectedPosesTest, StampsOfAnotherRecordedSessionAreRefused) {
  // Session 0's stamps are session 1's too (a replay): a path naming keyframe 0 corrects the replay, so
  // session 0 holds no stamp of its own. Another session recorded here with stamps of its own shows it.
  LoopDetector detector(config());
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 3600; ++i) {
    const double a = i * 2.0 * M_PI / 3600.0, r = 10.0 + 5.0 * std::sin(3.0 * a);
    cloud.push_back(pcl::PointXYZ(r * std::cos(a), r * std::sin(a), (i % 7) * 0.3));
  }
  for (int session = 0; session < 2; ++session) {
    for (int k = 0; k < 3; ++k) {
      KeyframeInfo info;
      setKeyframeStamp(stampOf(3 * session + k), &info);
      info.pose = Eigen::Isometry3d(Eigen::Translation3d(2.0 * k, 0.0, 0.0));
      ASSERT_TRUE(detector.process(viewOf(cloud), info).accepted);
    }
    detector.startSession();
  }
  CorrectedPoses corrected("corrected_test", &counters_);
  ASSERT_TRUE(corrected.offer(boost::make_shared<nav_msgs::Path>(path({0, 1, 3, 9}))));
  corrected.applyNewest(detector.database());
  ASSERT_TRUE(corrected.corrections());
  EXPECT_EQ(corrected.corrections()->size(), 2u) << "keyframes 0 and 1 of the first session";
  EXPECT_EQ(counters_.corrections_refused.load(), 1u) << "keyframe 3: the second session's";
  EXPECT_EQ(counters_.corrections_unknown.load(), 1u) << "stamp 9: no keyframe";
}

TEST_F(CorrectedPosesTest, OnlyTheNewestOfThePathsWaitingIsApplied) {
  EXPECT_TRUE(corrected_.offer(boost::make_shared<nav_msgs::Path>(path({0}))));
  EXPECT_FALSE(corrected_.offer(boost::make_shared<nav_msgs::Path>(path({1, 2})))) << "a task is queued already";
  corrected_.applyNewest(detector_.database());
  EXPECT_EQ(table(), (std::map<std::size_t, double>{{6, 101}, {7, 102}}));
  corrected_.applyNewest(detector_.database());  // nothing waits: nothing changes
  EXPECT_EQ(corrected_.version(), 1u);
  EXPECT_TRUE(corrected_.offer(boost::make_shared<nav_msgs::Path>(path({3}))));
}

}  // namespace
}  // namespace scan_context_loop
