// Turning a route drawn as a polyline into a drivable path: evenly spaced points and rounded corners.
// Shared by the generated drives. Internal to the simulator library.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

/// Points every `step` metres along the polyline `raw` (linear interpolation). `mark`, an index into
/// raw, becomes the index of the first sample after raw[mark - 1].
std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& raw, double step, std::size_t* mark);

/// The points smoothed by a moving average over +-`window` points (fewer at the ends), which rounds
/// the corners and leaves straight stretches where they are, with headings along the smoothed path.
std::vector<PathPoint> smoothPath(const std::vector<Eigen::Vector2d>& points, int window);

/// A generated drive along the drawn route `raw`: resampled every 0.5 m, its corners rounded by a moving
/// average over +-8 m, timed at `speed` [m/s] with a stop of `pause` seconds before raw[mark].
TimedPath timedDrive(const std::vector<Eigen::Vector2d>& raw, std::size_t mark, double speed, double pause);

/// Straight legs through the waypoints, corners rounded with arcs of `radius`, sampled every `step`.
std::vector<PathPoint> roundedPolyline(const std::vector<Eigen::Vector2d>& waypoints, double radius, double step);

}  // namespace sim
}  // namespace scan_context_loop
