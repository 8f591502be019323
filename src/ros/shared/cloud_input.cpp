#include "shared/cloud_input.h"

#include <cstdint>

namespace scan_context_loop {

namespace {

bool floatField(const sensor_msgs::PointCloud2& msg, const char* name, std::size_t* offset, std::string* why) {
  for (const auto& f : msg.fields) {
    if (f.name != name) continue;
    if (f.datatype != sensor_msgs::PointField::FLOAT32 || f.count != 1) {
      *why = std::string("field ") + name + " is not a single float32";
      return false;
    }
    if (static_cast<std::uint64_t>(f.offset) + 4 > msg.point_step) {
      *why = std::string("field ") + name + " lies beyond point_step";
      return false;
    }
    *offset = f.offset;
    return true;
  }
  *why = std::string("no field ") + name;
  return false;
}

}  // namespace

bool viewCloud(const sensor_msgs::PointCloud2& msg, PointView* view, std::string* why) {
  const bool host_big_endian = [] {
    const std::uint16_t one = 1;
    return *reinterpret_cast<const std::uint8_t*>(&one) == 0;
  }();
  if (static_cast<bool>(msg.is_bigendian) != host_big_endian) {
    *why = "byte order differs from this machine's";
    return false;
  }
  PointView v;
  if (!floatField(msg, "x", &v.offset_x, why) || !floatField(msg, "y", &v.offset_y, why) ||
      !floatField(msg, "z", &v.offset_z, why)) {
    return false;
  }
  const std::uint64_t width = msg.width, height = msg.height, step = msg.point_step, row = msg.row_step;
  if (width * height > 0 && (step == 0 || row < width * step)) {
    *why = "row_step " + std::to_string(row) + " is shorter than width " + std::to_string(width) + " x point_step " +
           std::to_string(step);
    return false;
  }
  if (row * height != msg.data.size()) {
    *why = "data holds " + std::to_string(msg.data.size()) + " bytes, row_step x height says " +
           std::to_string(row * height);
    return false;
  }
  v.count = static_cast<std::size_t>(width * height);
  v.stride = static_cast<std::size_t>(step);
  v.data = v.count > 0 ? msg.data.data() : nullptr;
  if (height > 1 && row != width * step) {
    // Padded rows cannot be walked with one stride.
    *why = "padded rows (row_step != width x point_step) are not supported";
    return false;
  }
  *view = v;
  return true;
}

}  // namespace scan_context_loop
