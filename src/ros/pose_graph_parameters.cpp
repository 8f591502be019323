#include "scan_context_loop/ros/pose_graph_parameters.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include <xmlrpcpp/XmlRpcValue.h>

#include "scan_context_loop/ros/frame_ids.h"
#include "scan_context_loop/ros/parameters.h"

namespace scan_context_loop {

namespace {

/// One key: how to take a value of the parameter server into its member. `take` returns false when the
/// value's type does not fit.
struct Key {
  std::string type_name;
  std::function<bool(XmlRpc::XmlRpcValue&)> take;
};

Key number(double* target) {
  return {"a number", [target](XmlRpc::XmlRpcValue& v) {
            if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) *target = static_cast<double>(v);
            else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) *target = static_cast<int>(v);
            else return false;
            return true;
          }};
}

Key integer(int* target) {
  return {"an integer", [target](XmlRpc::XmlRpcValue& v) {
            if (v.getType() != XmlRpc::XmlRpcValue::TypeInt) return false;
            *target = static_cast<int>(v);
            return true;
          }};
}

Key flag(bool* target) {
  return {"true or false", [target](XmlRpc::XmlRpcValue& v) {
            if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) return false;
            *target = static_cast<bool>(v);
            return true;
          }};
}

Key text(std::string* target) {
  return {"a string", [target](XmlRpc::XmlRpcValue& v) {
            if (v.getType() != XmlRpc::XmlRpcValue::TypeString) return false;
            *target = static_cast<std::string>(v);
            return true;
          }};
}

}  // namespace

std::vector<std::string> readPoseGraphParameters(const ros::NodeHandle& pnh, PoseGraphConfig* g,
                                                 KeyframeMapConfig* m, PoseGraphOptions* o) {
  const std::map<std::string, Key> keys = {
      {"odometry_translation_floor", number(&g->odometry_translation_floor)},
      {"odometry_translation_per_metre", number(&g->odometry_translation_per_metre)},
      {"odometry_rotation_floor", number(&g->odometry_rotation_floor)},
      {"odometry_rotation_per_metre", number(&g->odometry_rotation_per_metre)},
      {"loop_robust_scale", number(&g->loop_robust_scale)},
      {"max_iterations", integer(&g->max_iterations)},
      {"map_voxel", number(&m->voxel)},
      {"map_max_range", number(&m->max_range)},
      {"map_keyframe_stride", integer(&m->keyframe_stride)},
      {"map_frame", text(&o->map_frame)},
      {"publish_tf", flag(&o->publish_tf)},
      {"tf_rate", number(&o->tf_rate)},
      {"verified_only", flag(&o->verified_only)},
      {"stamp_tolerance", number(&o->stamp_tolerance)},
      {"min_solve_interval", number(&o->min_solve_interval)},
      {"map_period", number(&o->map_period)},
      {"queue_size", integer(&o->queue_size)},
      {"build_map", flag(&o->build_map)},
  };
  std::vector<std::string> problems;
  for (const auto& [key, reader] : keys) {
    XmlRpc::XmlRpcValue value;
    if (!pnh.getParam(key, value)) continue;  // the default stays
    if (!reader.take(value)) problems.push_back(key + ": expected " + reader.type_name + ", got " + value.toXml());
  }
  // A private parameter that is no key is a misspelling.
  for (const auto& key : unknownPrivateParameters(pnh, [&](const std::string& k) { return keys.count(k) > 0; })) {
    problems.push_back(key + ": unknown parameter (see doc/pose_graph.md)");
  }
  for (const auto& p : g->validate()) problems.push_back(p);
  for (const auto& p : m->validate()) problems.push_back(p);
  const auto check = [&](bool ok, const std::string& rule) {
    if (!ok) problems.push_back(rule);
  };
  o->map_frame = normaliseFrameId(o->map_frame);  // tf2's name: no leading '/'
  check(!o->map_frame.empty(), "map_frame must not be empty");
  check(o->tf_rate > 0.0 && o->tf_rate <= 1000.0, "tf_rate must be in (0, 1000] Hz");
  check(o->stamp_tolerance >= 0.0 && o->stamp_tolerance <= 1.0, "stamp_tolerance must be in [0, 1] s");
  check(o->min_solve_interval >= 0.0 && std::isfinite(o->min_solve_interval), "min_solve_interval must be >= 0 s");
  check(o->map_period >= 0.0 && std::isfinite(o->map_period), "map_period must be >= 0 s (0: on request only)");
  check(o->queue_size >= 1 && o->queue_size <= 1000000, "queue_size must be in [1, 1000000]");
  return problems;
}

}  // namespace scan_context_loop
