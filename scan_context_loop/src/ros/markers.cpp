#include "scan_context_loop/ros/markers.h"

#include <algorithm>
#include <cstdio>

namespace scan_context_loop {

namespace {

geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point q;
  q.x = p.x();
  q.y = p.y();
  q.z = p.z();
  return q;
}

std_msgs::ColorRGBA colour(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker base(const std::string& frame, const ros::Time& stamp, const std::string& ns, int id,
                                int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray makeLoopMarkers(const std::vector<Eigen::Vector3d>& positions,
                                                const std::vector<LoopEdge>& loops,
                                                const std::vector<LoopEdge>& rejected, const std::string& frame,
                                                const ros::Time& stamp, double threshold) {
  visualization_msgs::MarkerArray array;
  auto keyframes = base(frame, stamp, "keyframes", 0, visualization_msgs::Marker::SPHERE_LIST);
  keyframes.scale.x = keyframes.scale.y = keyframes.scale.z = 0.6;
  keyframes.color = colour(0.2f, 0.5f, 1.0f);
  auto trajectory = base(frame, stamp, "trajectory", 0, visualization_msgs::Marker::LINE_STRIP);
  trajectory.scale.x = 0.25;
  trajectory.color = colour(0.8f, 0.8f, 0.8f);
  for (const auto& p : positions) {
    keyframes.points.push_back(point(p));
    trajectory.points.push_back(point(p));
  }
  array.markers.push_back(keyframes);
  if (trajectory.points.size() >= 2) array.markers.push_back(trajectory);

  auto edges = base(frame, stamp, "loops", 0, visualization_msgs::Marker::LINE_LIST);
  edges.scale.x = 0.8;
  edges.color = colour(0.0f, 1.0f, 0.0f);
  // Both ends of every loop, large enough to see a revisit on a city-scale map from above.
  auto ends = base(frame, stamp, "loop_ends", 0, visualization_msgs::Marker::SPHERE_LIST);
  ends.scale.x = ends.scale.y = ends.scale.z = 2.5;
  ends.color = colour(0.0f, 1.0f, 0.0f);
  int label_id = 0;
  for (const auto& loop : loops) {
    if (loop.query >= positions.size() || loop.match >= positions.size()) continue;
    const float t = static_cast<float>(std::min(1.0, std::max(0.0, loop.distance / threshold)));
    const auto c = colour(t, 1.0f - t, 0.0f);
    for (std::size_t end : {loop.query, loop.match}) {
      edges.points.push_back(point(positions[end]));
      edges.colors.push_back(c);
      ends.points.push_back(point(positions[end]));
      ends.colors.push_back(c);
    }
    auto label = base(frame, stamp, "labels", label_id++, visualization_msgs::Marker::TEXT_VIEW_FACING);
    label.pose.position = point(positions[loop.query] + Eigen::Vector3d(0.0, 0.0, 3.5));
    label.scale.z = 1.5;
    label.color = colour(1.0f, 1.0f, 1.0f);
    char text[64];
    std::snprintf(text, sizeof text, "%zu -> %zu (%.2f)", loop.query, loop.match, loop.distance);
    label.text = text;
    array.markers.push_back(label);
  }
  if (!edges.points.empty()) {
    array.markers.push_back(edges);
    array.markers.push_back(ends);
  }
  auto turned_down = base(frame, stamp, "rejected", 0, visualization_msgs::Marker::LINE_LIST);
  turned_down.scale.x = 0.15;
  turned_down.color = colour(0.6f, 0.6f, 0.6f, 0.25f);
  for (const auto& r : rejected) {
    if (r.query >= positions.size() || r.match >= positions.size()) continue;
    turned_down.points.push_back(point(positions[r.query]));
    turned_down.points.push_back(point(positions[r.match]));
  }
  if (!turned_down.points.empty()) array.markers.push_back(turned_down);
  return array;
}

}  // namespace scan_context_loop
