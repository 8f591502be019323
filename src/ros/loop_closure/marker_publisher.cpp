#include "loop_closure/marker_publisher.h"

#include "shared/stored_keyframe.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

void MarkerPublisher::advertise(const ros::NodeHandle& nh, const std::function<void()>& on_subscriber) {
  // Markers go out incrementally; a new subscriber (RViz opened late) gets every marker once.
  ros::NodeHandle handle(nh);
  pub_ = handle.advertise<visualization_msgs::MarkerArray>(
      topic_names::kLoopMarkers, 1, [on_subscriber](const ros::SingleSubscriberPublisher&) { on_subscriber(); },
      ros::SubscriberStatusCallback(), ros::VoidConstPtr(), true);
}

void MarkerPublisher::publish(const Database& database) {
  MarkerKeyframes keyframes;
  keyframes.count = database.size();
  keyframes.position = [&database](std::size_t k) { return keyframePosition(database.keyframe(k)); };
  keyframes.session = [&database](std::size_t k) { return database.keyframe(k).session; };
  const ros::Time stamp = keyframeStamp(database.keyframe(database.size() - 1).info);
  auto update = makeLoopMarkers(keyframes, loops_, rejected_, frame_, stamp, config_.distance_threshold, &shown_);
  if (update.markers.empty()) return;
  if (!robot_.empty()) {
    for (auto& marker : update.markers) marker.ns = robot_ + "/" + marker.ns;  // a team's markers apart in RViz
  }
  pub_.publish(update);
}

void MarkerPublisher::redraw(const Database& database) {
  if (database.size() == 0) return;
  shown_ = MarkerState();
  publish(database);
}

void MarkerPublisher::clear() {
  loops_.clear();
  rejected_.clear();
  shown_ = MarkerState();
  if (!listened()) return;
  visualization_msgs::MarkerArray clear;
  clear.markers.resize(1);
  clear.markers[0].action = visualization_msgs::Marker::DELETEALL;
  pub_.publish(clear);
}

}  // namespace scan_context_loop
