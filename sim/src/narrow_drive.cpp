#include "scan_context_sim/narrow_drive.h"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "polyline.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {

TimedPath narrowDrive(const NarrowOptions& options) {
  std::mt19937 rng(options.seed);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const double heading = uniform(0.0, 2.0 * M_PI);
  const Eigen::Vector2d east(std::cos(heading), std::sin(heading)), north(-east.y(), east.x());
  // Four lanes each way; parallel ones far enough apart for a row of buildings from each side.
  double x[4] = {}, y[4] = {};
  for (int i = 1; i < 4; ++i) {
    x[i] = x[i - 1] + uniform(options.spacing_min, options.spacing_max);
    y[i] = y[i - 1] + uniform(options.spacing_min, options.spacing_max);
  }
  // Junctions (column, row) in walking order.
  const int route[][2] = {// A loop around the four south-west blocks, back to the start.
                          {0, 0},
                          {2, 0},
                          {2, 2},
                          {0, 2},
                          {0, 0},
                          // Its south lane again the same way, then round the far side of the grid.
                          {2, 0},
                          {3, 0},
                          {3, 3},
                          {0, 3},
                          // Down the loop's west lane the same way, through the middle.
                          {0, 1},
                          {1, 1},
                          {1, 2},
                          // The loop's north, east and south lanes the other way, ending at the start.
                          {2, 2},
                          {2, 0},
                          {0, 0}};
  std::vector<Eigen::Vector2d> corners;
  for (const auto& node : route) corners.push_back(x[node[0]] * east + y[node[1]] * north);
  std::size_t no_mark = 0;
  const std::vector<Eigen::Vector2d> points = resample(corners, 0.5, &no_mark);
  // A moving average over +-2 m rounds the corners as a walker cuts them, within the lanes.
  TimedPath drive;
  drive.path = smoothPath(points, 4);
  drive.times = distanceAlong(drive.path);
  for (double& t : drive.times) t /= options.speed;
  return drive;
}

void narrowWorld(const NarrowOptions& options, WorldOptions* world) {
  world->road_half_width = options.half_width;
  world->vehicles = false;
}

}  // namespace sim
}  // namespace scan_context_loop
