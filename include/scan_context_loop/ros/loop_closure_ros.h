// The ROS adapter: subscribes to keyframe clouds and poses, runs the core detector on a worker thread
// and publishes loop-closure constraints, RViz markers and diagnostics.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <boost/thread/recursive_mutex.hpp>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/KeyframeTiming.h"
#include "scan_context_loop/LoopClosure.h"
#include "scan_context_loop/LoopClosureConfig.h"
#include "scan_context_loop/LoadDatabase.h"
#include "scan_context_loop/Relocalize.h"
#include "scan_context_loop/SaveDatabase.h"
#include "scan_context_loop/ros/markers.h"
#include "scan_context_loop/ros/parameters.h"
#include "scan_context_loop/ros/sensor_extrinsic.h"

namespace scan_context_loop {

class HeapStatistics;

class LoopClosureRos {
 public:
  /// `nh` resolves the topics (relative names), `pnh` the parameters; `name` prefixes the logs.
  LoopClosureRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name);
  /// Stops the worker (it finishes the keyframe in hand) and unsubscribes; never blocks for long.
  ~LoopClosureRos();

  /// Reads and validates the parameters, then subscribes, advertises and starts the worker. Returns
  /// false, having logged every problem as fatal, when the configuration is impossible.
  bool start();

 private:
  /// A keyframe waiting for the worker.
  struct Item {
    sensor_msgs::PointCloud2ConstPtr cloud;
    bool has_pose = false;  ///< false in tf mode: the worker looks it up
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    // Frame ids as tf2 names them (frame_ids.h), normalised by the callback.
    std::string pose_frame;
    std::string child_frame;  ///< the odometry's child_frame_id (odom mode)
    std::string cloud_frame;  ///< the cloud's frame_id
    std::chrono::steady_clock::time_point queued;  ///< when the callback queued it
    std::size_t queue_length = 0;                  ///< keyframes left in the queue when the worker took it
  };
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2, nav_msgs::Odometry>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<sensor_msgs::PointCloud2, nav_msgs::Odometry>;

