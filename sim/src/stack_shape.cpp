#include "scan_context_sim/stack_shape.h"

namespace scan_context_loop {
namespace sim {

namespace {

StackShape shape(const char* name, const char* cloud_topic, const char* odom_topic, const char* cloud_frame,
                 const char* odom_frame, const char* child_frame, bool registered) {
  StackShape s;
  s.name = name;
  s.cloud_topic = cloud_topic;
  s.odom_topic = odom_topic;
  s.cloud_frame = cloud_frame;
  s.odom_frame = odom_frame;
  s.child_frame = child_frame;
  s.registered = registered;
  s.rate_hz = 10.0;
  return s;
}

std::vector<StackShape> makeShapes() {
  // laserMapping: every scan registered in camera_init (z up despite the name), frames written with
  // tf1's leading '/', and the tf /camera_init -> /aft_mapped with each pose.
  StackShape aloam = shape("aloam", "/velodyne_cloud_registered", "/aft_mapped_to_init", "/camera_init", "/camera_init",
                           "/aft_mapped", true);
  aloam.odom_tf = true;
  aloam.world_at_first_scan = true;
  // imageProjection (base_link clouds) and transformFusion (pose in camera axes, y up, with the tf
  // /camera_init -> /camera); run.launch sends /camera -> /base_link and /map -> /camera_init with tf1's
  // static_transform_publisher, every 10 ms on /tf.
  StackShape lego =
      shape("lego_loam", "/full_cloud_projected", "/integrated_to_init", "base_link", "/camera_init", "/camera", false);
  lego.camera_axes = true;
  lego.extrinsic_parent = "/camera";
  lego.extrinsic_child = "/base_link";
  lego.map_frame = "/map";
  lego.fixed_tf_period = 0.01;
  lego.odom_tf = true;
  lego.world_at_first_scan = true;
  // mapOptimization: every deskewed scan registered in odom.
  StackShape lio_sam = shape("lio_sam", "/lio_sam/mapping/cloud_registered_raw", "/lio_sam/mapping/odometry", "odom",
                             "odom", "odom_mapping", true);
  // laserMapping: every scan in the body frame, whose pose /Odometry gives.
  // Its world frame is the first IMU frame (the gravity alignment is left out), not gravity-aligned.
  StackShape fast_lio = shape("fast_lio", "/cloud_registered_body", "/Odometry", "body", "camera_init", "body", false);
  fast_lio.world_at_first_scan = true;
  // SC-A-LOAM: A-LOAM's laserMapping, which also publishes each scan in the sensor frame on
  // /velodyne_cloud_registered_local, still labelled /camera_init (the world's name on sensor-frame points).
  StackShape sc_aloam = shape("sc_aloam", "/velodyne_cloud_registered_local", "/aft_mapped_to_init", "/camera_init",
                              "/camera_init", "/aft_mapped", false);
  sc_aloam.odom_tf = true;
  sc_aloam.world_at_first_scan = true;
  // hdl_graph_slam: prefiltering's /filtered_points in base_link (the LiDAR's frame here) and
  // scan_matching_odometry's /odom (odom -> base_link, also on /tf), its world the first scan's frame.
  StackShape hdl = shape("hdl_graph_slam", "/filtered_points", "/odom", "base_link", "odom", "base_link", false);
  hdl.odom_tf = true;
  hdl.world_at_first_scan = true;
  return {aloam, lego, lio_sam, fast_lio, sc_aloam, hdl};
}

}  // namespace

const std::vector<StackShape>& stackShapes() {
  static const std::vector<StackShape> shapes = makeShapes();
  return shapes;
}

const StackShape* findStackShape(const std::string& name) {
  for (const StackShape& s : stackShapes()) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string stackNames() {
  std::string names;
  for (const StackShape& s : stackShapes()) names += (names.empty() ? "" : " | ") + s.name;
  return names;
}

namespace {

std::string withoutSlash(const std::string& name) { return !name.empty() && name[0] == '/' ? name.substr(1) : name; }

}  // namespace

std::string robotTopic(const std::string& robot, const std::string& topic) {
  return robot.empty() ? topic : "/" + robot + "/" + withoutSlash(topic);
}

std::string robotFrame(const std::string& robot, const std::string& frame) {
  return robot.empty() || frame.empty() ? frame : robot + "/" + withoutSlash(frame);
}

StackShape forRobot(const StackShape& shape, const std::string& robot) {
  StackShape s = shape;
  for (std::string* topic : {&s.cloud_topic, &s.odom_topic}) *topic = robotTopic(robot, *topic);
  for (std::string* frame :
       {&s.cloud_frame, &s.odom_frame, &s.child_frame, &s.extrinsic_parent, &s.extrinsic_child, &s.map_frame}) {
    *frame = robotFrame(robot, *frame);
  }
  return s;
}

Eigen::Isometry3d odometryAxes(const StackShape& shape) {
  Eigen::Isometry3d axes = Eigen::Isometry3d::Identity();
  if (shape.camera_axes) axes.linear() << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return axes;
}

std::vector<FixedTransform> fixedTransforms(const StackShape& shape) {
  std::vector<FixedTransform> fixed;
  if (shape.camera_axes) fixed.push_back({shape.extrinsic_parent, shape.extrinsic_child, odometryAxes(shape)});
  if (!shape.map_frame.empty()) {
    // The world in camera axes, turned back to z up: T_map<-odometry frame is the axes' inverse.
    fixed.push_back({shape.map_frame, shape.odom_frame, odometryAxes(shape).inverse()});
  }
  return fixed;
}

Eigen::Isometry3d toStackPose(const StackShape& shape, const Eigen::Isometry3d& lidar_pose) {
  const Eigen::Isometry3d axes = odometryAxes(shape);
  return axes * lidar_pose * axes.inverse();
}

Eigen::Isometry3d fromStackPose(const StackShape& shape, const Eigen::Isometry3d& stack_pose) {
  const Eigen::Isometry3d axes = odometryAxes(shape);
  return axes.inverse() * stack_pose * axes;
}

}  // namespace sim
}  // namespace scan_context_loop
