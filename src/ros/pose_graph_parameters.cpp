#include "scan_context_loop/ros/pose_graph_parameters.h"

#include "scan_context_loop/ros/frame_ids.h"
#include "scan_context_loop/ros/parameters.h"

namespace scan_context_loop {

std::vector<std::string> readPoseGraphParameters(const ros::NodeHandle& pnh, PoseGraphConfig* g,
                                                 KeyframeMapConfig* m, PoseGraphOptions* o,
                                                 std::vector<std::string>* warnings) {
  std::vector<std::string> problems;
  readTable(pnh, poseGraphSettings(), g, &problems, warnings);
  readTable(pnh, keyframeMapSettings(), m, &problems, warnings);
  readTable(pnh, poseGraphNodeSettings(), o, &problems, warnings);
  reportUnknownParameters(pnh,
                          {knownKeyOf(poseGraphSettings()), knownKeyOf(keyframeMapSettings()),
                           knownKeyOf(poseGraphNodeSettings())},
                          "config/pose_graph.yaml", &problems);
  o->map_frame = normaliseFrameId(o->map_frame);  // tf2's name: no leading '/'
  for (const auto& p : g->validate()) problems.push_back(p);
  for (const auto& p : m->validate()) problems.push_back(p);
  for (const auto& p : checkSettings(poseGraphNodeSettings(), *o)) problems.push_back(p);
  return problems;
}

}  // namespace scan_context_loop
