#include "loop_closure/keyframe_input.h"

#include <algorithm>
#include <utility>

#include "shared/frame_ids.h"
#include "shared/pose_input.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

namespace {

double wallNow() { return ros::WallTime::now().toSec(); }

}  // namespace

KeyframeInput::KeyframeInput(const ros::NodeHandle& nh, const std::string& name, const NodeOptions& options,
                             KeyframeQueue* queue, NodeCounters* counters)
    : nh_(nh), name_(name), options_(options), queue_(queue), counters_(counters) {}

void KeyframeInput::start() {
  start_wall_ = wallNow();
  if (options_.pose_source == PoseSource::kTf) {
    cloud_only_sub_ =
        nh_.subscribe(topic_names::kKeyframeCloud, options_.sync_queue_size, &KeyframeInput::onCloudOnly, this);
  } else {
    cloud_sub_.subscribe(nh_, topic_names::kKeyframeCloud, options_.sync_queue_size);
    odom_sub_.subscribe(nh_, topic_names::kKeyframeOdom, options_.sync_queue_size);
    cloud_sub_.registerCallback(&KeyframeInput::onAnyCloud, this);
    odom_sub_.registerCallback(&KeyframeInput::onAnyOdom, this);
    if (options_.approximate_sync) {
      approx_sync_.reset(new message_filters::Synchronizer<ApproxPolicy>(ApproxPolicy(options_.sync_queue_size),
                                                                         cloud_sub_, odom_sub_));
      approx_sync_->registerCallback(&KeyframeInput::onCloudAndOdom, this);
    } else {
      exact_sync_.reset(
          new message_filters::Synchronizer<ExactPolicy>(ExactPolicy(options_.sync_queue_size), cloud_sub_, odom_sub_));
      exact_sync_->registerCallback(&KeyframeInput::onCloudAndOdom, this);
    }
    sync_timer_ = nh_.createWallTimer(ros::WallDuration(1.0), &KeyframeInput::checkSynchronisation, this);
  }
  input_timer_ = nh_.createWallTimer(ros::WallDuration(1.0), &KeyframeInput::checkInputs, this);
}

void KeyframeInput::stop() {
  cloud_sub_.unsubscribe();
  odom_sub_.unsubscribe();
  cloud_only_sub_.shutdown();
  sync_timer_.stop();
  input_timer_.stop();
}

std::string KeyframeInput::cloudTopic() const {
  return cloud_only_sub_ ? cloud_only_sub_.getTopic() : cloud_sub_.getTopic();
}

std::string KeyframeInput::poseSource() const {
  return options_.pose_source == PoseSource::kTf ? "tf (" + options_.fixed_frame + ")" : odom_sub_.getTopic();
}

// ---- callbacks: copy the message pointers into the queue and return ----------------------------

void KeyframeInput::onAnyCloud(const sensor_msgs::PointCloud2ConstPtr&) {
  ++counters_->clouds_received;
  const double now = wallNow();
  counters_->last_cloud_wall = now;
  if (counters_->first_unpaired_wall.load() == 0.0) counters_->first_unpaired_wall = now;
}

void KeyframeInput::onAnyOdom(const nav_msgs::OdometryConstPtr&) { counters_->last_odom_wall = wallNow(); }

void KeyframeInput::onCloudAndOdom(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                   const nav_msgs::OdometryConstPtr& odom) {
  ++counters_->clouds_paired;
  counters_->last_pair_wall = wallNow();
  counters_->first_unpaired_wall = 0.0;
  QueuedKeyframe keyframe;
  std::string why;
  if (!poseFromMsg(odom->pose.pose, &keyframe.pose, &why)) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its odometry pose is unusable: %s",
                             cloud->header.stamp.toSec(), why.c_str());
    return;
  }
  keyframe.cloud = cloud;
  keyframe.has_pose = true;
  keyframe.pose_frame = normaliseFrameId(odom->header.frame_id);
  keyframe.child_frame = normaliseFrameId(odom->child_frame_id);
  keyframe.cloud_frame = normaliseFrameId(cloud->header.frame_id);
  enqueue(std::move(keyframe));
}

void KeyframeInput::onCloudOnly(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  ++counters_->clouds_received;
  ++counters_->clouds_paired;
  counters_->last_cloud_wall = wallNow();
  QueuedKeyframe keyframe;
  keyframe.cloud = cloud;
  keyframe.pose_frame = options_.fixed_frame;
  keyframe.cloud_frame = normaliseFrameId(cloud->header.frame_id);
  enqueue(std::move(keyframe));
}

void KeyframeInput::enqueue(QueuedKeyframe keyframe) {
  keyframe.queued = std::chrono::steady_clock::now();
  if (queue_->push(std::move(keyframe))) return;
  ++counters_->dropped;
  ROS_WARN_THROTTLE_NAMED(5.0, name_, "worker queue full (%d keyframes): dropped %zu keyframes so far",
                          options_.queue_size, counters_->dropped.load());
}

// ---- input checks (wall timers) -----------------------------------------------------------------

void KeyframeInput::checkSynchronisation(const ros::WallTimerEvent&) {
  const double now = wallNow();
  const double since = counters_->first_unpaired_wall.load();
  if (since > 0.0 && now - since > options_.unsynchronised_warning && now - counters_->last_cloud_wall.load() < 2.0) {
    ROS_WARN_THROTTLE_NAMED(10.0, name_,
                            "clouds on %s have found no matching pose on %s for %.0f s: are both published, "
                            "with matching stamps (approximate_sync: %s)?",
                            cloud_sub_.getTopic().c_str(), odom_sub_.getTopic().c_str(), now - since,
                            options_.approximate_sync ? "true" : "false");
  }
}

void KeyframeInput::checkInputs(const ros::WallTimerEvent&) {
  // Repeated every no_input_warning seconds while it lasts.
  const double now = wallNow(), after = options_.no_input_warning, every = after;
  const double since_cloud = now - std::max(start_wall_, counters_->last_cloud_wall.load());
  if (since_cloud >= after) {
    const bool tf = options_.pose_source == PoseSource::kTf;
    const std::string topic = tf ? cloud_only_sub_.getTopic() : cloud_sub_.getTopic();
    const std::uint32_t publishers =
        tf ? cloud_only_sub_.getNumPublishers() : cloud_sub_.getSubscriber().getNumPublishers();
    const std::string poses = tf ? " (poses come from tf, in " + options_.fixed_frame + ", at each cloud's stamp)" : "";
    ROS_WARN_THROTTLE_NAMED(every, name_, "no keyframe cloud on %s for %.0f s (%u publishers)%s", topic.c_str(),
                            since_cloud, publishers, poses.c_str());
  }
  if (options_.pose_source != PoseSource::kOdom) return;
  const double since_odom = now - std::max(start_wall_, counters_->last_odom_wall.load());
  if (since_odom >= after) {
    ROS_WARN_THROTTLE_NAMED(every, name_, "no keyframe odometry on %s for %.0f s (%u publishers)",
                            odom_sub_.getTopic().c_str(), since_odom, odom_sub_.getSubscriber().getNumPublishers());
  }
}

}  // namespace scan_context_loop
