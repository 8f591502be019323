// The changed world (WorldOptions::changed_world): what happens to a street between a visit and one
// days later. Internal to the simulator library.
#pragma once

#include <vector>

#include "street_kit.h"

namespace scan_context_loop {
namespace sim {

/// Changes the built street with strength options.changed_world (0 to 1): each changeable thing changes
/// with about that chance, at a time drawn in the drive's duration, so a place revisited much later
/// almost surely shows it. Parked cars leave, arrive or move; new cars park in empty spaces; canopies,
/// bushes and hedges grow or are cut, some go and new hedges appear; construction sites appear; and
/// traffic and pedestrians pass. Draws only from a generator of its own (seeded from the seed), so the
/// world as built stays as it was.
void changeWorld(const std::vector<PathPoint>& path, const StreetRecord& record, StreetKit* kit);

/// Traffic in the road lanes and pedestrians on the pavements, each present for a few seconds near
/// where the sensor then is, never within 2 m of it; about `strength` vehicles every 4 s and a
/// pedestrian every 2 s. `path` is the drive (options.times, or a uniform speed, gives its times).
void addTraffic(const std::vector<PathPoint>& path, double strength, StreetKit* kit);

}  // namespace sim
}  // namespace scan_context_loop
