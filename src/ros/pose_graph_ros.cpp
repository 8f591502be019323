#include "scan_context_loop/ros/pose_graph_ros.h"

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
  odom_sub_.shutdown();
  cloud_sub_.shutdown();
  loop_sub_.shutdown();
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

  // Latched: RViz opened late, or a tool asking once, still gets the latest paths and map.
  path_pub_ = nh_.advertise<nav_msgs::Path>("corrected_path", 1, true);
  odometry_path_pub_ = nh_.advertise<nav_msgs::Path>("odometry_path", 1, true);
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
  odom_sub_ = nh_.subscribe("selected_keyframe_odom", 1000, &PoseGraphRos::onOdom, this);
  loop_sub_ = nh_.subscribe("loop_closures", 1000, &PoseGraphRos::onLoop, this);
  if (options_.build_map) cloud_sub_ = nh_.subscribe("selected_keyframe_cloud", 1000, &PoseGraphRos::onCloud, this);
  ROS_INFO_NAMED(name_, "pose graph on %s + %s%s; %s loops; corrected poses in %s", odom_sub_.getTopic().c_str(),
                 loop_sub_.getTopic().c_str(), options_.build_map ? (", map from " + cloud_sub_.getTopic()).c_str() : "",
                 options_.verified_only ? "verified" : "all", options_.map_frame.c_str());
  return true;
}

// ---- callbacks: queue and return ----------------------------------------------------------------

void PoseGraphRos::onOdom(const nav_msgs::OdometryConstPtr& msg) {
  Event event;
  event.odom = msg;
  enqueue(std::move(event));
}

void PoseGraphRos::onCloud(const sensor_msgs::PointCloud2ConstPtr& msg) {
  Event event;
  event.cloud = msg;
  enqueue(std::move(event));
}

void PoseGraphRos::onLoop(const scan_context_loop::LoopClosureConstPtr& msg) {
  if (options_.verified_only && !msg->verified) {
    ++loops_skipped_;
    return;
  }
  Event event;
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
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "pose graph queue full (%d): dropped %zu messages so far", options_.queue_size,
                              dropped_.load());
      return;
    }
    queue_.push_back(std::move(event));
  }
  queue_cv_.notify_one();
}

void PoseGraphRos::onTfTimer(const ros::TimerEvent&) {
  geometry_msgs::TransformStamped tf;
  {
    std::lock_guard<std::mutex> lock(correction_mutex_);
    if (!have_correction_) return;
    tf = tf2::eigenToTransform(correction_);
    tf.child_frame_id = odom_frame_;
  }
  tf.header.frame_id = options_.map_frame;
  tf.header.stamp = ros::Time::now();
  tf_broadcaster_->sendTransform(tf);
}

void PoseGraphRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  if (dropped_ > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "messages dropped (queue full)");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  status.add("keyframes", keyframes_.load());
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
