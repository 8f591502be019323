// Fuzz target: sensor_msgs/PointCloud2 decoding (viewCloud) and the core behind it.
//
// Input bytes, in order: u8 configuration choice (smallConfig), u8 flags (1: big-endian, 2: sizes made
// to agree with the data, 4: the cloud processed twice, the second time moved and turned so that it
// queries the first), u16 width, u16 height, u16 point_step, u32 row_step, u8 field count (0-5), per
// field u8 name (x, y, z, intensity, other), u32 offset, u8 datatype, u32 count; the rest is the data.
#include <Eigen/Geometry>
#include <sensor_msgs/PointCloud2.h>

#include "fuzz_input.h"
#include "scan_context_loop/core/keyframes.h"
#include "shared/cloud_input.h"

namespace scan_context_loop::fuzz {

namespace {

sensor_msgs::PointCloud2 decodeCloud(FuzzBytes* in, std::uint8_t flags) {
  sensor_msgs::PointCloud2 msg;
  msg.is_bigendian = (flags & 1) != 0;
  msg.width = in->take<std::uint16_t>();
  msg.height = in->take<std::uint16_t>();
  msg.point_step = in->take<std::uint16_t>();
  msg.row_step = in->take<std::uint32_t>();
  const int fields = in->take<std::uint8_t>() % 6;
  const char* const kNames[] = {"x", "y", "z", "intensity", "ring"};
  for (int i = 0; i < fields; ++i) {
    sensor_msgs::PointField f;
    f.name = kNames[in->take<std::uint8_t>() % 5];
    f.offset = in->take<std::uint32_t>();
    f.datatype = in->take<std::uint8_t>();
    f.count = in->take<std::uint32_t>();
    msg.fields.push_back(f);
  }
  msg.data = in->rest();
  if ((flags & 2) && msg.point_step > 0) {
    // Sizes that agree with the data, so that the points themselves reach the core.
    msg.height = msg.height % 4 + 1;
    msg.width = static_cast<std::uint32_t>(msg.data.size() / (std::size_t(msg.point_step) * msg.height));
    msg.row_step = msg.width * msg.point_step;
    msg.data.resize(std::size_t(msg.row_step) * msg.height);
  }
  return msg;
}

}  // namespace

int cloudInput(const std::uint8_t* data, std::size_t size) {
  FuzzBytes in(data, size);
  const std::uint8_t choice = in.take<std::uint8_t>();
  const std::uint8_t flags = in.take<std::uint8_t>();
  const sensor_msgs::PointCloud2 msg = decodeCloud(&in, flags);
  PointView view;
  std::string why;
  if (!viewCloud(msg, &view, &why)) return 0;
  KeyframePipeline pipeline(smallConfig(choice));
  KeyframeInfo info;
  info.pose = Eigen::Isometry3d::Identity();
  pipeline.process(view, info);
  if (flags & 4) {
    info.stamp = 10.0;
    info.pose = Eigen::Translation3d(0.5, 0.2, 0.0) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ());
    pipeline.process(view, info);
  }
  return 0;
}

}  // namespace scan_context_loop::fuzz
