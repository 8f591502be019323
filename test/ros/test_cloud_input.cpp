// PointCloud2 checks: a well-formed cloud is viewed in place, each malformed one refused with its reason
// and without a byte read. No ROS master needed.
#include <cstring>
#include <string>

#include <gtest/gtest.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>

#include "shared/cloud_input.h"

namespace scan_context_loop {
namespace {

/// 6 x 2 points with x, y, z and intensity (16-byte points); point i at (i, -i, 0.5 i).
sensor_msgs::PointCloud2 goodCloud() {
  pcl::PointCloud<pcl::PointXYZI> cloud(6, 2);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    cloud[i].x = static_cast<float>(i);
    cloud[i].y = -static_cast<float>(i);
    cloud[i].z = 0.5f * i;
    cloud[i].intensity = 1.0f;
  }
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(cloud, msg);
  return msg;
}

float zOf(const PointView& view, std::size_t i) {
  float z;
  std::memcpy(&z, view.data + i * view.stride + view.offset_z, 4);
  return z;
}

/// Expects `msg` refused with a reason that contains `words`, the view left as it was.
void expectRefused(const sensor_msgs::PointCloud2& msg, const std::string& words) {
  PointView view;
  view.count = 12345;
  std::string why;
  EXPECT_FALSE(viewCloud(msg, &view, &why));
  EXPECT_NE(why.find(words), std::string::npos) << "reason: " << why << "; expected: " << words;
  EXPECT_EQ(view.count, 12345u);
}

TEST(CloudInput, AWellFormedCloudIsViewedInPlace) {
  const sensor_msgs::PointCloud2 msg = goodCloud();
  PointView view;
  std::string why;
  ASSERT_TRUE(viewCloud(msg, &view, &why)) << why;
  EXPECT_EQ(view.count, 12u);
  EXPECT_EQ(view.stride, msg.point_step);
  EXPECT_EQ(view.data, msg.data.data());
  EXPECT_FLOAT_EQ(zOf(view, 7), 3.5f);
}

TEST(CloudInput, AnEmptyCloudIsAcceptedAsNoPoints) {
  sensor_msgs::PointCloud2 msg = goodCloud();
  msg.width = msg.height = msg.row_step = 0;
  msg.data.clear();
  PointView view;
  std::string why;
  ASSERT_TRUE(viewCloud(msg, &view, &why)) << why;
  EXPECT_EQ(view.count, 0u);
}

TEST(CloudInput, MissingOrMistypedFieldsAreRefused) {
  sensor_msgs::PointCloud2 msg = goodCloud();
  msg.fields.erase(msg.fields.begin() + 2);  // z
  expectRefused(msg, "no field z");
  msg = goodCloud();
  msg.fields[0].datatype = sensor_msgs::PointField::FLOAT64;
  expectRefused(msg, "field x is not a single float32");
  msg = goodCloud();
  msg.fields[1].count = 0;
  expectRefused(msg, "field y is not a single float32");
  msg = goodCloud();
  msg.fields[2].offset = msg.point_step - 2;
  expectRefused(msg, "field z lies beyond point_step");
}

TEST(CloudInput, SizesThatDisagreeAreRefused) {
  sensor_msgs::PointCloud2 msg = goodCloud();
  msg.data.resize(msg.data.size() / 2);
  expectRefused(msg, "bytes, row_step x height says");
  msg = goodCloud();
  msg.width += 1;  // row_step no longer covers a row
  expectRefused(msg, "is shorter than width");
  msg = goodCloud();
  msg.point_step = 0;
  expectRefused(msg, "beyond point_step");
  msg = goodCloud();
  msg.row_step += 4;  // padded rows, and data that does not hold them
  expectRefused(msg, "row_step x height says");
  msg.data.resize(msg.row_step * msg.height);
  expectRefused(msg, "padded rows");
  msg = goodCloud();
  msg.height = 0x40000000u;  // a product that would overflow 32 bits
  expectRefused(msg, "row_step x height says");
}

TEST(CloudInput, TheOtherByteOrderIsRefused) {
  sensor_msgs::PointCloud2 msg = goodCloud();
  msg.is_bigendian = !msg.is_bigendian;
  expectRefused(msg, "byte order");
}

}  // namespace
}  // namespace scan_context_loop
