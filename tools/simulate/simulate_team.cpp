#include "simulate_team.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/team_file.h"

namespace scan_context_loop {
namespace sim {

namespace {

double lengthOf(const std::vector<Eigen::Isometry3d>& poses) {
  double length = 0.0;
  for (std::size_t k = 1; k < poses.size(); ++k) length += (poses[k].translation() - poses[k - 1].translation()).norm();
  return length;
}

}  // namespace

bool simulateTeam(const TeamRun& run, std::string* error) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<RobotDrive> drives = teamDrives(run.team);
  WorldOptions world_options = run.world;
  world_options.duration = 0.0;
  for (const RobotDrive& r : drives) {
    world_options.duration = std::max(world_options.duration, r.start + r.drive.times.back());
  }
  world_options.times.clear();
  const World world = generateWorld(teamStreets(drives), world_options);

  std::vector<TeamMember> team;
  std::vector<BagSequence> bag_sequences;
  std::ofstream info(run.out + "/sequence.txt");
  info << "trajectory: team\nrobots: " << drives.size() << "\nsensor: " << run.sensor.name
       << "\nkeyframe_spacing_m: " << run.spacing << "\nvoxel_m: " << run.voxel << "\nseed: " << run.seed
       << "\nworld_primitives: " << world.size() << "\nspeed_m_per_s: " << run.team.speed
       << "\ndrift_translation_per_m: " << run.drift.translation_per_metre
       << "\ndrift_yaw_deg_per_m: " << run.drift.yaw_per_metre << "\ndrift_yaw_per_deg: " << run.drift.yaw_per_degree
       << "\ndrift_correlation_m: " << run.drift.correlation_length << "\n";
  for (std::size_t r = 0; r < drives.size(); ++r) {
    const RobotDrive& robot = drives[r];
    DriftOptions drift = run.drift;
    drift.seed = robotSeed(run.seed, static_cast<int>(r));
    const SequenceData data = robotSequence(world, robot, run.sensor.mount_height, run.spacing, drift);
    const std::string dir = run.out + "/" + robot.id;
    const double mean_points = writeSequence(dir, world, run.sensor, data, run.voxel, drift.seed, run.threads, error);
    if (mean_points < 0) return false;
    team.push_back({robot.id, robot.start, data.origin});
    std::vector<double> clock;
    for (double t : data.times) clock.push_back(robot.start + t);
    bag_sequences.push_back({dir, data.truth, data.odometry, clock, robot.id});
    const double length = lengthOf(data.truth);
    std::ofstream robot_info(dir + "/sequence.txt");
    robot_info << "trajectory: team\nrobot: " << robot.id << "\nkeyframes: " << data.truth.size()
               << "\nkeyframe_spacing_m: " << run.spacing << "\nlength_m: " << length
               << "\nstart_seconds: " << robot.start << "\nsensor: " << run.sensor.name
               << "\nmount_height_m: " << run.sensor.mount_height << "\nvoxel_m: " << run.voxel
               << "\nseed: " << drift.seed << "\n";
    info << robot.id << ": keyframes " << data.truth.size() << ", length_m " << length << ", start_seconds "
         << robot.start << ", duration_s " << data.times.back() << ", seed " << drift.seed << ", mean_points "
         << mean_points << "\n";
    std::printf("%s: %zu keyframes, %.0f m, starts at %.0f s, %.0f points on average\n", robot.id.c_str(),
                data.truth.size(), length, robot.start, mean_points);
  }
  for (std::size_t a = 0; a < drives.size(); ++a) {
    for (std::size_t b = 0; b < drives.size(); ++b) {
      if (a == b) continue;
      const Overlap o = overlapOf(drives[a].drive.path, drives[b].drive.path);
      info << "overlap " << drives[a].id << " on " << drives[b].id << ": same_lane_m " << o.same_lane
           << ", other_lane_m " << o.other_lane << ", reverse_m " << o.reverse << ", any_m " << o.any << "\n";
      if (a < b) {
        std::printf("%s and %s share %.0f m: %.0f m same lane, %.0f m a lane over, %.0f m the other way\n",
                    drives[a].id.c_str(), drives[b].id.c_str(), o.any, o.same_lane, o.other_lane, o.reverse);
      }
    }
  }
  if (!writeTeamFile(run.out + "/team.txt", team, error)) return false;
  if (!run.bag.path.empty() && !writeBag(bag_sequences, run.bag, error)) return false;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  info << "seconds: " << seconds << "\n";
  std::printf("%zu robots (%s) in %.1f s with %d threads -> %s\n", drives.size(), run.sensor.name.c_str(), seconds,
              run.threads, run.out.c_str());
  return true;
}

}  // namespace sim
}  // namespace scan_context_loop
