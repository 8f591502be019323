#include "pose_graph/pose_graph_parameters.h"

#include <algorithm>

#include "shared/frame_ids.h"
#include "shared/parameters.h"

namespace scan_context_loop {

std::vector<std::string> readPoseGraphParameters(const ros::NodeHandle& pnh, PoseGraphConfig* g, KeyframeMapConfig* m,
                                                 PoseGraphOptions* o, std::vector<std::string>* warnings) {
  std::vector<std::string> problems;
  readTable(pnh, poseGraphSettings(), g, &problems, warnings);
  readTable(pnh, keyframeMapSettings(), m, &problems, warnings);
  // `robots` may be a YAML list of strings: read as the table's text (ids separated by spaces).
  std::vector<Setting<PoseGraphOptions>> node_table = poseGraphNodeSettings();
  XmlRpc::XmlRpcValue robots;
  if (pnh.getParam("robots", robots) && robots.getType() == XmlRpc::XmlRpcValue::TypeArray) {
    node_table.erase(std::remove_if(node_table.begin(), node_table.end(),
                                    [](const Setting<PoseGraphOptions>& s) { return s.key == "robots"; }),
                     node_table.end());
    std::string text;
    for (int i = 0; i < robots.size(); ++i) {
      if (robots[i].getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string>(robots[i]).empty() ||
          static_cast<std::string>(robots[i]).find(' ') != std::string::npos) {
        problems.push_back("robots: expected a list of robot ids, got " + robots.toXml());
        text.clear();
        break;
      }
      text += (text.empty() ? "" : " ") + static_cast<std::string>(robots[i]);
    }
    o->robots = text;
  }
  readTable(pnh, node_table, o, &problems, warnings);
  reportUnknownParameters(
      pnh, {knownKeyOf(poseGraphSettings()), knownKeyOf(keyframeMapSettings()), knownKeyOf(poseGraphNodeSettings())},
      "config/pose_graph.yaml", &problems);
  o->map_frame = normaliseFrameId(o->map_frame);  // tf2's name: no leading '/'
  for (const auto& p : g->validate()) problems.push_back(p);
  for (const auto& p : m->validate()) problems.push_back(p);
  for (const auto& p : checkSettings(poseGraphNodeSettings(), *o)) problems.push_back(p);
  return problems;
}

}  // namespace scan_context_loop