  void onCloudAndOdom(const sensor_msgs::PointCloud2ConstPtr& cloud, const nav_msgs::OdometryConstPtr& odom);
  void onCloudOnly(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onAnyCloud(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onAnyOdom(const nav_msgs::OdometryConstPtr& odom);
  void enqueue(Item item);
  void work();
  /// Runs `work` (one keyframe, one service task) on the worker behind the exception barrier: what it
  /// throws is logged with `context`, counted, and the per-keyframe lists catch up with the database,
  /// which is kept. Returns false, with the exception's what() in `what`, when it threw.
  bool runGuarded(const std::string& context, const std::function<void()>& work, std::string* what = nullptr);
  void process(Item item);
  /// Worker: processes `item` behind the exception barrier (runGuarded), and the heap statistics after it.
  void processGuarded(Item item, HeapStatistics* heap);
  /// Worker: holds `item` while the extrinsic it needs is missing (at most queue_size keyframes; the
  /// oldest held is dropped first), else processes it with those held before it.
  void processOrHold(Item item, HeapStatistics* heap);
  /// Worker: processes the held keyframes, in order, once the extrinsic is known or given up on.
  void releaseHeld(HeapStatistics* heap);
  bool lookUpPose(Item* item);
  void publishLoops(const Detection& detection, const std::string& frame);
  void publishRejected(const Loop& rejected, const std::string& frame);
  /// Warns (throttled) while levelling finds the odometry's world frame tilted from gravity (world_tilt.h).
  void reportWorldTilt(const Detection& detection);
  scan_context_loop::LoopClosure makeLoop(const Loop& loop, const std::string& frame) const;
  void publishMarkers(const std::string& frame);
  /// The extrinsic `item` needs (odometry of another frame than the sensor's: LeGO-LOAM's camera axes,
  /// an IMU body), from tf without waiting: known (the identity when none is needed), waiting, or given up.
  SensorExtrinsic::State resolveExtrinsic(const Item& item);
  /// Turns the pose into the sensor's with the extrinsic from tf (child <- sensor), once it is known.
  void applyExtrinsic(Item* item);
  /// lio_sam_output: the loop on lio_loop if it is verified, new and due (lio_sam_min_interval).
  void sendToLioSam(const scan_context_loop::LoopClosure& loop);
  void checkSynchronisation(const ros::WallTimerEvent&);
  /// Warns, naming the topic, when no cloud (odom mode: no odometry either) came for no_input_warning s.
  void checkInputs(const ros::WallTimerEvent&);

  // Database services and relocalization (database_services.cpp). Each service hands its work to the
  // worker, which owns the database, and waits for it.
  bool onSave(scan_context_loop::SaveDatabase::Request& request, scan_context_loop::SaveDatabase::Response& response);
  bool onLoad(scan_context_loop::LoadDatabase::Request& request, scan_context_loop::LoadDatabase::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onRelocalize(scan_context_loop::Relocalize::Request& request, scan_context_loop::Relocalize::Response& response);
  /// Runs `task` on the worker between keyframes and waits for it; "" when it ran, else why not (the
  /// node is stopping, or it threw).
  std::string runOnWorker(std::function<void()> task);
  /// Loads a database file into the pipeline (worker, or start() before the worker runs); "" or why not.
  std::string loadFile(const std::string& path);
  /// The per-keyframe lists (positions, poses, stamps, sessions) for the keyframes the database holds
  /// beyond them: those a load added, or one whose processing threw after it entered the database.
  void adoptDatabaseKeyframes();
  /// mode relocalize: a loop into the map as T_map<-sensor on `relocalization`.
  void publishRelocalization(const scan_context_loop::LoopClosure& loop);
  void advertiseSessionServices();
  /// dynamic_reconfigure: checks the live settings and hands them to the worker (applied before its
  /// next keyframe); a refused change is logged and the values in force are reported back.
  void onReconfigure(scan_context_loop::LoopClosureConfig& values, std::uint32_t level);
  /// Worker: takes the settings onReconfigure accepted, if any.
  void takeReconfigured();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_, pnh_;
  std::string name_;
  // Read in start(); then config_ is the worker's, and options_ is read by callbacks too, so the worker
  // changes only its live members, which callbacks never read (takeReconfigured).
  Config config_;
  RosOptions options_;

  // Inputs and outputs (set up in start(), used from callbacks; ROS handles are thread-safe).
  message_filters::Subscriber<sensor_msgs::PointCloud2> cloud_sub_;
  message_filters::Subscriber<nav_msgs::Odometry> odom_sub_;
  std::unique_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_sync_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  ros::Subscriber cloud_only_sub_;
  ros::Publisher loop_pub_, rejected_pub_, marker_pub_, lio_pub_, pair_pub_, array_pub_, relocalization_pub_,
      timing_pub_;
  ros::ServiceServer save_srv_, load_srv_, reset_srv_, relocalize_srv_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::WallTimer sync_timer_, input_timer_;
  ros::Timer diagnostics_timer_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  boost::recursive_mutex reconfigure_mutex_;  // dynamic_reconfigure's own (guards its Server's state)
  std::unique_ptr<dynamic_reconfigure::Server<scan_context_loop::LoopClosureConfig>> reconfigure_server_;

  // queue_mutex_ guards queue_, stop_, redraw_markers_ and the live settings below; queue_cv_ wakes the
  // worker.
  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::deque<Item> queue_;
  bool stop_ = false;
  bool redraw_markers_ = false;  // a marker subscriber connected: publish every marker once
  std::deque<std::function<void()>> tasks_;  // service work for the worker, in order
  // dynamic_reconfigure's accepted settings (all keys; only live ones ever differ from config_), and
  // whether the worker has yet to take them.
  Config live_config_;
  RosOptions live_options_;
  bool reconfigured_ = false;
  std::thread worker_;

  // Counters read by diagnostics and the synchronisation check; written by callbacks and the worker.
  std::atomic<std::size_t> dropped_{0}, rejected_{0}, loops_found_{0}, database_size_{0}, queue_length_{0},
      loops_waiting_{0}, lio_skipped_{0}, sessions_count_{1}, failures_{0}, registration_bytes_{0},
      registration_memory_{0}, database_bytes_per_keyframe_{0};
  // Clouds that reached the node, and those that became keyframes (paired with a pose, or taken alone
  // with tf poses): a cloud lost before the node (roscpp's subscriber queue of sync_queue_size) is in
  // neither; one whose pose never came is in the first only.
  std::atomic<std::size_t> clouds_received_{0}, clouds_paired_{0};
  std::atomic<long long> heap_allocated_{-1}, heap_free_{-1};  // malloc's statistics at the worker's last read
  std::atomic<double> heap_statistics_ms_{0.0};
  std::atomic<double> last_query_ms_{0.0}, last_keyframe_ms_{0.0}, max_keyframe_ms_{0.0};
  std::atomic<double> last_cloud_wall_{0.0}, last_pair_wall_{0.0}, first_unpaired_wall_{0.0}, last_odom_wall_{0.0};
  double start_wall_ = 0.0;  // when start() subscribed (set before any callback)
  std::atomic<std::size_t> held_count_{0};  // keyframes the worker holds for the extrinsic

  // Worker-only state: touched by the worker thread alone, no lock.
  std::unique_ptr<KeyframePipeline> pipeline_;
  std::vector<Eigen::Vector3d> positions_;  // keyframe positions in the pose frame, by keyframe number
  std::vector<Eigen::Isometry3d> poses_;    // keyframe sensor poses in the pose frame, by keyframe number
  std::vector<ros::Time> stamps_;           // keyframe stamps, by keyframe number
  std::vector<std::uint32_t> sessions_;     // keyframe sessions, by keyframe number
  std::vector<LoopEdge> edges_, rejected_edges_;
  MarkerState markers_shown_;   // what the published markers already show
  std::string marker_frame_;    // the pose frame of the newest keyframe
  ros::Time lio_last_sent_;     // lio_loop: when the last message went out, and its query keyframe
  std::size_t lio_last_query_ = static_cast<std::size_t>(-1);
  std::unique_ptr<SensorExtrinsic> extrinsic_;  // child <- sensor (odom mode with sensor_extrinsic_from_tf)
  std::deque<Item> held_;                       // keyframes waiting for the extrinsic, in order
};

}  // namespace scan_context_loop
