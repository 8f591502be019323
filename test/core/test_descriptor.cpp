#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/descriptor.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

using test::rotateTranslate;
using test::sectorCentredScene;

pcl::PointCloud<pcl::PointXYZ> onePoint(double range, double azimuth_deg, double z) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  const double a = azimuth_deg * M_PI / 180.0;
  cloud.push_back(pcl::PointXYZ(static_cast<float>(range * std::cos(a)), static_cast<float>(range * std::sin(a)),
                                static_cast<float>(z)));
  return cloud;
}

TEST(HeightGrid, BinsFollowTheDocumentedGeometry) {
  Config config;  // 20 rings of 4 m, 60 sectors of 6 degrees, lidar_height 2
  struct Case {
    double range, azimuth_deg;
    int ring, sector;
  };
  const Case cases[] = {{1.0, 3.0, 0, 0},           {5.0, 9.0, 1, 1},     {79.9, 357.0, 19, 59},
                        {10.0, 180.0 + 3.0, 2, 30}, {42.0, -3.0, 10, 59}, {0.5, 90.0 + 1.0, 0, 15}};
  for (const auto& c : cases) {
    const HeightGrid grid = makeHeightGrid(onePoint(c.range, c.azimuth_deg, 1.5), config);
    ASSERT_EQ(grid.points_used, 1u) << c.range << " " << c.azimuth_deg;
    EXPECT_EQ(grid.occupied(c.ring, c.sector), 1) << c.range << " " << c.azimuth_deg;
    EXPECT_FLOAT_EQ(grid.heights(c.ring, c.sector), 3.5f);
    EXPECT_EQ(grid.occupied.cast<int>().sum(), 1);
  }
}

TEST(HeightGrid, KeepsTheMaximumHeightPerBin) {
  Config config;
  pcl::PointCloud<pcl::PointXYZ> cloud = onePoint(20.0, 30.0 + 2.0, -1.0);
  cloud += onePoint(20.5, 30.0 + 4.0, 4.0);
  cloud += onePoint(21.0, 30.0 + 1.0, 0.5);
  const HeightGrid grid = makeHeightGrid(cloud, config);
  EXPECT_FLOAT_EQ(grid.heights(5, 5), 6.0f);
}

TEST(HeightGrid, BinsWithNegativeOrZeroHeightsStayOccupied) {
  Config config;
  config.lidar_height = 0.0;
  pcl::PointCloud<pcl::PointXYZ> cloud = onePoint(10.0, 10.0, -3.0);
  cloud += onePoint(30.0, 100.0, 0.0);
  const HeightGrid grid = makeHeightGrid(cloud, config);
  EXPECT_EQ(grid.occupied.cast<int>().sum(), 2);
  EXPECT_FLOAT_EQ(grid.heights(2, 1), -3.0f);
  const Descriptor d = makeDescriptor(grid, config);
  EXPECT_EQ(d.occupied_columns, 2);
  EXPECT_FALSE(d.empty());
}

TEST(HeightGrid, RotatingBySectorsShiftsColumns) {
  Config config;
  const double sector = 2.0 * M_PI / config.num_sectors;
  const auto cloud = sectorCentredScene(7, config.num_sectors, config.max_radius);
  const HeightGrid base = makeHeightGrid(cloud, config);
  for (int k : {1, 5, 29, 30, 59, -1, -7, -31}) {
    const HeightGrid rotated = makeHeightGrid(rotateTranslate(cloud, k * sector), config);
    for (int s = 0; s < config.num_sectors; ++s) {
      const int moved = ((s + k) % config.num_sectors + config.num_sectors) % config.num_sectors;
      ASSERT_TRUE(rotated.heights.col(moved).isApprox(base.heights.col(s), 1e-6f)) << "k = " << k << ", column " << s;
      ASSERT_EQ(rotated.occupied.col(moved), base.occupied.col(s)) << "k = " << k;
    }
  }
}

