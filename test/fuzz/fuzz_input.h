// The fuzz targets of scripts/dev/fuzz (libFuzzer), callable without libFuzzer too: the regression test
// replays the inputs kept under test/fuzz_regressions/<target>/ through these same functions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "scan_context_loop/core/byte_stream.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop::fuzz {

/// A sensor_msgs/PointCloud2 decoded from the bytes (viewCloud), then, when it is accepted, processed
/// as one or two keyframes of a small KeyframePipeline.
int cloudInput(const std::uint8_t* data, std::size_t size);
/// Up to 4 nav_msgs/Odometry messages decoded from the bytes (poseFromMsg), each processed with a
/// fixed cloud as a keyframe of a small KeyframePipeline.
int odometryInput(const std::uint8_t* data, std::size_t size);
/// A database file in memory (readDatabase), appended to a small LoopDetector that is then queried.
int databaseFile(const std::uint8_t* data, std::size_t size);

/// Reads values from the fuzzer's bytes front to back; once they run out, every value is 0.
class FuzzBytes {
 public:
  FuzzBytes(const std::uint8_t* data, std::size_t size) : in_(data, size) {}

  template <typename T>
  T take() {
    T value{};
    if (const std::uint8_t* p = in_.take(sizeof(T))) std::memcpy(&value, p, sizeof(T));
    return value;
  }
  /// One selector byte, then a double: its raw bits (NaN, Inf, denormals, huge values), a small value
  /// (i16 / 256), or one of 0, ±Inf, NaN, DBL_MAX, the smallest denormal and 1e300.
  double number();
  /// Everything not read yet.
  std::vector<std::uint8_t> rest();
  std::size_t remaining() const { return in_.remaining(); }

 private:
  ByteReader in_;
};

/// A configuration small enough for thousands of inputs a second: a 5 x 12 grid of 20 m, verification
/// voxels of 2 m within 10 m, no recent
/// keyframes excluded, so that a second keyframe queries the first. The bits of `choice` turn on
/// registered clouds (1), the gravity alignment mode (2 bits from 2), verification (8), scan accumulation
/// (16), keyframe selection by motion (32), the voxel filter (64) and the occupancy ring key (128).
Config smallConfig(std::uint8_t choice);

/// The choice the database target loads with and fuzz_seeds saves with: verification on.
constexpr std::uint8_t kDatabaseChoice = 8;

/// A small fixed scene: two walls and a wavy fence around the sensor, 48 points.
PointView fixedCloud();

}  // namespace scan_context_loop::fuzz
