// The reference backend's ROS adapter: keyframe poses (selected_keyframe_odom) and loop closures
// (loop_closures) in; the corrected keyframe path, the raw odometry path, the loops as markers, the
// correction as the tf map_frame -> odometry frame, and a corrected map cloud out; the map as files on
// ~save_map and at shutdown (map_save). With `robots`, the same per robot (`<robot>/...`, each robot a
// chain of the graph, pose_graph_robots.h) and one merged map. Callbacks queue what arrives; one worker
// owns the graph and the map and publishes.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include "scan_context_loop/LoopClosure.h"
#include "scan_context_loop/SaveMap.h"
#include "scan_context_loop/graph/keyframe_map.h"
#include "scan_context_loop/graph/map_files.h"
#include "scan_context_loop/graph/pose_graph.h"
#include "pose_graph/pose_graph_parameters.h"
#include "pose_graph/pose_graph_robots.h"
#include "shared/data_clock.h"

namespace scan_context_loop {

class PoseGraphRos {
 public:
  /// `nh` resolves the topics (relative names), `pnh` the parameters; `name` prefixes the logs.
  PoseGraphRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name);
  /// Stops the inputs and the worker (it finishes the solve in hand); with map_save set, the worker
  /// first handles what is queued and the map is written there.
  ~PoseGraphRos();

  /// Reads and validates the parameters, then subscribes, advertises and starts the worker. False, with
  /// every problem logged as fatal, when the configuration is impossible.
  bool start();

 private:
  /// Something that arrived, waiting for the worker: exactly one pointer is set, or publish_map, or task.
  struct Event {
    std::size_t robot = 0;  ///< robots_ index of the robot whose topic it came on
    nav_msgs::OdometryConstPtr odom;
    sensor_msgs::PointCloud2ConstPtr cloud;
    scan_context_loop::LoopClosureConstPtr loop;
    bool publish_map = false;    ///< the publish_map service asked for the map
    std::function<void()> task;  ///< a service's work on the graph (runOnWorker)
  };

  /// Sets up robots_ and subscribes each robot's inputs (the worker runs already).
  void subscribeRobots();
  void onOdom(const nav_msgs::OdometryConstPtr& msg, std::size_t robot);
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& msg, std::size_t robot);
  void onLoop(const scan_context_loop::LoopClosureConstPtr& msg, std::size_t robot);
  bool onPublishMap(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  void enqueue(Event event);
  void onTfTimer(const ros::TimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  // Saving the map (pose_graph_saving.cpp).
  void advertiseSaveMap();
  bool onSaveMap(scan_context_loop::SaveMap::Request& request, scan_context_loop::SaveMap::Response& response);
  /// Runs `task` on the worker and waits for it; "" when it ran, else why not (stopping, timed out, threw).
  std::string runOnWorker(std::function<void()> task);
  /// The directory a save writes for `requested` (~save_map's path; empty: map_save), checked as
  /// ~save_database's paths are (database_paths.h); false with the reason.
  bool mapTarget(const std::string& requested, std::string* directory, std::string* error) const;
  /// Worker: solves if a solve is due, then copies the graph and assembles the map.
  MapFiles snapshotMap();
  /// Writes `files` into `directory` and counts the save; false with the reason.
  bool writeMap(const std::string& directory, const MapFiles& files, MapFilesReport* report, std::string* error);
  /// After the worker stopped: writes map_save, if set.
  void saveAtShutdown();

  // Worker (pose_graph_worker.cpp).
  void work();
  /// Handles a batch taken from the queue; true if one asked for the map.
  bool handleBatch(const std::deque<Event>& batch, bool* changed);
  void handle(const Event& event);
  void addKeyframe(const nav_msgs::Odometry& msg, GraphRobot* robot);
  void addCloud(const sensor_msgs::PointCloud2& msg, GraphRobot* robot);
  /// Adds the loop (that came on robot `robot`'s topic) if both keyframes are known; false if it has to
  /// wait for them.
  bool addLoop(const scan_context_loop::LoopClosure& msg, std::size_t robot);
  void retryWaitingLoops();
  void solveAndPublish(bool solve);
  /// The loops between keyframes in map_frame as markers (those of robots not joined are left out).
  void publishMarkers(const std::vector<Eigen::Isometry3d>& poses, const ros::Time& stamp);
  void publishMap();

  ros::NodeHandle nh_, pnh_;
  std::string name_;
  PoseGraphConfig graph_config_;
  KeyframeMapConfig map_config_;
  PoseGraphOptions options_;

  /// The robots (one, id "", without the `robots` parameter), the anchor first; set up by start().
  std::vector<GraphRobot> robots_;
  bool team_ = false;  ///< the `robots` parameter is set
  ros::Publisher marker_pub_, map_pub_;
  ros::ServiceServer map_srv_, save_srv_;
  // ~save_map has its own queue and thread: a call waits for the worker and for its write, and holds up
  // nothing else meanwhile.
  ros::CallbackQueue service_queue_;
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;
  ros::Timer tf_timer_, diagnostics_timer_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;

  // queue_mutex_ guards queue_ and stop_; queue_cv_ wakes the worker.
  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::deque<Event> queue_;
  bool stop_ = false;
  std::thread worker_;

  // correction_mutex_ guards tf_frames_ (worker writes, tf timer reads): map_frame -> each joined
  // robot's odometry frame, its correction.
  struct TfFrame {
    std::string odom_frame;
    Eigen::Isometry3d correction;
  };
  std::mutex correction_mutex_;
  std::vector<TfFrame> tf_frames_;

  // data_clock_mutex_ guards data_clock_ (the callbacks observe each input's stamp, the tf timer reads
  // it): the tf is stamped with the data's time, so a replay without --clock can still look it up.
  std::mutex data_clock_mutex_;
  DataClock data_clock_;
  /// Notes an input's stamp in data_clock_ (callback threads).
  void observeStamp(const ros::Time& stamp);

  // Counters read by diagnostics; written by callbacks and the worker.
  std::atomic<std::size_t> keyframes_{0}, loops_used_{0}, loops_skipped_{0}, loops_waiting_{0}, rejected_{0},
      dropped_{0}, solves_{0}, map_points_{0}, saves_{0}, save_failures_{0}, robots_joined_{0};
  std::atomic<double> last_solve_ms_{0.0}, last_cost_{0.0};

  // Worker-only state.
  std::unique_ptr<PoseGraph> graph_;
  std::unique_ptr<KeyframeMap> map_;
  struct WaitingLoop {
    scan_context_loop::LoopClosure msg;
    std::size_t robot;  // the robot whose topic it came on
  };
  std::vector<WaitingLoop> waiting_;  // loops whose keyframes have not arrived yet
  struct UsedLoop {
    std::size_t query, match;
    bool verified;
  };
  std::vector<UsedLoop> used_;
  ros::WallTime last_solve_;
  ros::WallTime last_map_;
  bool solve_pending_ = false;
  bool map_changed_ = false;
};

}  // namespace scan_context_loop
