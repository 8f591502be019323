// The worker's exception barrier: whatever it runs may throw, and the next keyframe is still processed.
#include <chrono>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>
#include <ros/time.h>

#include "loop_closure/keyframe_processor.h"
#include "loop_closure/keyframe_queue.h"
#include "loop_closure/keyframe_source.h"
#include "loop_closure/keyframe_worker.h"
#include "loop_closure/node_output.h"

namespace scan_context_loop {
namespace {

/// A keyframe with a pose: a ring of walls around the sensor, stamped `stamp`.
QueuedKeyframe keyframeAt(double stamp) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 3600; ++i) {
    const double a = i * 2.0 * M_PI / 3600.0, r = 10.0 + 5.0 * std::sin(3.0 * a);
    cloud.push_back(pcl::PointXYZ(r * std::cos(a), r * std::sin(a), (i % 7) * 0.3));
  }
  auto message = boost::make_shared<sensor_msgs::PointCloud2>();
  pcl::toROSMsg(cloud, *message);
  message->header.stamp = ros::Time(stamp);
  message->header.frame_id = "velodyne";
  QueuedKeyframe keyframe;
  keyframe.cloud = message;
  keyframe.has_pose = true;
  keyframe.pose_frame = "odom";
  keyframe.child_frame = "velodyne";
  keyframe.cloud_frame = "velodyne";
  keyframe.queued = std::chrono::steady_clock::now();
  return keyframe;
}

TEST(KeyframeWorker, WhatThrowsIsCountedAndTheNextKeyframeIsProcessed) {
  ros::Time::init();  // the throttled logs read the time
  Config config;
  config.verification.enabled = false;
  NodeOptions options;
  NodeCounters counters;
  KeyframeSource source("worker_test", config, options, &counters);
  KeyframeProcessor processor("worker_test", config, options, &counters);
  LoopClosureOutput output("worker_test", config, options, &counters);
  KeyframeQueue queue(10, &counters.queue_length);
  bool settings_throw = true;  // the hand-over of reconfigured settings throws once
  KeyframeWorker worker("worker_test", {&queue, &source, &processor, &output, &counters},
                        options.heap_statistics_interval, [&] {
                          if (!settings_throw) return;
                          settings_throw = false;
                          throw std::runtime_error("the settings hand-over threw");
                        });
  worker.start();
  ASSERT_TRUE(queue.pushTask([] { throw std::runtime_error("a task threw"); }));
  ASSERT_TRUE(queue.push(keyframeAt(1.0)));
  // The queue hands out tasks before keyframes, so the keyframe's end is watched for, not a task's.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (counters.database_size.load() == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  queue.stop();
  worker.join();
  EXPECT_EQ(counters.failures.load(), 2u) << "the settings hand-over and the task";
  EXPECT_EQ(processor.database().size(), 1u) << "the keyframe after them was not processed";
  EXPECT_EQ(counters.database_size.load(), 1u);
}

TEST(KeyframeQueue, StopSaysHowManyKeyframesWillNotBeProcessed) {
  std::atomic<std::size_t> length{0};
  KeyframeQueue queue(10, &length);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(queue.push(keyframeAt(1.0 + i)));
  EXPECT_EQ(length.load(), 3u);
  EXPECT_EQ(queue.stop(), 3u);
  WorkerJob job;
  EXPECT_FALSE(queue.take(std::chrono::milliseconds(0), &job)) << "a stopped queue still hands out work";
}

}  // namespace
}  // namespace scan_context_loop
