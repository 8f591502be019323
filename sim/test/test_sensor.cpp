// Beam patterns and the scan model: rings on flat ground, noise, dropout, fading with range.
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "scan_context_sim/sensor.h"

namespace scan_context_loop {
namespace sim {
namespace {

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

SensorModel exact(const std::string& name) {
  SensorModel m;
  EXPECT_TRUE(sensorPreset(name, &m));
  m.range_noise = 0.0f;
  m.dropout = 0.0f;
  m.dim_range = 0.0f;
  return m;
}

TEST(Sensor, PresetsHaveTheRealBeamPatterns) {
  SensorModel m;
  ASSERT_TRUE(sensorPreset("hdl64", &m));
  ASSERT_EQ(m.elevations_deg.size(), 64u);
  EXPECT_FLOAT_EQ(m.elevations_deg.front(), 2.0f);
  EXPECT_FLOAT_EQ(m.elevations_deg.back(), -24.9f);
  EXPECT_NEAR(360.0 / m.columns, 0.17, 0.02);
  ASSERT_TRUE(sensorPreset("vlp16", &m));
  ASSERT_EQ(m.elevations_deg.size(), 16u);
  EXPECT_FLOAT_EQ(m.elevations_deg.front(), 15.0f);
  EXPECT_FLOAT_EQ(m.elevations_deg.back(), -15.0f);
  EXPECT_NEAR(m.elevations_deg[0] - m.elevations_deg[1], 2.0f, 1e-5f);
  EXPECT_NEAR(360.0 / m.columns, 0.2, 1e-9);
  ASSERT_TRUE(sensorPreset("os1-64", &m));
  ASSERT_EQ(m.elevations_deg.size(), 64u);
  EXPECT_FLOAT_EQ(m.elevations_deg.front(), 16.6f);
  EXPECT_FLOAT_EQ(m.elevations_deg.back(), -16.6f);
  EXPECT_EQ(m.columns, 1024);
  EXPECT_FALSE(sensorPreset("hdl32e", &m));
  // Every name the usage text lists is a preset.
  std::istringstream names(sensorPresetNames());
  int listed = 0;
  for (std::string name; names >> name;) {
    if (name == "|") continue;
    EXPECT_TRUE(sensorPreset(name, &m)) << name;
    EXPECT_EQ(m.name, name);
    ++listed;
  }
  EXPECT_EQ(listed, 5);
}

TEST(Sensor, Hdl64RingsOnFlatGround) {
  const SensorModel hdl = exact("hdl64");
  const World flat({}, Eigen::Vector3d::Zero());
  const auto cloud = scan(flat, hdl, at(0, 0, hdl.mount_height), 0.0, 1);
  // One ring per beam below the horizon whose ground range is under max_range, each a full circle at
  // mount_height / tan(-elevation).
  std::map<int, std::pair<int, double>> rings;  // elevation [centidegrees] -> (points, mean range)
  for (const auto& p : cloud) {
    const double r = std::hypot(p.x, p.y);
    auto& ring = rings[static_cast<int>(std::lround(std::atan2(p.z, r) * 180.0 / M_PI * 100))];
    ++ring.first;
    ring.second += r;
    ASSERT_NEAR(p.z, -hdl.mount_height, 1e-3);
  }
  int reaching = 0;
  for (float e : hdl.elevations_deg) {
    const double ground_range = hdl.mount_height / std::tan(-e * M_PI / 180.0);
    if (e >= 0.0f || ground_range >= hdl.max_range) continue;
    ++reaching;
    const auto it = rings.find(static_cast<int>(std::lround(e * 100)));
    ASSERT_NE(it, rings.end()) << "no ring for the " << e << " deg beam";
    EXPECT_EQ(it->second.first, hdl.columns) << e;
    EXPECT_NEAR(it->second.second / it->second.first, ground_range, 1e-3 * ground_range) << e;
  }
  EXPECT_EQ(static_cast<int>(rings.size()), reaching);
  // The lowest beam (-24.9 deg) meets the ground 1.73 / tan(24.9 deg) = 3.73 m away.
  EXPECT_NEAR(rings.begin()->second.second / rings.begin()->second.first, 1.73 / std::tan(24.9 * M_PI / 180.0), 1e-3);
}

TEST(Sensor, Os1ReportsRaysWithoutAReturnAsZeros) {
  // Over flat ground, the beams above the horizon hit nothing: an OS1-64 reports each such ray as
  // (0, 0, 0), one point per ray in all; the HDL-64E leaves them out.
  const SensorModel os1 = exact("os1-64");
  ASSERT_TRUE(os1.zeros_for_no_return);
  const World flat({}, Eigen::Vector3d::Zero());
  const auto cloud = scan(flat, os1, at(0, 0, os1.mount_height), 0.0, 1);
  EXPECT_EQ(cloud.size(), static_cast<std::size_t>(os1.columns) * os1.elevations_deg.size());
  std::size_t zeros = 0, beams_up = 0;
  for (const auto& p : cloud) zeros += (p.x == 0.0f && p.y == 0.0f && p.z == 0.0f);
  for (float e : os1.elevations_deg) {
    const double ground_range = os1.mount_height / std::tan(-e * M_PI / 180.0);
    beams_up += e >= 0.0f || ground_range >= os1.max_range;
  }
  EXPECT_EQ(zeros, beams_up * os1.columns);
  SensorModel dropped = os1;
  dropped.zeros_for_no_return = false;
  EXPECT_EQ(scan(flat, dropped, at(0, 0, os1.mount_height), 0.0, 1).size(), cloud.size() - zeros);
}

TEST(Sensor, NoiseDropoutAndFading) {
  // A wall 20 m ahead, 60 m wide and 30 m tall, over flat ground.
  Primitive wall;
  wall.kind = Primitive::Kind::kBox;
  wall.center = Eigen::Vector3f(20.5f, 0, 0);
  wall.half = Eigen::Vector3f(0.5f, 30, 0);
  wall.z0 = -1;
  wall.z1 = 30;
  const World world({wall}, Eigen::Vector3d::Zero());
  SensorModel hdl = exact("hdl64");
  const Eigen::Isometry3d pose = at(0, 0, hdl.mount_height);
  const auto clean = scan(world, hdl, pose, 0.0, 1);

  hdl.range_noise = 0.05f;
  const auto noisy = scan(world, hdl, pose, 0.0, 1);
  ASSERT_EQ(noisy.size(), clean.size());
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    const double d = std::hypot(noisy[i].x, noisy[i].y, noisy[i].z) - std::hypot(clean[i].x, clean[i].y, clean[i].z);
    sum += d;
    sum2 += d * d;
    ++n;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.003);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.05, 0.005);

