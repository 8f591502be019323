#include "loop_closure/markers.h"

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

/// Keyframes of session s: blue for the first, then orange, green, purple, ... (repeating).
std_msgs::ColorRGBA sessionColour(std::uint32_t s) {
  static const float palette[][3] = {{0.2f, 0.5f, 1.0f}, {1.0f, 0.6f, 0.1f}, {0.3f, 0.8f, 0.3f},
                                     {0.7f, 0.4f, 0.9f}, {0.1f, 0.8f, 0.8f}, {0.9f, 0.9f, 0.2f}};
  const auto& p = palette[s % (sizeof(palette) / sizeof(palette[0]))];
  return colour(p[0], p[1], p[2]);
}

/// The first chunk that changed when `published` items of a list were already out: the chunk of the
/// last published item (it may have grown, and a strip's chunk ends on the next chunk's first point).
std::size_t firstChangedChunk(std::size_t published) { return published == 0 ? 0 : (published - 1) / kMarkerChunk; }

void addKeyframeChunk(const MarkerKeyframes& drawn, std::size_t chunk, const std::string& frame, const ros::Time& stamp,
                      visualization_msgs::MarkerArray* array) {
  const auto& session = drawn.session;
  const std::size_t count = drawn.count;
  const std::size_t begin = chunk * kMarkerChunk, end = std::min(count, begin + kMarkerChunk);
  auto keyframes = base(frame, stamp, "keyframes", static_cast<int>(chunk), visualization_msgs::Marker::SPHERE_LIST);
  keyframes.scale.x = keyframes.scale.y = keyframes.scale.z = 0.6;
  keyframes.color = sessionColour(0);
  auto trajectory = base(frame, stamp, "trajectory", static_cast<int>(chunk), visualization_msgs::Marker::LINE_LIST);
  trajectory.scale.x = 0.25;
  trajectory.color = colour(0.8f, 0.8f, 0.8f);
  for (std::size_t k = begin; k < end; ++k) {
    const Eigen::Vector3d position = drawn.position(k);
    keyframes.points.push_back(point(position));
    keyframes.colors.push_back(sessionColour(session(k)));
    // Each keyframe joins the next one of its session, the next chunk's first one too, so chunks join.
    if (k + 1 < count && session(k + 1) == session(k)) {
      trajectory.points.push_back(point(position));
      trajectory.points.push_back(point(drawn.position(k + 1)));
    }
  }
  array->markers.push_back(keyframes);
  if (trajectory.points.size() >= 2) array->markers.push_back(trajectory);
}

void addLoop(const MarkerKeyframes& keyframes, const LoopEdge& loop, std::size_t index, const std::string& frame,
             const ros::Time& stamp, double threshold, visualization_msgs::MarkerArray* array) {
  const int id = static_cast<int>(index);
  const float t = static_cast<float>(std::min(1.0, std::max(0.0, loop.distance / threshold)));
  const auto c = colour(t, 1.0f - t, 0.0f);
  auto edge = base(frame, stamp, "loops", id, visualization_msgs::Marker::LINE_LIST);
  edge.scale.x = 0.8;
  edge.color = c;
  // Both ends, large enough to see a revisit on a city-scale map from above.
  auto ends = base(frame, stamp, "loop_ends", id, visualization_msgs::Marker::SPHERE_LIST);
  ends.scale.x = ends.scale.y = ends.scale.z = 2.5;
  ends.color = c;
  for (std::size_t end : {loop.query, loop.match}) {
    const geometry_msgs::Point p = point(keyframes.position(end));
    edge.points.push_back(p);
    ends.points.push_back(p);
  }
  auto label = base(frame, stamp, "labels", id, visualization_msgs::Marker::TEXT_VIEW_FACING);
  label.pose.position = point(keyframes.position(loop.query) + Eigen::Vector3d(0.0, 0.0, 3.5));
  label.scale.z = 1.5;
  label.color = colour(1.0f, 1.0f, 1.0f);
  char text[64];
  std::snprintf(text, sizeof text, "%zu -> %zu (%.2f)", loop.query, loop.match, loop.distance);
  label.text = text;
  array->markers.push_back(edge);
  array->markers.push_back(ends);
  array->markers.push_back(label);
}

void addRejectedChunk(const MarkerKeyframes& keyframes, const std::vector<LoopEdge>& rejected, std::size_t chunk,
                      const std::string& frame, const ros::Time& stamp, visualization_msgs::MarkerArray* array) {
  auto lines = base(frame, stamp, "rejected", static_cast<int>(chunk), visualization_msgs::Marker::LINE_LIST);
  lines.scale.x = 0.15;
  lines.color = colour(0.6f, 0.6f, 0.6f, 0.25f);
  const std::size_t begin = chunk * kMarkerChunk, end = std::min(rejected.size(), begin + kMarkerChunk);
  for (std::size_t i = begin; i < end; ++i) {
    if (rejected[i].query >= keyframes.count || rejected[i].match >= keyframes.count) continue;
    lines.points.push_back(point(keyframes.position(rejected[i].query)));
    lines.points.push_back(point(keyframes.position(rejected[i].match)));
  }
  if (!lines.points.empty()) array->markers.push_back(lines);
}

}  // namespace

visualization_msgs::MarkerArray makeLoopMarkers(const std::vector<Eigen::Vector3d>& positions,
                                                const std::vector<std::uint32_t>& sessions,
                                                const std::vector<LoopEdge>& loops,
                                                const std::vector<LoopEdge>& rejected, const std::string& frame,
                                                const ros::Time& stamp, double threshold, MarkerState* published) {
  MarkerKeyframes keyframes;
  keyframes.count = positions.size();
  keyframes.position = [&positions](std::size_t k) { return positions[k]; };
  keyframes.session = [&sessions](std::size_t k) { return k < sessions.size() ? sessions[k] : 0u; };
  return makeLoopMarkers(keyframes, loops, rejected, frame, stamp, threshold, published);
}

visualization_msgs::MarkerArray makeLoopMarkers(const MarkerKeyframes& keyframes, const std::vector<LoopEdge>& loops,
                                                const std::vector<LoopEdge>& rejected, const std::string& frame,
                                                const ros::Time& stamp, double threshold, MarkerState* published) {
  MarkerState none;
  MarkerState& since = published != nullptr ? *published : none;
  visualization_msgs::MarkerArray array;
  if (keyframes.count > since.keyframes) {
    const std::size_t last = (keyframes.count - 1) / kMarkerChunk;
    for (std::size_t c = firstChangedChunk(since.keyframes); c <= last; ++c) {
      addKeyframeChunk(keyframes, c, frame, stamp, &array);
    }
  }
  for (std::size_t i = since.loops; i < loops.size(); ++i) {
    if (loops[i].query >= keyframes.count || loops[i].match >= keyframes.count) continue;
    addLoop(keyframes, loops[i], i, frame, stamp, threshold, &array);
  }
  if (rejected.size() > since.rejected) {
    const std::size_t last = (rejected.size() - 1) / kMarkerChunk;
    for (std::size_t c = firstChangedChunk(since.rejected); c <= last; ++c) {
      addRejectedChunk(keyframes, rejected, c, frame, stamp, &array);
    }
  }
  since.keyframes = keyframes.count;
  since.loops = loops.size();
  since.rejected = rejected.size();
  return array;
}

}  // namespace scan_context_loop
