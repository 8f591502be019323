#include "written_sequence.h"

#include <gtest/gtest.h>

#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {

eval::Sequence writtenSequence(const Drive& drive, const std::string& dir, std::uint32_t seed, double stamp_offset) {
  sim::SequenceData data;
  data.truth = drive.truth;
  for (double t : drive.times) data.times.push_back(t + stamp_offset);
  data.world_clock = drive.world_clock - stamp_offset;
  sim::DriftOptions drift;
  drift.seed = seed;
  data.odometry = sim::driftedOdometry(data.truth, drift);
  const Eigen::Isometry3d origin = data.odometry.front().inverse();
  for (Eigen::Isometry3d& pose : data.odometry) pose = origin * pose;
  std::string error;
  EXPECT_GT(sim::writeSequence(dir, drive.world, drive.sensor, data, 0.0, seed, 2, &error), 1000.0) << error;
  eval::Sequence sequence;
  EXPECT_TRUE(eval::loadSequence(dir, eval::SequenceOptions(), &sequence, &error)) << error;
  return sequence;
}

}  // namespace test
}  // namespace scan_context_loop
