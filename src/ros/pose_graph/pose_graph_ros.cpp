#include "pose_graph/pose_graph_ros.h"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Path.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

namespace scan_context_loop {

PoseGraphRos::PoseGraphRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name)
    : nh_(nh), pnh_(pnh), name_(name) {}

PoseGraphRos::~PoseGraphRos() {
  save_srv_.shutdown();
  if (service_spinner_) service_spinner_->stop();  // a save in progress finishes first
  map_srv_.shutdown();
  for (GraphRobot& robot : robots_) {
    robot.odom_sub.shutdown();
    robot.cloud_sub.shutdown();
    robot.loop_sub.shutdown();
  }
  tf_timer_.stop();
  diagnostics_timer_.stop();
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    stop_ = true;
  }
  queue_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
  saveAtShutdown();
}

bool PoseGraphRos::start() {
  std::vector<std::string> warnings;
  const auto problems = readPoseGraphParameters(pnh_, &graph_config_, &map_config_, &options_, &warnings);
  for (const auto& w : warnings) ROS_WARN_NAMED(name_, "parameter: %s", w.c_str());
  if (!problems.empty()) {
    for (const auto& p : problems) ROS_FATAL_NAMED(name_, "invalid parameter: %s", p.c_str());
    ROS_FATAL_NAMED(name_, "not starting: fix the parameters above (see launch/pose_graph.launch)");
    return false;
  }
  graph_.reset(new PoseGraph(graph_config_));
  map_.reset(new KeyframeMap(map_config_));

  // The robots and their outputs (latched: RViz opened late, or a tool asking once, still gets the
  // latest paths and map).
  const std::vector<std::string> ids = robotIds(options_);
  team_ = !ids.empty();
  robots_.resize(team_ ? ids.size() : 1);
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    GraphRobot& robot = robots_[r];
    robot.id = team_ ? ids[r] : "";
    robot.chain = r;
    robot.path_pub = nh_.advertise<nav_msgs::Path>(robot.topic("corrected_path"), 1, true);
    robot.odometry_path_pub = nh_.advertise<nav_msgs::Path>(robot.topic("odometry_path"), 1, true);
  }
  marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("graph_markers", 1, true);
  map_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("map_cloud", 1, true);
  map_srv_ = pnh_.advertiseService("publish_map", &PoseGraphRos::onPublishMap, this);
  advertiseSaveMap();
  if (options_.publish_tf) {
    tf_broadcaster_.reset(new tf2_ros::TransformBroadcaster);
    tf_timer_ = nh_.createTimer(ros::Duration(1.0 / options_.tf_rate), &PoseGraphRos::onTfTimer, this);
  }
  diagnostics_.reset(new diagnostic_updater::Updater(nh_, pnh_, name_));
  diagnostics_->setHardwareID("none");
  diagnostics_->add("pose graph", this, &PoseGraphRos::diagnose);
  diagnostics_timer_ = nh_.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { diagnostics_->update(); });

  worker_ = std::thread(&PoseGraphRos::work, this);
  subscribeRobots();
  return true;
}

void PoseGraphRos::subscribeRobots() {
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    GraphRobot& robot = robots_[r];
    robot.odom_sub = nh_.subscribe<nav_msgs::Odometry>(
        robot.topic("selected_keyframe_odom"), 1000, [this, r](const nav_msgs::OdometryConstPtr& m) { onOdom(m, r); });
    robot.loop_sub = nh_.subscribe<scan_context_loop::LoopClosure>(
        robot.topic("loop_closures"), 1000,
        [this, r](const scan_context_loop::LoopClosureConstPtr& m) { onLoop(m, r); });
    if (options_.build_map) {
      robot.cloud_sub = nh_.subscribe<sensor_msgs::PointCloud2>(
          robot.topic("selected_keyframe_cloud"), 1000,
          [this, r](const sensor_msgs::PointCloud2ConstPtr& m) { onCloud(m, r); });
    }
    ROS_INFO_NAMED(name_, "pose graph on %s + %s%s; %s loops; corrected poses in %s%s%s",
                   robot.odom_sub.getTopic().c_str(), robot.loop_sub.getTopic().c_str(),
                   options_.build_map ? (", map from " + robot.cloud_sub.getTopic()).c_str() : "",
                   options_.verified_only ? "verified" : "all", options_.map_frame.c_str(),
                   team_ ? (r == 0 ? " (the anchor: robot " : " (robot ") : "",
                   team_ ? (robot.id + ", chain " + std::to_string(r) + ")").c_str() : "");
  }
}

