#include "test_scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/kitti_io.h"

namespace scan_context_loop {
namespace test {

Descriptor descriptorWithKey(const std::vector<float>& key, const Config& config) {
  Descriptor d;
  d.num_rings = config.num_rings;
  d.num_sectors = config.num_sectors;
  d.ring_key.assign(key.begin(), key.end());
  d.sector_key.assign(config.num_sectors, 1.0f);
  d.column_occupied.assign(config.num_sectors, 1);
  d.occupied_columns = config.num_sectors;
  d.unit_columns.resize(static_cast<std::size_t>(config.num_rings) * config.num_sectors);
  const std::vector<float> heights(config.num_rings, 1.0f);
  for (int s = 0; s < config.num_sectors; ++s) {
    quantiseUnitColumn(heights.data(), config.num_rings,
                       &d.unit_columns[static_cast<std::size_t>(s) * config.num_rings]);
  }
  return d;
}

namespace {

/// Vertical faces of an axis-aligned box, sampled on a regular grid (about `step` metres apart) as a
/// scanner sweeping the facade would: every bin the box covers sees its true top edge.
void addBoxSurface(pcl::PointCloud<pcl::PointXYZ>* cloud, double cx, double cy, double half_x, double half_y, double z0,
                   double z1, double step) {
  const auto face = [&](double x0, double y0, double x1, double y1) {
    const double length = std::hypot(x1 - x0, y1 - y0);
    const int n = std::max(2, static_cast<int>(length / step));
    const int m = std::max(2, static_cast<int>((z1 - z0) / step));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      for (int j = 0; j <= m; ++j) {
        cloud->push_back(pcl::PointXYZ(static_cast<float>(x0 + t * (x1 - x0)), static_cast<float>(y0 + t * (y1 - y0)),
                                       static_cast<float>(z0 + (z1 - z0) * j / m)));
      }
    }
  };
  face(cx - half_x, cy - half_y, cx + half_x, cy - half_y);
  face(cx - half_x, cy + half_y, cx + half_x, cy + half_y);
  face(cx - half_x, cy - half_y, cx - half_x, cy + half_y);
  face(cx + half_x, cy - half_y, cx + half_x, cy + half_y);
}

}  // namespace

std::string sharedData() {
  const char* env = std::getenv("SCL_SHARED_DATA");
  return env != nullptr && *env != '\0' ? std::string(env) : std::string(SCL_SHARED_DATA);
}

PointView inLayout(const std::vector<Eigen::Vector3f>& points, std::size_t stride, std::size_t offset_x,
                   std::vector<std::uint8_t>* bytes) {
  bytes->assign(points.size() * stride + 1, 0xAB);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::memcpy(bytes->data() + 1 + i * stride + offset_x, points[i].data(), 3 * sizeof(float));
  }
  PointView view;
  view.data = bytes->data() + 1;
  view.count = points.size();
  view.stride = stride;
  view.offset_x = offset_x;
  view.offset_y = offset_x + 4;
  view.offset_z = offset_x + 8;
  return view;
}

const std::vector<std::pair<std::size_t, std::size_t>>& pointLayouts() {
  static const std::vector<std::pair<std::size_t, std::size_t>> layouts = {
      {16, 0}, {32, 0}, {12, 0}, {16, 4}, {40, 12}};
  return layouts;
}

pcl::PointCloud<pcl::PointXYZ> streetScene(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  const double ground = -1.7;
  // Ground rings, as a spinning sensor sees them.
  for (int ring = 0; ring < 24; ++ring) {
    const double r = 3.5 + ring * 1.6;
    for (int k = 0; k < 360; ++k) {
      const double a = (k + unit(rng) * 0.5) * M_PI / 180.0;
      cloud.push_back(pcl::PointXYZ(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)),
                                    static_cast<float>(ground + 0.03 * (unit(rng) - 0.5))));
    }
  }
  // Facades lining both sides of a street running along x, with gaps.
  for (int side = -1; side <= 1; side += 2) {
    double x = -70.0;
    while (x < 70.0) {
      const double length = 8.0 + 18.0 * unit(rng);
      const double depth = 6.0 + 8.0 * unit(rng);
      const double height = 4.0 + 26.0 * unit(rng);
      const double setback = 7.0 + 4.0 * unit(rng);
      addBoxSurface(&cloud, x + length / 2, side * (setback + depth / 2), length / 2, depth / 2, ground,
                    ground + height, 0.5);
      x += length + 2.0 + 10.0 * unit(rng);
    }
  }
  // Poles and parked cars.
  for (int i = 0; i < 16; ++i) {
    const double x = -60.0 + 120.0 * unit(rng);
    const double y = (unit(rng) < 0.5 ? -1 : 1) * (5.0 + 1.5 * unit(rng));
    if (i % 2 == 0) {
      addBoxSurface(&cloud, x, y, 0.15, 0.15, ground, ground + 6.0 + 4.0 * unit(rng), 0.2);
    } else {
      addBoxSurface(&cloud, x, y, 2.2, 0.9, ground, ground + 1.5, 0.2);
    }
  }
  return cloud;
}

pcl::PointCloud<pcl::PointXYZ> sectorCentredScene(std::uint32_t seed, int sectors, double max_radius) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double width = 2.0 * M_PI / sectors;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 20000; ++i) {
    const int sector = static_cast<int>(unit(rng) * sectors) % sectors;
    const double a = (sector + 1.0 / 3.0 + unit(rng) / 3.0) * width;
    const double r = 1.0 + unit(rng) * (max_radius - 2.0);
    const double z = -2.0 + 12.0 * unit(rng) * unit(rng);
    cloud.push_back(
        pcl::PointXYZ(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)), static_cast<float>(z)));
  }
  return cloud;
}

pcl::PointCloud<pcl::PointXYZ> rotateTranslate(const pcl::PointCloud<pcl::PointXYZ>& cloud, double yaw, double tx,
                                               double ty) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  pcl::PointCloud<pcl::PointXYZ> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) {
    out.push_back(
        pcl::PointXYZ(static_cast<float>(c * p.x - s * p.y + tx), static_cast<float>(s * p.x + c * p.y + ty), p.z));
  }
  return out;
}

pcl::PointCloud<pcl::PointXYZI> kittiScan(const std::string& sequence, int frame) {
  pcl::PointCloud<pcl::PointXYZI> cloud;
  std::string error;
  const std::string path = kitti::scanPath(sharedData() + "/kitti/" + sequence, frame);
  EXPECT_TRUE(kitti::readScan(path, &cloud, &error)) << error;
  return cloud;
}

Eigen::Isometry3d kittiRelative(const std::string& sequence, int query, int match) {
  const std::string dir = sharedData() + "/kitti/" + sequence;
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Isometry3d tr;
  std::string error;
  EXPECT_TRUE(kitti::readPoses(dir + "/poses.txt", &poses, &error)) << error;
  EXPECT_TRUE(kitti::readCalibTr(dir + "/calib.txt", &tr, &error)) << error;
  if (poses.size() <= static_cast<std::size_t>(std::max(query, match))) return Eigen::Isometry3d::Identity();
  const auto lidar = kitti::lidarPoses(poses, tr);
  return lidar[query].inverse() * lidar[match];
}

double kittiTrueYaw(const std::string& sequence, int query, int match) {
  const Eigen::Matrix3d r = kittiRelative(sequence, query, match).linear();
  return std::atan2(r(1, 0), r(0, 0));
}

}  // namespace test
}  // namespace scan_context_loop
