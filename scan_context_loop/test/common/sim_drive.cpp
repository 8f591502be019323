#include "sim_drive.h"

#include <cmath>

#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {

pcl::PointCloud<pcl::PointXYZI> Drive::scan(std::size_t k) const {
  return sim::scan(world, sensor, truth[k], times[k], 1000 + k);
}

Drive blockDrive(bool reverse_second_lap, std::uint32_t seed) {
  using V = Eigen::Vector2d;
  const std::vector<V> ccw = {V(0, 0), V(60, 0), V(60, 40), V(0, 40)};
  std::vector<sim::PathPoint> path;
  const auto leg = [&](const V& a, const V& b) {
    const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
    for (double s = 0; s < (b - a).norm(); s += 0.5) {
      const V p = a + (b - a).normalized() * s;
      path.push_back({p.x(), p.y(), heading});
    }
  };
  for (int c = 0; c < 4; ++c) leg(ccw[c], ccw[(c + 1) % 4]);
  if (reverse_second_lap) {
    for (int c = 4; c > 0; --c) leg(ccw[c % 4], ccw[c - 1]);
  } else {
    // Lap 1 again, 3 m further out: ignoring the corners, it runs parallel to lap 1.
    const double o = 3.0;
    const std::vector<V> out = {V(0, -o), V(60 + o, -o), V(60 + o, 40 + o), V(-o, 40 + o)};
    for (int c = 0; c < 4; ++c) leg(out[c], out[(c + 1) % 4]);
  }
  Drive d;
  sim::WorldOptions options;
  options.seed = seed;
  d.world = sim::generateWorld(path, options);
  sim::sensorPreset("hdl64", &d.sensor);
  d.sensor.columns = 900;
  for (std::size_t k : sim::keyframesEvery(path, 2.0)) {
    d.truth.push_back(sim::sensorPose(d.world, path[k], d.sensor.mount_height));
    d.times.push_back(0.1 * d.times.size());
  }
  return d;
}

}  // namespace test
}  // namespace scan_context_loop