// ---- callbacks: queue and return ----------------------------------------------------------------

void PoseGraphRos::observeStamp(const ros::Time& stamp) {
  std::lock_guard<std::mutex> lock(data_clock_mutex_);
  data_clock_.observe(stamp, ros::Time::now());
}

void PoseGraphRos::onOdom(const nav_msgs::OdometryConstPtr& msg, std::size_t robot) {
  observeStamp(msg->header.stamp);
  Event event;
  event.robot = robot;
  event.odom = msg;
  enqueue(std::move(event));
}

void PoseGraphRos::onCloud(const sensor_msgs::PointCloud2ConstPtr& msg, std::size_t robot) {
  observeStamp(msg->header.stamp);
  Event event;
  event.robot = robot;
  event.cloud = msg;
  enqueue(std::move(event));
}

void PoseGraphRos::onLoop(const scan_context_loop::LoopClosureConstPtr& msg, std::size_t robot) {
  if (options_.verified_only && !msg->verified) {
    ++loops_skipped_;
    return;
  }
  Event event;
  event.robot = robot;
  event.loop = msg;
  enqueue(std::move(event));
}

bool PoseGraphRos::onPublishMap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  if (!options_.build_map) {
    response.success = false;
    response.message = "build_map is false: no keyframe clouds are kept";
    return true;
  }
  Event event;
  event.publish_map = true;
  enqueue(std::move(event));
  response.success = true;
  response.message = "the map goes out on " + map_pub_.getTopic();
  return true;
}

void PoseGraphRos::enqueue(Event event) {
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (queue_.size() >= static_cast<std::size_t>(options_.queue_size)) {
      ++dropped_;
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "pose graph queue full (%d): dropped %zu messages so far",
                              options_.queue_size, dropped_.load());
      return;
    }
    queue_.push_back(std::move(event));
  }
  queue_cv_.notify_one();
}

void PoseGraphRos::onTfTimer(const ros::TimerEvent&) {
  std::vector<geometry_msgs::TransformStamped> transforms;
  {
    std::lock_guard<std::mutex> lock(correction_mutex_);
    for (const TfFrame& frame : tf_frames_) {
      transforms.push_back(tf2::eigenToTransform(frame.correction));
      transforms.back().child_frame_id = frame.odom_frame;
    }
  }
  if (transforms.empty()) return;
  // Stamped with the data's time (shared/data_clock.h); not again at a stamp already sent (a paused replay).
  ros::Time stamp;
  {
    std::lock_guard<std::mutex> lock(data_clock_mutex_);
    if (!data_clock_.next(ros::Time::now(), &stamp)) return;
  }
  for (auto& tf : transforms) {
    tf.header.frame_id = options_.map_frame;
    tf.header.stamp = stamp;
  }
  tf_broadcaster_->sendTransform(transforms);
}

void PoseGraphRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  if (dropped_ > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "messages dropped (queue full)");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  status.add("keyframes", keyframes_.load());
  if (team_) {
    status.add("robots", robots_.size());
    status.add("robots joined", robots_joined_.load());
  }
  status.add("loops in the graph", loops_used_.load());
  status.add("loops skipped (unverified)", loops_skipped_.load());
  status.add("loops waiting for keyframes", loops_waiting_.load());
  status.add("inputs rejected", rejected_.load());
  status.add("messages dropped", dropped_.load());
  status.add("solves", solves_.load());
  status.add("last solve [ms]", last_solve_ms_.load());
  status.add("last final cost", last_cost_.load());
  status.add("map points kept", map_points_.load());
  status.add("map saves written", saves_.load());
  status.add("map saves failed", save_failures_.load());
}

}  // namespace scan_context_loop
