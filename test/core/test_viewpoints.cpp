// Virtual lateral viewpoints: the grid seen from a point beside the sensor, and the detector finding a
// revisit one lane over through them.
#include <cmath>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/detector.h"
#include "test_scenes.h"
#include "../common/planar.h"

namespace scan_context_loop {
namespace {

using test::kDeg;
using test::yawOf;

TEST(Viewpoints, GridFromAViewpointIsTheGridOfTheShiftedCloud) {
  Config config;
  const auto cloud = test::streetScene(3);
  const HeightGrid from_view = makeHeightGrid(cloud, config, Eigen::Vector2f(1.5f, -3.0f));
  const HeightGrid shifted = makeHeightGrid(test::rotateTranslate(cloud, 0.0, -1.5, 3.0), config);
  ASSERT_EQ(from_view.points_used, shifted.points_used);
  EXPECT_LT((from_view.heights - shifted.heights).cwiseAbs().maxCoeff(), 1e-4f);
  EXPECT_EQ(from_view.occupied, shifted.occupied);
  // And it is not the grid of the real viewpoint.
  EXPECT_GT((from_view.heights - makeHeightGrid(cloud, config).heights).cwiseAbs().maxCoeff(), 1.0f);
}

TEST(Viewpoints, GridsOfSeveralViewpointsInOnePassAreEachViewpointsGridOfTheTurnedCloud) {
  Config config;
  const auto cloud = test::streetScene(3);
  // A gravity alignment of a few degrees in roll and pitch, applied while binning.
  const Eigen::Matrix3f level =
      (Eigen::AngleAxisf(0.06f, Eigen::Vector3f::UnitX()) * Eigen::AngleAxisf(-0.04f, Eigen::Vector3f::UnitY()))
          .toRotationMatrix();
  const pcl::PointCloud<pcl::PointXYZ> turned = rotatedCloud(viewOf(cloud), level);
  const std::vector<Eigen::Vector2f> views = {Eigen::Vector2f::Zero(), Eigen::Vector2f(0.0f, 2.5f),
                                              Eigen::Vector2f(0.0f, -2.5f)};
  const std::vector<HeightGrid> grids = makeHeightGrids(viewOf(cloud), config, views, level);
  ASSERT_EQ(grids.size(), views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    const HeightGrid one = makeHeightGrid(turned, config, views[v]);
    EXPECT_EQ(grids[v].points_used, one.points_used) << "view " << v;
    EXPECT_LT((grids[v].heights - one.heights).cwiseAbs().maxCoeff(), 1e-4f) << "view " << v;
    EXPECT_EQ(grids[v].occupied, one.occupied) << "view " << v;
  }
  // The turn is applied: the same views of the cloud as it is differ.
  EXPECT_GT((grids[0].heights - makeHeightGrid(cloud, config).heights).cwiseAbs().maxCoeff(), 0.1f);
  EXPECT_TRUE(makeHeightGrids(viewOf(cloud), config, {}, level).empty());
}

TEST(Viewpoints, LateralViewpointsAreNearestFirstOnBothSides) {
  Config config;
  EXPECT_EQ(lateralViewpoints(config).size(), 2u);  // one a side by default
  config.lateral_offset_step = 0.0;
  EXPECT_TRUE(lateralViewpoints(config).empty());
  config.lateral_offset_step = 2.5;
  config.lateral_offset_count = 2;
  const auto views = lateralViewpoints(config);
  ASSERT_EQ(views.size(), 4u);
  EXPECT_EQ(views[0], Eigen::Vector2f(0.0f, 2.5f));
  EXPECT_EQ(views[1], Eigen::Vector2f(0.0f, -2.5f));
  EXPECT_EQ(views[2], Eigen::Vector2f(0.0f, 5.0f));
  EXPECT_EQ(views[3], Eigen::Vector2f(0.0f, -5.0f));
}

/// The street seen at the first visit, then again 4 m to the left and turned by 30 degrees.
struct LaneChange {
  pcl::PointCloud<pcl::PointXYZ> first = test::streetScene(11);
  // T_query<-match = (Rz(30 deg), (0, 4)): the match's sensor stood 4 m to the query's left.
  pcl::PointCloud<pcl::PointXYZ> again = test::rotateTranslate(first, 30.0 * kDeg, 0.0, 4.0);

  Detection run(Config config) const {
    config.exclude_recent_frames = 0;
    LoopDetector detector(config);
    KeyframeInfo info;
    info.stamp = 0.0;
    detector.process(viewOf(first), info);
    info.stamp = 1.0;
    return detector.process(viewOf(again), info);
  }
};

TEST(Viewpoints, DetectorFindsARevisitOneLaneOverFromTheMatchingViewpoint) {
  const LaneChange scene;
  Config plain;
  plain.verification.enabled = false;  // the descriptor's own loop, with the viewpoint as its prior
  plain.lateral_offset_step = 0.0;
  const Detection without = scene.run(plain);
  ASSERT_NE(without.query.best(), nullptr);
  Config config = plain;
  config.lateral_offset_step = 4.0;
  const Detection with = scene.run(config);
  ASSERT_NE(with.query.best(), nullptr);
  const Candidate& best = *with.query.best();
  EXPECT_EQ(best.index, 0u);
  EXPECT_NEAR(best.viewpoint.x(), 0.0, 1e-9);
  EXPECT_NEAR(best.viewpoint.y(), 4.0, 1e-9);
  EXPECT_LT(best.alignment.distance, 0.5 * without.query.best()->alignment.distance)
      << "from the viewpoint " << best.alignment.distance << ", from the sensor "
      << without.query.best()->alignment.distance;
  EXPECT_TRUE(with.query.matched);
  EXPECT_NEAR(best.alignment.yaw, 30.0 * kDeg, 3.0 * kDeg);
  // The loop carries the viewpoint as its translation prior.
  ASSERT_EQ(with.loops.size(), 1u);
  EXPECT_NEAR(with.loops[0].relative().translation().y(), 4.0, 1e-9);
}

TEST(Viewpoints, VerificationStartsFromTheViewpointAndRecoversTheLaneChange) {
  const LaneChange scene;
  Config config;
  config.lateral_offset_step = 4.0;
  config.verification.enabled = true;
  config.verification.threshold = 0.5;
  config.consistency_min_support = 0;  // a single loop: report it at once
  const Detection d = scene.run(config);
  ASSERT_TRUE(d.verified) << (d.verifications.empty() ? "nothing verified" : d.verifications.back().result.reason);
  ASSERT_EQ(d.loops.size(), 1u);
  const Eigen::Isometry3d relative = d.loops[0].relative();
  EXPECT_LT((relative.translation() - Eigen::Vector3d(0.0, 4.0, 0.0)).norm(), 0.1)
      << relative.translation().transpose();
  EXPECT_NEAR(yawOf(relative), 30.0 * kDeg, 0.5 * kDeg);
}

}  // namespace
}  // namespace scan_context_loop
