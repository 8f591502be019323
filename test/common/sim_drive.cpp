#include "sim_drive.h"

#include <cmath>

#include "scan_context_sim/second_session.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {

pcl::PointCloud<pcl::PointXYZI> Drive::scan(std::size_t k) const {
  return sim::scan(world, sensor, truth[k], world_clock + times[k], 1000 + k);
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

namespace {

/// Keyframes every 2 m along a drive through `world`, timed by its clock.
void keyframesAlong(const sim::TimedPath& drive, Drive* d) {
  sim::sensorPreset("hdl64", &d->sensor);
  d->sensor.columns = 900;
  for (std::size_t k : sim::keyframesEvery(drive.path, 2.0)) {
    d->truth.push_back(sim::sensorPose(d->world, drive.path[k], d->sensor.mount_height));
    d->times.push_back(drive.times[k]);
  }
}

}  // namespace

Sessions blockSessions(std::uint32_t seed) {
  std::vector<sim::PathPoint> lap = sim::blockPath(false);
  lap.resize(lap.size() / 2);
  sim::TimedPath first{lap, {0.0}};
  for (std::size_t k = 1; k < lap.size(); ++k) {
    first.times.push_back(first.times.back() + std::hypot(lap[k].x - lap[k - 1].x, lap[k].y - lap[k - 1].y) / 10.0);
  }
  sim::WorldOptions options;
  options.seed = seed;
  options.times = first.times;
  options.duration = first.times.back();
  const sim::SecondSessionOptions next_day;
  const sim::TimedPath second = sim::secondSessionDrive(lap, first.times, next_day);
  const sim::LaterDrive later = sim::laterDrive(second, options.duration, next_day);
  Sessions s;
  s.first.world = sim::generateWorld(lap, options);
  keyframesAlong(first, &s.first);
  s.second.world = sim::generateWorld(lap, options, later);
  s.second.world_clock = later.times.front();
  keyframesAlong(second, &s.second);
  return s;
}

}  // namespace test
}  // namespace scan_context_loop