TEST(Descriptor, KeysAndUnitColumns) {
  Config config;
  const auto cloud = test::streetScene(3);
  for (RingKeyType type : {RingKeyType::kOccupancy, RingKeyType::kMeanHeight}) {
    config.ring_key = type;
    const HeightGrid grid = makeHeightGrid(cloud, config);
    const Descriptor d = makeDescriptor(grid, config);
    ASSERT_EQ(d.ring_key.size(), 20u);
    ASSERT_EQ(d.sector_key.size(), 60u);
    for (int r = 0; r < config.num_rings; ++r) {
      const float expected =
          type == RingKeyType::kOccupancy ? grid.occupied.row(r).cast<float>().mean() : grid.heights.row(r).mean();
      EXPECT_NEAR(d.ring_key[r], expected, 1e-5f);
    }
    for (int s = 0; s < config.num_sectors; ++s) {
      Eigen::Map<const Eigen::Matrix<std::int8_t, Eigen::Dynamic, 1>> column(&d.unit_columns[s * config.num_rings],
                                                                             config.num_rings);
      const float length = column.cast<float>().norm() / kUnitColumnScale;
      if (d.column_occupied[s]) {
        EXPECT_NEAR(length, 1.0f, quantisedColumnTolerance(config.num_rings));
        // Each entry is its height's share of the column's length, rounded to a 127th.
        const float norm = grid.heights.col(s).norm();
        for (int r = 0; r < config.num_rings; ++r) {
          EXPECT_NEAR(column[r], grid.heights(r, s) / norm * kUnitColumnScale, 0.5f + 1e-4f);
        }
      } else {
        EXPECT_EQ(length, 0.0f);
      }
      EXPECT_NEAR(d.sector_key[s], grid.heights.col(s).mean(), 1e-5f);
    }
  }
}

TEST(Descriptor, SameResultForEveryPointTypeAndFitsTheMemoryBudget) {
  Config config;
  const auto xyz = test::streetScene(5);
  pcl::PointCloud<pcl::PointXYZI> xyzi;
  pcl::PointCloud<pcl::PointXYZRGB> xyzrgb;
  for (const auto& p : xyz) {
    pcl::PointXYZI q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    q.intensity = 0.3f;
    xyzi.push_back(q);
    pcl::PointXYZRGB c;
    c.x = p.x;
    c.y = p.y;
    c.z = p.z;
    xyzrgb.push_back(c);
  }
  const Descriptor a = makeDescriptor(xyz, config);
  const Descriptor b = makeDescriptor(xyzi, config);
  const Descriptor c = makeDescriptor(xyzrgb, config);
  EXPECT_EQ(a.unit_columns, b.unit_columns);
  EXPECT_EQ(a.unit_columns, c.unit_columns);
  EXPECT_EQ(a.ring_key, b.ring_key);
  // int8 unit columns (1,200 bytes at 20 x 60), the occupancy and the float keys: about 1.6 KB.
  EXPECT_LE(a.bytes(), 1700u);
}

TEST(HeightGrid, EveryMemoryLayoutBinsAlike) {
  // The binning reads x, y, z first in 16- or 32-byte points with a loop of its own; any other layout
  // point by point. Both must give the same grids, with NaN and Inf points, a turn and three viewpoints.
  Config config;
  const auto scene = test::streetScene(5);
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : scene) points.emplace_back(p.x, p.y, p.z);
  points.emplace_back(NAN, 1.0f, 0.0f);
  points.emplace_back(3.0f, INFINITY, 0.0f);
  ASSERT_GT(points.size(), 2000u);
  const auto& layouts = test::pointLayouts();
  const std::vector<Eigen::Vector2f> views = {Eigen::Vector2f::Zero(), {0.0f, 2.5f}, {0.0f, -2.5f}};
  const Eigen::Matrix3f turn = Eigen::AngleAxisf(0.1f, Eigen::Vector3f(1, 1, 0).normalized()).toRotationMatrix();
  for (const Eigen::Matrix3f& rotation : {Eigen::Matrix3f(Eigen::Matrix3f::Identity()), turn}) {
    std::vector<std::vector<HeightGrid>> grids;
    for (const auto& [stride, offset] : layouts) {
      std::vector<std::uint8_t> bytes;
      grids.push_back(makeHeightGrids(test::inLayout(points, stride, offset, &bytes), config, views, rotation));
    }
    for (std::size_t l = 1; l < layouts.size(); ++l) {
      SCOPED_TRACE("stride " + std::to_string(layouts[l].first) + ", x at " + std::to_string(layouts[l].second));
      ASSERT_EQ(grids[l].size(), views.size());
      for (std::size_t v = 0; v < views.size(); ++v) {
        EXPECT_TRUE(grids[l][v].heights == grids[0][v].heights) << "view " << v;
        EXPECT_TRUE(grids[l][v].occupied == grids[0][v].occupied) << "view " << v;
        EXPECT_EQ(grids[l][v].points_used, grids[0][v].points_used);
        EXPECT_EQ(grids[l][v].points_skipped, grids[0][v].points_skipped);
      }
    }
    EXPECT_GT(grids[0][0].occupied.cast<int>().sum(), 100);
    EXPECT_GE(grids[0][0].points_skipped, 2u) << "the NaN and Inf points";
  }
}

}  // namespace
}  // namespace scan_context_loop
