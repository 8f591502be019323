#include "scan_context_loop/ros/parameters.h"

#include <cmath>

namespace scan_context_loop {

std::vector<std::string> readParameters(const ros::NodeHandle& pnh, Config* c, RosOptions* o) {
  pnh.param("num_rings", c->num_rings, c->num_rings);
  pnh.param("num_sectors", c->num_sectors, c->num_sectors);
  pnh.param("max_radius", c->max_radius, c->max_radius);
  pnh.param("min_range", c->min_range, c->min_range);
  pnh.param("lidar_height", c->lidar_height, c->lidar_height);
  std::string ring_key = ringKeyTypeName(c->ring_key);
  pnh.param("ring_key", ring_key, ring_key);
  std::string levelling = levellingModeName(c->levelling);
  pnh.param("levelling", levelling, levelling);
  pnh.param("levelling_max_tilt", c->levelling_max_tilt, c->levelling_max_tilt);
  pnh.param("num_candidates", c->num_candidates, c->num_candidates);
  pnh.param("search_ratio", c->search_ratio, c->search_ratio);
  pnh.param("distance_threshold", c->distance_threshold, c->distance_threshold);
  pnh.param("lateral_offset_step", c->lateral_offset_step, c->lateral_offset_step);
  pnh.param("lateral_offset_count", c->lateral_offset_count, c->lateral_offset_count);
  pnh.param("exclude_recent_frames", c->exclude_recent_frames, c->exclude_recent_frames);
  pnh.param("exclude_recent_seconds", c->exclude_recent_seconds, c->exclude_recent_seconds);
  pnh.param("exclude_recent_distance", c->exclude_recent_distance, c->exclude_recent_distance);
  pnh.param("gate_odometry_distance", c->gate_odometry_distance, c->gate_odometry_distance);
  pnh.param("gate_odometry_drift", c->gate_odometry_drift, c->gate_odometry_drift);
  pnh.param("verify", c->verify, c->verify);
  pnh.param("verify_threshold", c->verify_threshold, c->verify_threshold);
  pnh.param("verify_max_candidates", c->verify_max_candidates, c->verify_max_candidates);
  pnh.param("verify_max_bytes", c->verify_max_bytes, c->verify_max_bytes);
  pnh.param("verify_voxel_leaf", c->verify_voxel_leaf, c->verify_voxel_leaf);
  pnh.param("verify_max_range", c->verify_max_range, c->verify_max_range);
  pnh.param("verify_min_inlier_ratio", c->verify_min_inlier_ratio, c->verify_min_inlier_ratio);
  pnh.param("verify_supported_inlier_ratio", c->verify_supported_inlier_ratio, c->verify_supported_inlier_ratio);
  pnh.param("verify_max_fitness", c->verify_max_fitness, c->verify_max_fitness);
  pnh.param("verify_max_violation", c->verify_max_violation, c->verify_max_violation);
  pnh.param("verify_supported_max_violation", c->verify_supported_max_violation, c->verify_supported_max_violation);
  std::string verify_method = registrationMethodName(c->verify_method);
  pnh.param("verify_method", verify_method, verify_method);
  pnh.param("verify_odometry_rotation", c->verify_odometry_rotation, c->verify_odometry_rotation);
  pnh.param("verify_odometry_rotation_drift", c->verify_odometry_rotation_drift, c->verify_odometry_rotation_drift);
  pnh.param("verify_submap", c->verify_submap, c->verify_submap);
  pnh.param("verify_allow_degenerate", c->verify_allow_degenerate, c->verify_allow_degenerate);
  pnh.param("consistency_min_support", c->consistency_min_support, c->consistency_min_support);
  pnh.param("consistency_window", c->consistency_window, c->consistency_window);
  pnh.param("consistency_translation", c->consistency_translation, c->consistency_translation);
  pnh.param("consistency_rotation", c->consistency_rotation, c->consistency_rotation);
  pnh.param("consistency_drift", c->consistency_drift, c->consistency_drift);

  pnh.param("pose_source", o->pose_source, o->pose_source);
  pnh.param("fixed_frame", o->fixed_frame, o->fixed_frame);
  pnh.param("tf_timeout", o->tf_timeout, o->tf_timeout);
  pnh.param("sensor_frame", o->sensor_frame, o->sensor_frame);
  pnh.param("approximate_sync", o->approximate_sync, o->approximate_sync);
  pnh.param("sync_queue_size", o->sync_queue_size, o->sync_queue_size);
  pnh.param("cloud_in_world_frame", o->cloud_in_world_frame, o->cloud_in_world_frame);
  pnh.param("keyframe_min_distance", o->keyframe_min_distance, o->keyframe_min_distance);
  pnh.param("keyframe_min_angle", o->keyframe_min_angle, o->keyframe_min_angle);
  pnh.param("voxel_leaf", o->voxel_leaf, o->voxel_leaf);
  pnh.param("queue_size", o->queue_size, o->queue_size);
  pnh.param("lio_sam_output", o->lio_sam_output, o->lio_sam_output);
  pnh.param("unsynchronised_warning", o->unsynchronised_warning, o->unsynchronised_warning);
  pnh.param("covariance_translation", o->covariance_translation, o->covariance_translation);
  pnh.param("covariance_rotation", o->covariance_rotation, o->covariance_rotation);

  std::vector<std::string> problems;
  if (!parseRingKeyType(ring_key, &c->ring_key)) {
    problems.push_back("ring_key = " + ring_key + ": must be mean_height or occupancy");
  }
  if (!parseLevellingMode(levelling, &c->levelling)) {
    problems.push_back("levelling = " + levelling + ": must be auto, pose, ground or off");
  }
  if (!parseRegistrationMethod(verify_method, &c->verify_method)) {
    problems.push_back("verify_method = " + verify_method + ": must be vgicp, gicp, icp or ndt");
  }
  for (const auto& p : c->validate()) problems.push_back(p);
  const auto check = [&](bool ok, const std::string& text) {
    if (!ok) problems.push_back(text);
  };
  check(o->pose_source == "odom" || o->pose_source == "tf", "pose_source = " + o->pose_source + ": must be odom or tf");
  check(!o->fixed_frame.empty() || o->pose_source != "tf", "fixed_frame must be set when pose_source is tf");
  check(std::isfinite(o->tf_timeout) && o->tf_timeout >= 0.0, "tf_timeout must be >= 0 seconds");
  check(!(o->pose_source == "tf" && o->cloud_in_world_frame && o->sensor_frame.empty()),
        "sensor_frame must name the sensor's tf frame when pose_source is tf and cloud_in_world_frame is true");
  check(o->sync_queue_size >= 1 && o->sync_queue_size <= 10000, "sync_queue_size must be in [1, 10000]");
  check(std::isfinite(o->keyframe_min_distance) && o->keyframe_min_distance >= 0.0, "keyframe_min_distance must be >= 0");
  check(std::isfinite(o->keyframe_min_angle) && o->keyframe_min_angle >= 0.0, "keyframe_min_angle must be >= 0");
  check(std::isfinite(o->voxel_leaf) && o->voxel_leaf >= 0.0, "voxel_leaf must be >= 0 (0 disables)");
  check(o->queue_size >= 1 && o->queue_size <= 100000, "queue_size must be in [1, 100000]");
  check(std::isfinite(o->unsynchronised_warning) && o->unsynchronised_warning > 0.0, "unsynchronised_warning must be > 0");
  check(std::isfinite(o->covariance_translation) && o->covariance_translation > 0.0, "covariance_translation must be > 0");
  check(std::isfinite(o->covariance_rotation) && o->covariance_rotation > 0.0, "covariance_rotation must be > 0");
  return problems;
}

}  // namespace scan_context_loop
