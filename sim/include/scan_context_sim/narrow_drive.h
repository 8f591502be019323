// A walk through a campus or old town: narrow lanes between buildings a few metres to either side,
// walked again later the same way and the other way, ending where it started.
#pragma once

#include <cstdint>

#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

struct NarrowOptions {
  std::uint32_t seed = 1;
  double speed = 1.5;                             ///< walking pace [m/s]
  double spacing_min = 40.0, spacing_max = 55.0;  ///< between parallel lanes [m]
  double half_width = 2.75;                       ///< path centre to the lane's edge [m]
};

/// About 1.25 km (1.0-1.4 km with the seed: 26 lane spacings) over a grid of lanes, four each way at a
/// heading drawn from the seed, 40-55 m apart, sampled every 0.5 m: a loop around four blocks back to
/// the start, its first lane again the same way, out around the grid's far side, down the loop's west
/// lane the same way again, through the middle, and back along the loop's north, east and south lanes
/// the other way to the start. Corners are rounded (about 2 m). Stamps at `speed`. Deterministic from
/// the seed.
TimedPath narrowDrive(const NarrowOptions& options);

/// The world options a narrow walk needs: paths `half_width` wide to either side and no vehicles.
void narrowWorld(const NarrowOptions& options, WorldOptions* world);

}  // namespace sim
}  // namespace scan_context_loop
