// A drive through a street network that is not a grid: streets at random headings meeting at oblique
// angles, some gently curved, with same-direction, reverse and one-lane-over revisits an hour later.
#pragma once

#include <cstdint>
#include <vector>

#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

/// A path with its own clock, for drives that stop along the way.
struct TimedPath {
  std::vector<PathPoint> path;
  std::vector<double> times;  ///< seconds from the start, one per path point
};

struct CityOptions {
  std::uint32_t seed = 1;
  double lane = 3.25;     ///< lateral offset of a revisit in the other lane [m]
  double speed = 10.0;    ///< [m/s]
  double pause = 3600.0;  ///< stop between the two halves of the drive [s]
};

/// About 2.5 km (2.2-3 km depending on the seed), sampled about every 0.5 m. Three long streets cross
/// four shorter ones at 55-70 degrees (or the supplement), each street's heading a few degrees off its
/// family's and half of the shorter ones curved (radius 600-1000 m), so the junctions meet at about
/// 35-145 degrees and parallel streets stay about 60 m or more apart. The first half is a loop around
/// the six blocks. After a stop of `pause` seconds, the second half drives the loop's first street
/// again one lane to the right (same direction, a lane to the side), the loop's second street and a
/// third of its third in the loop's lane (same direction), through the middle of the blocks on streets
/// not driven before, and up the second half of the loop's last street and along two thirds of its
/// third street the other way, in the opposite lane (reverse, a lane to the side). Corners are rounded
/// (about 10 m radius). Deterministic from the seed.
TimedPath cityDrive(const CityOptions& options);

}  // namespace sim
}  // namespace scan_context_loop
