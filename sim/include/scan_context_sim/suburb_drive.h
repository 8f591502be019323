// A drive through a suburb: a ring of gently curving residential streets with cul-de-sacs off it,
// driven round once, and after a stop partly again one lane over and then all the way round the
// other way.
#pragma once

#include <cstdint>

#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

struct SuburbOptions {
  std::uint32_t seed = 1;
  double lane = 1.6;      ///< a lane's centre to the street's centre line [m]
  double speed = 8.0;     ///< [m/s]
  double pause = 1800.0;  ///< stop between the two laps [s]
};

/// About 2.3-2.7 km, sampled about every 0.5 m. The streets: a ring (an ellipse of 120-150 x 85-105 m
/// with its 12 vertices jittered, smoothed into gentle curves) at a heading drawn from the seed, and
/// three cul-de-sacs of 50-75 m with a kink (two into the ring, one out of it), each ending in a
/// turning circle. Lap 1 drives the ring anticlockwise in the right-hand lane and into each cul-de-sac,
/// round its turning circle and out again (the way out is the way in reversed, a lane over). After
/// `pause` seconds lap 2 drives half the ring the same way one lane to the left (a same-direction
/// revisit 2 x lane to the side), the second cul-de-sac as lap 1 did (the same lane), and then the
/// whole ring clockwise in its right-hand lane (reverse revisits 2 x lane to the side). Corners and
/// lane changes are smoothed over about 8 m. Deterministic from the seed.
TimedPath suburbDrive(const SuburbOptions& options);

/// The world options a suburb needs: its style, and kerbs 4.5 m from each lane (6.1 m from the centre
/// line of a street driven both ways).
void suburbWorld(WorldOptions* world);

}  // namespace sim
}  // namespace scan_context_loop