  hdl.range_noise = 0.0f;
  hdl.dropout = 0.1f;
  EXPECT_NEAR(static_cast<double>(scan(world, hdl, pose, 0.0, 1).size()) / clean.size(), 0.9, 0.01);

  // Fading: the bright wall stays whole; flat ground thins out with range, half gone past ~64 m.
  hdl.dropout = 0.0f;
  hdl.dim_range = 80.0f;
  const auto faded = scan(world, hdl, pose, 0.0, 1);
  const auto share = [](const pcl::PointCloud<pcl::PointXYZI>& cloud, double r0, double r1, bool on_wall) {
    int count = 0;
    for (const auto& p : cloud) {
      const bool wall_point = p.x > 19.9f && std::fabs(p.y) < 30.0f;
      const double r = std::hypot(p.x, p.y);
      count += wall_point == on_wall && r >= r0 && r < r1 && (on_wall || p.x < 0.0f);
    }
    return count;
  };
  EXPECT_GT(share(faded, 0, 100, true), 0.98 * share(clean, 0, 100, true));
  EXPECT_GT(share(faded, 10, 30, false), 0.97 * share(clean, 10, 30, false));
  EXPECT_LT(share(faded, 70, 100, false), 0.5 * share(clean, 70, 100, false));
  EXPECT_GT(share(clean, 70, 100, false), 1000);
}

TEST(Sensor, ScansAreRepeatableForASeed) {
  Primitive box;
  box.kind = Primitive::Kind::kBox;
  box.center = Eigen::Vector3f(8, 3, 0);
  box.half = Eigen::Vector3f(2, 1, 0);
  box.z0 = 0;
  box.z1 = 2;
  const World world({box}, Eigen::Vector3d::Zero());
  SensorModel vlp;
  ASSERT_TRUE(sensorPreset("vlp16", &vlp));
  const auto a = scan(world, vlp, at(0, 0, 1.73), 0.0, 7);
  const auto b = scan(world, vlp, at(0, 0, 1.73), 0.0, 7);
  const auto c = scan(world, vlp, at(0, 0, 1.73), 0.0, 8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].x, b[i].x);
    ASSERT_EQ(a[i].intensity, b[i].intensity);
  }
  bool differs = a.size() != c.size();
  for (std::size_t i = 0; !differs && i < a.size(); ++i) differs = a[i].x != c[i].x;
  EXPECT_TRUE(differs);
}

const std::vector<std::string> kLivox = {"livox-avia", "livox-mid360"};

/// Azimuth (x = 0, to the left positive) and elevation of a direction or point [deg].
Eigen::Vector2d anglesDeg(const Eigen::Vector3f& v) {
  return Eigen::Vector2d(std::atan2(v.y(), v.x()), std::atan2(v.z(), std::hypot(v.x(), v.y()))) * (180.0 / M_PI);
}

/// The 1 x 1 deg cells the rays of `scans` consecutive scans (0.1 s apart, from `time`) fall in.
std::set<std::pair<int, int>> cellsHit(const SensorModel& m, double time, int scans) {
  std::set<std::pair<int, int>> cells;
  for (int k = 0; k < scans; ++k) {
    for (const auto& ray : rayDirections(m, time + 0.1 * k)) {
      const Eigen::Vector2d a = anglesDeg(ray);
      cells.emplace(static_cast<int>(std::floor(a.x())), static_cast<int>(std::floor(a.y())));
    }
  }
  return cells;
}

