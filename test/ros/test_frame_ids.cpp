// Frame ids normalised as tf2 names them: tf1's leading '/' goes, nothing else changes.
#include <gtest/gtest.h>

#include "shared/frame_ids.h"

namespace scan_context_loop {
namespace {

TEST(FrameIds, LeadingSlashesGoTheRestStays) {
  EXPECT_EQ(normaliseFrameId("/camera_init"), "camera_init");
  EXPECT_EQ(normaliseFrameId("//camera"), "camera");
  EXPECT_EQ(normaliseFrameId("camera_init"), "camera_init");
  EXPECT_EQ(normaliseFrameId("robot/base_link"), "robot/base_link");
  EXPECT_EQ(normaliseFrameId("/robot/base_link/"), "robot/base_link/");
  EXPECT_EQ(normaliseFrameId(""), "");
  EXPECT_EQ(normaliseFrameId("/"), "");
}

TEST(FrameIds, EveryFrameParameter) {
  NodeOptions options;
  options.fixed_frame = "/camera_init";
  options.sensor_frame = "/base_link";
  options.map_frame = "/map";
  options.database_load = "/tmp/map.scdb";  // a path, not a frame: kept
  normaliseFrameIds(&options);
  EXPECT_EQ(options.fixed_frame, "camera_init");
  EXPECT_EQ(options.sensor_frame, "base_link");
  EXPECT_EQ(options.map_frame, "map");
  EXPECT_EQ(options.database_load, "/tmp/map.scdb");
  NodeOptions defaults, normalised;
  normaliseFrameIds(&normalised);
  EXPECT_EQ(normalised.fixed_frame, defaults.fixed_frame);
  EXPECT_EQ(normalised.sensor_frame, defaults.sensor_frame);
}

}  // namespace
}  // namespace scan_context_loop
