// Writes the seed corpora of the fuzz targets: fuzz_seeds OUT_DIR makes
// OUT_DIR/{cloudInput,odometryInput,databaseFile}/ with a few valid inputs each, in the byte layouts the targets read
// (fuzz_cloud.cpp, fuzz_odometry.cpp, fuzz_database.cpp).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/stat.h>

#include "fuzz_input.h"
#include "scan_context_loop/core/database_file.h"

using namespace scan_context_loop;

namespace {

void writeSeed(const std::string& dir, const std::string& name, const std::vector<std::uint8_t>& bytes) {
  ::mkdir(dir.c_str(), 0755);
  std::ofstream(dir + "/" + name, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

/// The fixed cloud as a PointCloud2 with float32 x, y, z and, with `intensity`, a fourth float.
std::vector<std::uint8_t> cloudSeed(std::uint8_t choice, std::uint8_t flags, bool intensity) {
  const PointView view = fuzz::fixedCloud();
  const std::uint32_t step = intensity ? 16 : 12;
  ByteWriter out;
  out.u8(choice);
  out.u8(flags);
  const std::uint16_t width = static_cast<std::uint16_t>(view.count), height = 1;
  for (std::uint16_t v : {width, height, static_cast<std::uint16_t>(step)}) {
    out.u8(static_cast<std::uint8_t>(v));
    out.u8(static_cast<std::uint8_t>(v >> 8));
  }
  out.u32(width * step);
  out.u8(intensity ? 4 : 3);
  for (std::uint8_t field = 0; field < (intensity ? 4 : 3); ++field) {
    out.u8(field);       // x, y, z, intensity
    out.u32(4 * field);  // offset
    out.u8(7);           // FLOAT32
    out.u32(1);
  }
  for (std::size_t i = 0; i < view.count; ++i) {
    const float* p = reinterpret_cast<const float*>(view.data + i * view.stride);
    out.f32s(p, 3);
    if (intensity) out.f32(static_cast<float>(i));
  }
  return out.buffer();
}

/// Four odometry messages a metre apart, turning, one second apart; `broken` adds one whose
/// orientation is all zeros.
std::vector<std::uint8_t> odometrySeed(std::uint8_t choice, std::uint8_t mode, bool broken) {
  ByteWriter out;
  out.u8(choice);
  out.u8(mode);
  for (int i = 0; i < 4; ++i) {
    out.u32(100 + i);
    out.u32(250000000);
    const double yaw = 0.1 * i;
    const bool zero = broken && i == 3;
    for (double v : {1.0 * i, 0.2 * i, 0.0, 0.0, 0.0, zero ? 0.0 : std::sin(yaw / 2), zero ? 0.0 : std::cos(yaw / 2)}) {
      out.u8(0);  // a raw double
      out.f64(v);
    }
  }
  return out.buffer();
}

/// A database of four keyframes of the fixed cloud, saved with smallConfig(kDatabaseChoice).
std::vector<std::uint8_t> databaseSeed(std::uint8_t mode, bool clouds, const std::string& scratch) {
  LoopDetector detector(fuzz::smallConfig(fuzz::kDatabaseChoice));
  for (int i = 0; i < 4; ++i) {
    KeyframeInfo info;
    info.stamp = i;
    info.pose = Eigen::Isometry3d(Eigen::Translation3d(0.5 * i, 0.0, 0.0));
    detector.process(fuzz::fixedCloud(), info);
  }
  SaveOptions options;
  options.include_clouds = clouds;
  std::string error;
  if (!saveDatabase(detector, scratch, options, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  std::ifstream file(scratch, std::ios::binary);
  std::vector<std::uint8_t> bytes{mode};
  bytes.insert(bytes.end(), std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  std::remove(scratch.c_str());
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT_DIR\n");
    return 2;
  }
  const std::string out = argv[1];
  ::mkdir(out.c_str(), 0755);
  for (std::uint8_t choice : {0, 8, 1 | 8, 16 | 32, 64 | 128}) {
    const std::string c = std::to_string(choice);
    writeSeed(out + "/cloudInput", "xyz_" + c, cloudSeed(choice, 2 | 4, false));
    writeSeed(out + "/cloudInput", "xyzi_" + c, cloudSeed(choice, 4, true));
    writeSeed(out + "/odometryInput", "drive_" + c, odometrySeed(choice, 0, false));
    writeSeed(out + "/odometryInput", "zero_quaternion_" + c, odometrySeed(choice, 1, true));
  }
  for (std::uint8_t mode : {0, 3}) {
    writeSeed(out + "/databaseFile", "descriptors_" + std::to_string(mode), databaseSeed(mode, false, out + "/db.tmp"));
    writeSeed(out + "/databaseFile", "clouds_" + std::to_string(mode), databaseSeed(mode, true, out + "/db.tmp"));
  }
  return 0;
}