/// The field of view's solid angle in square degrees: an ellipse for the rosette, a band for the sweep.
double fovArea(const SensorModel& m) {
  const double height = m.fov_top_deg - m.fov_bottom_deg;
  return m.pattern == ScanPattern::kRosette ? M_PI / 4.0 * m.fov_horizontal_deg * height : 360.0 * height;
}

TEST(Sensor, LivoxScansStayInTheirFieldOfViewAndReachItsEdges) {
  // Four walls 20 m away, 50 m tall, around the sensor: every ray returns.
  std::vector<Primitive> walls;
  for (int side = 0; side < 4; ++side) {
    Primitive w;
    w.kind = Primitive::Kind::kBox;
    const float offset = side % 2 ? -20.5f : 20.5f;
    w.center = side < 2 ? Eigen::Vector3f(offset, 0, 0) : Eigen::Vector3f(0, offset, 0);
    w.half = side < 2 ? Eigen::Vector3f(0.5f, 21, 0) : Eigen::Vector3f(21, 0.5f, 0);
    w.z0 = -1;
    w.z1 = 50;
    walls.push_back(w);
  }
  const World world(walls, Eigen::Vector3d::Zero());
  for (const auto& name : kLivox) {
    const SensorModel m = exact(name);
    ASSERT_NE(m.pattern, ScanPattern::kSpinning) << name;
    EXPECT_EQ(m.rays_per_scan, static_cast<int>(std::lround(0.1 * m.ray_rate))) << name;
    Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
    for (int k = 0; k < 10; ++k) {
      const auto cloud = scan(world, m, at(0, 0, m.mount_height), 100.0 + 0.1 * k, 1);
      ASSERT_EQ(cloud.size(), static_cast<std::size_t>(m.rays_per_scan)) << name;
      for (const auto& p : cloud) {
        const Eigen::Vector2d a = anglesDeg(p.getVector3fMap());
        low = low.cwiseMin(a);
        high = high.cwiseMax(a);
      }
    }
    const double half_width = 0.5 * m.fov_horizontal_deg;
    EXPECT_GE(low.x(), -half_width - 0.01) << name;
    EXPECT_LE(high.x(), half_width + 0.01) << name;
    EXPECT_GE(low.y(), m.fov_bottom_deg - 0.01) << name;
    EXPECT_LE(high.y(), m.fov_top_deg + 0.01) << name;
    // A second of scans reaches the edges.
    EXPECT_LT(low.x(), -0.97 * half_width) << name;
    EXPECT_GT(high.x(), 0.97 * half_width) << name;
    EXPECT_LT(low.y(), m.fov_bottom_deg + 0.03 * (m.fov_top_deg - m.fov_bottom_deg)) << name;
    EXPECT_GT(high.y(), m.fov_top_deg - 0.03 * (m.fov_top_deg - m.fov_bottom_deg)) << name;
  }
}

TEST(Sensor, LivoxScanCoversPatchesThatFillInWhenMerged) {
  for (const auto& name : kLivox) {
    const SensorModel m = exact(name);
    const double area = fovArea(m);
    const double one = cellsHit(m, 42.0, 1).size() / area;
    const double half_second = cellsHit(m, 42.0, 5).size() / area;
    const double second = cellsHit(m, 42.0, 10).size() / area;
    // One 0.1 s scan leaves most of the field of view's square degrees empty, and covers less than
    // half of what as many rays scattered at random would; merged scans fill them in.
    EXPECT_LT(one, 0.5) << name;
    EXPECT_LT(one, 0.5 * (1.0 - std::exp(-m.rays_per_scan / area))) << name;
    EXPECT_GT(half_second, 1.5 * one) << name;
    EXPECT_GT(second, half_second) << name;
    EXPECT_GT(second, 0.85) << name;
    EXPECT_LT(second, 1.05) << name;
  }
}

TEST(Sensor, LivoxPatternChangesFromScanToScan) {
  for (const auto& name : kLivox) {
    const SensorModel m = exact(name);
    const auto first = cellsHit(m, 42.0, 1);
    // The same time gives the same rays; each of the next scans finds most of its cells new.
    EXPECT_EQ(cellsHit(m, 42.0, 1), first) << name;
    for (double later : {42.1, 42.2, 137.3}) {
      const auto next = cellsHit(m, later, 1);
      std::size_t fresh = 0;
      for (const auto& c : next) fresh += first.count(c) == 0;
      EXPECT_GT(fresh, next.size() / 2) << name << " at " << later;
    }
  }
  // A spinning sensor fires the same rays every revolution.
  const SensorModel hdl = exact("hdl64");
  EXPECT_EQ(rayDirections(hdl, 0.0), rayDirections(hdl, 0.1));
}

}  // namespace
}  // namespace sim
}  // namespace scan_context_loop
