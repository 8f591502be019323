// A simulated drive written in the KITTI layout and read back as the evaluator reads sequences.
#pragma once

#include <cstdint>
#include <string>

#include "scan_context_loop/eval/sequence.h"
#include "sim_drive.h"

namespace scan_context_loop {
namespace test {

/// Writes `drive` to `dir` with an odometry of its own that starts at the identity (as a run of its own
/// does), and loads it back. `stamp_offset` is added to its times. Failures are gtest failures.
eval::Sequence writtenSequence(const Drive& drive, const std::string& dir, std::uint32_t seed, double stamp_offset);

}  // namespace test
}  // namespace scan_context_loop
