// The changed world (WorldOptions::changed_world): what happens to a street between a visit and one
// days later. Internal to the simulator library.
#pragma once

#include <cmath>
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
  /// Traffic and pedestrians pass (off when WorldOptions::pass_traffic draws them per pass instead).
  bool traffic = true;
};

/// When a change happens: anywhere in the window (during the drive: the later a revisit, the likelier it
/// sees it).
double changeTime(StreetKit& kit, const Changes& c);

/// A point of the drive, drawn uniformly.
const PathPoint& randomPlace(StreetKit& kit);

/// Solid `index` is gone from `when` on.
void removeAt(StreetKit& kit, std::size_t index, double when);

/// Solid `index` is replaced by `after` from `when` on.
void replaceAt(StreetKit& kit, std::size_t index, Primitive after, double when);

/// Places about `count` things with place(), which tries one spot and says whether it was free; up to
/// `attempts` spots each, as streets are mostly full.
template <typename Place>
void placeSeveral(double count, Place place, int attempts = 5) {
  for (long i = 0; i < std::lround(count); ++i) {
    for (int attempt = 0; attempt < attempts && !place(); ++attempt) {
    }
  }
}

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

/// The same, with the vehicles and pedestrians drawn in the clock's window [from, to) only.
void addTraffic(const std::vector<PathPoint>& path, const std::vector<double>& times, double strength, StreetKit* kit,
                double from, double to);

/// The harder changes of WorldOptions (season, construction, furniture, pass_traffic) during the drive
/// `path` with its clock `times`, each from a generator of its own keyed by the seed.
void harderChanges(const std::vector<PathPoint>& path, const std::vector<double>& times, const StreetRecord& record,
                   StreetKit* kit);

/// Leaf-off: about c.strength of the broadleaved trees lose their leaves at their own time (their
/// canopies, grown or cut ones too, become a few limbs and a sparse crown of twigs), and as many
/// hedges and bushes thin out (light passes through them three to four times as far).
void leafOff(const StreetRecord& record, const Changes& c, StreetKit* kit);

/// About c.strength building sites per 100 m of drive: mesh site fences along the pavement, fenced
/// lots with a site cabin or containers, and stacks of shipping containers at the kerb or in lots.
void addBuildingSites(const Changes& c, StreetKit* kit);

/// About c.strength of the street furniture is moved 2-12 m along the pavement (a third taken away),
/// and new benches and bins appear.
void moveFurniture(const StreetRecord& record, const Changes& c, StreetKit* kit);

/// A different density on each pass (WorldOptions::pass_traffic, pass_seconds): parked cars present,
/// empty spaces taken and the traffic and pedestrians, drawn per pass.
void passDensity(const std::vector<PathPoint>& path, const std::vector<double>& times, const StreetRecord& record,
                 double strength, StreetKit* kit);

/// The suburb (WorldOptions::Style::kSuburb): plots with detached houses along both sides of the path.
StreetRecord buildSuburb(StreetKit* kit);
}  // namespace sim
}  // namespace scan_context_loop
