// The changed world (WorldOptions::changed_world): what happens to a street between a visit and one
// days later. Internal to the simulator library.
#pragma once

#include <cstdint>
#include <vector>

#include "street_kit.h"

namespace scan_context_loop {
namespace sim {

/// How much the street changes, and when.
struct Changes {
  double strength = 0.0;        ///< 0 to 1: the chance each changeable thing changes
  double from = 0.0, to = 0.0;  ///< change times are drawn in [from, to] (seconds on the world's clock)
  /// The street was seen before `from` (a drive on an earlier day): what was seen then stays as it was
  /// then, so a parked car that would arrive at `from` instead replaces the vehicle in its space, and
  /// only things that have not changed yet change.
  bool seen_before = false;
  std::uint64_t salt = 0;  ///< keys the generator the changes draw from
};

/// The changes of WorldOptions::changed_world during the drive itself: strength changed_world, times in
/// [0, duration].
Changes duringDrive(const WorldOptions& options);

/// Changes the built street: each changeable thing changes with about changes.strength chance, at a
/// time drawn in the window, so a place revisited much later almost surely shows it. Parked cars leave,
/// arrive (or, seen before, are replaced) or move; new cars park in empty spaces; canopies, bushes and
/// hedges grow or are cut, some go and new hedges appear; construction sites appear; and traffic and
/// pedestrians pass the drive `path` with its clock `times` (as addTraffic). Draws only from a generator
/// of its own (seeded from the seed and the salt), so the world as built stays as it was.
void changeWorld(const std::vector<PathPoint>& path, const std::vector<double>& times, const StreetRecord& record,
                 const Changes& changes, StreetKit* kit);

/// Traffic in the road lanes and pedestrians on the pavements, each present for a few seconds near
/// where the sensor then is, never within 2 m of it; about `strength` vehicles every 4 s and a
/// pedestrian every 2 s. `path` is the drive and `times` its clock (empty: a uniform speed over
/// options.duration). Draws from the kit's current generator.
void addTraffic(const std::vector<PathPoint>& path, const std::vector<double>& times, double strength, StreetKit* kit);

}  // namespace sim
}  // namespace scan_context_loop
