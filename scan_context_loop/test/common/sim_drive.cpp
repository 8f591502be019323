#include "sim_drive.h"

#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {

pcl::PointCloud<pcl::PointXYZI> Drive::scan(std::size_t k) const {
  return sim::scan(world, sensor, truth[k], times[k], 1000 + k);
}

Drive blockDrive(bool reverse_second_lap, std::uint32_t seed) {
  const std::vector<sim::PathPoint> path = sim::blockPath(reverse_second_lap);
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
