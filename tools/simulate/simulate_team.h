// scan_context_simulate --team: several robots through one world, written as OUT/team.txt, one KITTI
// folder per robot and, optionally, one bag of them all.
#pragma once

#include <cstdint>
#include <string>

#include "scan_context_sim/sensor.h"
#include "scan_context_sim/team_drive.h"
#include "scan_context_sim/trajectory.h"
#include "sim_bag.h"

namespace scan_context_loop {
namespace sim {

struct TeamRun {
  std::string out;
  TeamOptions team;
  SensorModel sensor;
  WorldOptions world;    ///< seed, dynamic cars, repeated templates
  DriftOptions drift;    ///< its seed is replaced by each robot's own
  double spacing = 2.0;  ///< one keyframe every `spacing` metres [m]
  double voxel = 0.0;
  std::uint32_t seed = 1;
  int threads = 1;
  BagOptions bag;  ///< no path: no bag
};

/// Builds the world along all the robots' drives, ray-casts each robot's keyframes and writes
/// OUT/team.txt, OUT/<robot>/ (writeSequence: truth and drifted odometry relative to the robot's first
/// keyframe, times from it, and its own sequence.txt), OUT/sequence.txt (what was simulated, with the
/// routes' overlaps) and the bag. Prints a summary; false with a reason.
bool simulateTeam(const TeamRun& run, std::string* error);

}  // namespace sim
}  // namespace scan_context_loop
