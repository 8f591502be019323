#include "loop_closure/keyframe_processor.h"

#include <utility>

#include <ros/console.h>

#include "shared/cloud_input.h"
#include "shared/stored_keyframe.h"

namespace scan_context_loop {

KeyframeProcessor::KeyframeProcessor(const std::string& name, const Config& config, const NodeOptions& options,
                                     NodeCounters* counters)
    : name_(name),
      config_(config),
      options_(options),
      counters_(counters),
      pipeline_(std::make_shared<KeyframePipeline>(config)) {}

KeyframeProcessor::~KeyframeProcessor() = default;

void KeyframeProcessor::resetPipeline() {
  pipeline_ = std::make_shared<KeyframePipeline>(config_);
  followCloudStore();
}

void KeyframeProcessor::followDatabase() {
  if (team_) team_->share(pipeline_->detector(), pipeline_, team_frame_);
  counters_->database_size = database().size();
  counters_->sessions = database().session() + 1;
  followCloudStore();
}

void KeyframeProcessor::followCloudStore() {
  const CloudStore& store = pipeline_->detector().cloudStore();
  counters_->registration_bytes = store.bytes();
  counters_->registration_memory = store.memoryBytes();
  if (!config_.verification.enabled) return;
  const std::size_t keyframes = database().size();
  counters_->keyframes_without_registration = keyframes > store.stored() ? keyframes - store.stored() : 0;
  // A halving happens at most a few dozen times in a run: each one is worth a warning of its own.
  const std::string warning = cloudStoreHalvingWarning(counters_->registration_stride, store, keyframes);
  if (!warning.empty()) ROS_WARN_NAMED(name_, "%s", warning.c_str());
  counters_->registration_stride = store.stride();
}

KeyframeResult KeyframeProcessor::process(const PosedKeyframe& keyframe, bool want_cloud, KeyframeClock* clock) {
  KeyframeResult result;
  const sensor_msgs::PointCloud2& msg = *keyframe.queued.cloud;
  PointView view;
  std::string why;
  if (!viewCloud(msg, &view, &why)) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe cloud at %.3f skipped: %s", msg.header.stamp.toSec(), why.c_str());
    return result;
  }
  KeyframeInfo info;
  setKeyframeStamp(msg.header.stamp, &info);  // the database keeps the ROS stamp exactly (stored_keyframe.h)
  info.pose = keyframe.queued.pose;
  // Keyframe selection, registered clouds back to the sensor frame, the voxel filter: in the core. The
  // points as described are wanted only while someone subscribes to them, or by a team.
  clock->detecting();
  result.detection = pipeline_->process(view, info, want_cloud || team_ ? &result.described : nullptr);
  clock->detected();
  const Detection& detection = result.detection;
  if (!detection.selected) return result;
  if (!detection.accepted) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: %s", info.stamp, detection.error.c_str());
    return result;
  }
  if (detection.points_used == 0) {
    ROS_WARN_THROTTLE_NAMED(5.0, name_,
                            "keyframe %zu at %.3f has no usable point (%zu NaN/Inf or out of range): kept as a "
                            "keyframe that never matches",
                            detection.index, info.stamp, detection.points_skipped);
  }
  reportWorldTilt(detection);
  countStored(detection, info.stamp);
  result.stored = true;
  return result;
}

void KeyframeProcessor::countStored(const Detection& detection, double stamp) {
  const Database& database = pipeline_->detector().database();
  if (detection.new_session) {
    const double previous = keyframeStamp(database.keyframe(detection.index - 1).info).toSec();
    ROS_WARN_NAMED(name_,
                   "keyframe stamp %.3f is %.1f s before the previous keyframe's (a bag played again, a restarted "
                   "odometry?): session %u starts; the %zu keyframes before it stay candidates",
                   stamp, previous - stamp, database.session(), database.sessionStart());
    counters_->sessions = database.session() + 1;
  }
  counters_->database_size = database.size();
  followCloudStore();
  counters_->database_bytes_per_keyframe = database.bytesPerKeyframe();
  counters_->last_query_ms = (detection.descriptor_seconds + detection.query_seconds) * 1e3;
  counters_->loops_waiting = pipeline_->detector().consistency().waiting();
}

void KeyframeProcessor::shareWithTeam(const PosedKeyframe& keyframe, KeyframeResult* result) {
  if (!team_) return;
  const std::size_t index = result->detection.index;
  team_frame_ = keyframe.queued.pose_frame;
  team_->share(pipeline_->detector(), pipeline_, team_frame_);
  const Keyframe& stored = database().keyframe(index);
  auto own = std::make_shared<OwnKeyframe>();
  own->index = static_cast<std::uint32_t>(index);
  own->session = stored.session;
  own->path_length = stored.path_length;
  own->stamp = keyframeStamp(stored.info);
  own->frame = keyframe.queued.pose_frame;
  own->pose = keyframe.queued.pose;
  own->described = std::move(result->described);
  team_->match(std::move(own));
}

void KeyframeProcessor::reportWorldTilt(const Detection& detection) {
  if (detection.world_tilt_deg < LoopDetector::kGravitySuspectDeg) return;
  ROS_WARN_THROTTLE_NAMED(
      300.0, name_,
      "gravity alignment: the odometry's world frame is %.1f deg off gravity (from %zu ground fits; A-LOAM "
      "and FAST-LIO start it at the first scan's frame, tilted as the sensor was): keyframes are "
      "gravity-aligned by that attitude, the same within this session; a database saved now does not "
      "match a session started at another tilt (doc/odometry_checks.md)",
      detection.world_tilt_deg, pipeline_->detector().worldTilt().fits());
}

}  // namespace scan_context_loop
