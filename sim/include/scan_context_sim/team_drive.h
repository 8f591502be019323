// A team of robots mapping one site: each drives its own route through one street grid, the routes
// overlapping the way real teams meet -- the same street the same way, the other way in the opposite
// lane, and one lane over -- with stretches only one robot sees, each robot starting when it is told.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/trajectory.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

struct TeamOptions {
  int robots = 3;  ///< 1 to kMaxTeam
  /// Seconds each robot starts after the earliest one (one per robot; the smallest counts as 0); empty:
  /// all at once.
  std::vector<double> start_offsets;
  double speed = 10.0;  ///< [m/s]
  /// Lane width [m]: robots drive in the right-hand lane, lane/2 right of the street's centre line, or
  /// in the one beside it, 1.5 lane right of it.
  double lane = 3.5;
};

constexpr int kMaxTeam = 6;

/// Empty when the options are usable, else what is wrong.
std::string checkTeam(const TeamOptions& options);

/// One robot's drive through the shared world.
struct RobotDrive {
  std::string id;      ///< "robot1", "robot2", ...
  TimedPath drive;     ///< in the world frame, sampled every 0.5 m; times from the robot's own start [s]
  double start = 0.0;  ///< the world's clock at the robot's first path point [s] (0 for the earliest)
};

/// The team's drives on a grid of 3 x 2 blocks, 70 x 50 m (streets x = 0, 70, 140, 210 and y = 0, 50,
/// 100), corners rounded (8 m), at `speed`:
///   robot1: 380 m counter-clockwise around the two western blocks (y = 0 east, x = 140 north, y = 50
///           west, x = 0 south), in the right-hand lane;
///   robot2: 430 m from the top of x = 70 south, along y = 50 west and x = 0 south behind robot1 (same
///           streets, same way, same lane), then y = 0 east one lane to the right of robot1 (second
///           lane), and x = 210 north to y = 50;
///   robot3: 410 m from the top of x = 0 south, y = 50 east and x = 140 south (robot1's streets the
///           other way, in the opposite lane; y = 50 against robot2 too), then y = 0 east in the second
///           lane and x = 210 north behind robot2 (same way, same lane), on to its top.
/// Robots 4 to 6 drive robots 1 to 3's routes turned half a turn about the grid's centre. Deterministic.
std::vector<RobotDrive> teamDrives(const TeamOptions& options);

/// The paths to build the world along (generateWorld with several paths): every robot's path, less
/// the stretches an earlier robot drove in the same lane (within `same_lane` metres), so each lane of
/// each street is furnished once.
std::vector<std::vector<PathPoint>> teamStreets(const std::vector<RobotDrive>& drives, double same_lane = 1.0);

/// How path `a` meets path `b`: the metres of a (by distance along it) whose nearest point of b, within
/// `reach` metres, is
struct Overlap {
  double same_lane = 0.0;   ///< within 1 m, heading within 30 degrees (the same street, way and lane)
  double other_lane = 0.0;  ///< 2.5 to 4.5 m to the side, heading within 30 degrees (a lane over)
  double reverse = 0.0;     ///< within 4.5 m, heading more than 150 degrees off (the other way)
  double any = 0.0;         ///< within `reach` whatever the heading (seen from the same street)
};
Overlap overlapOf(const std::vector<PathPoint>& a, const std::vector<PathPoint>& b, double reach = 4.5);

/// One robot's keyframes, one every `spacing` metres along its drive: origin = its first keyframe's true
/// pose over the world's ground (sensorPose), truth relative to it (the identity first), odometry drifting
/// from the identity (driftedOdometry with `drift`), times from its first keyframe and world_clock = the
/// robot's start.
SequenceData robotSequence(const World& world, const RobotDrive& robot, double mount_height, double spacing,
                           const DriftOptions& drift);

/// A seed of its own for each robot (noise, drift), from the run's seed and the robot's index (0-based).
std::uint32_t robotSeed(std::uint32_t seed, int robot);

}  // namespace sim
}  // namespace scan_context_loop
