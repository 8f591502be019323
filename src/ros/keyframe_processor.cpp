#include "scan_context_loop/ros/keyframe_processor.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include <sys/resource.h>
#include <time.h>

#include "scan_context_loop/ros/cloud_input.h"
#include "scan_context_loop/ros/pose_input.h"
#include "scan_context_loop/ros/stored_keyframe.h"

namespace scan_context_loop {

namespace {

double wallNow() { return ros::WallTime::now().toSec(); }

// A fixed extrinsic comes from a static tf publisher started with the stack: latched on /tf_static, it
// arrives as soon as the listener connects; tf1's static_transform_publisher resends it every period
// (10 ms in LeGO-LOAM's launch). Keyframes wait for it at most this long [s] (and at most queue_size of
// them): processed with poses in the odometry's axes they would stay in the database with the wrong
// poses, so waiting a little loses nothing. After it, tf is looked at again every kExtrinsicRecheck s.
constexpr double kExtrinsicWait = 5.0;
constexpr double kExtrinsicRecheck = 1.0;

/// A keyframe longer than this on the worker [ms] brings a throttled warning saying where the time went
/// (at the 10 Hz of a LiDAR, a keyframe stream has 100 ms a scan; the node takes a few).
constexpr double kSlowKeyframeMs = 50.0;

/// The parts of LoopDetector::process that Detection times [ms].
double coreMs(const Detection& d) {
  return (d.descriptor_seconds + d.query_seconds + d.verify_seconds + d.ground_check_seconds + d.choose_seconds) *
         1e3;
}

/// The calling thread's CPU time [ms], involuntary context switches and page faults so far.
struct ThreadUsage {
  double cpu_ms = 0.0;
  long preemptions = 0, page_faults = 0;

  static ThreadUsage now() {
    ThreadUsage u;
    timespec cpu{};
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu) == 0) u.cpu_ms = cpu.tv_sec * 1e3 + cpu.tv_nsec * 1e-6;
    rusage r{};
    if (getrusage(RUSAGE_THREAD, &r) == 0) {
      u.preemptions = r.ru_nivcsw;
      u.page_faults = r.ru_minflt + r.ru_majflt;
    }
    return u;
  }
};

}  // namespace

KeyframeProcessor::KeyframeProcessor(const std::string& name, const Config& config, const RosOptions& options,
                                     NodeCounters* counters, LoopPublisher* loops, MarkerPublisher* markers,
                                     SelectedKeyframePublisher* selected)
    : name_(name),
      config_(config),
      options_(options),
      counters_(counters),
      loops_(loops),
      markers_(markers),
      selected_(selected),
      pipeline_(std::make_shared<KeyframePipeline>(config)) {}

KeyframeProcessor::~KeyframeProcessor() = default;

void KeyframeProcessor::useTf(const tf2_ros::Buffer& tf) {
  tf_ = &tf;
  if (options_.pose_source == "odom" && options_.sensor_extrinsic_from_tf) {
    extrinsic_.reset(new SensorExtrinsic(tf, name_, kExtrinsicWait, kExtrinsicRecheck));
  }
}

void KeyframeProcessor::resetPipeline() {
  pipeline_ = std::make_shared<KeyframePipeline>(config_);
  followCloudStore();
}

void KeyframeProcessor::followDatabase() {
  if (team_) team_->share(pipeline_->detector(), pipeline_, team_frame_);
  counters_->database_size = database().size();
  counters_->sessions = database().session() + 1;
  followCloudStore();
  markers_->forgetShown();  // redraw everything with the new keyframes
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

bool KeyframeProcessor::lookUpPose(QueuedKeyframe* keyframe) {
  // A registered cloud's frame is the fixed frame: the sensor's own frame must be named.
  const std::string& sensor = sensorFrame(*keyframe);
  try {
    const auto t = tf_->lookupTransform(options_.fixed_frame, sensor, keyframe->cloud->header.stamp,
                                        ros::Duration(options_.tf_timeout));
    std::string why;
    if (!poseFromMsg(t.transform, &keyframe->pose, &why)) {
      ++counters_->rejected;
      ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: the transform %s <- %s is unusable: %s",
                               keyframe->cloud->header.stamp.toSec(), options_.fixed_frame.c_str(), sensor.c_str(),
                               why.c_str());
      return false;
    }
    keyframe->has_pose = true;
    return true;
  } catch (const tf2::TransformException& e) {
    ++counters_->rejected;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "keyframe skipped: no transform %s <- %s at its stamp: %s",
                            options_.fixed_frame.c_str(), sensor.c_str(), e.what());
    return false;
  }
}

const std::string& KeyframeProcessor::sensorFrame(const QueuedKeyframe& keyframe) const {
  // A registered cloud's own frame is the world's: only a named sensor_frame, or the odometry's child,
  // says where the sensor is (in tf mode the cloud's frame, as lookUpPose takes it, when none is named).
  if (!options_.sensor_frame.empty()) return options_.sensor_frame;
  return config_.cloud_in_world_frame && !keyframe.child_frame.empty() ? keyframe.child_frame : keyframe.cloud_frame;
}

SensorExtrinsic::State KeyframeProcessor::resolveExtrinsic(const QueuedKeyframe& keyframe) {
  if (!extrinsic_ || keyframe.child_frame.empty()) return SensorExtrinsic::State::kKnown;  // none needed
  return extrinsic_->resolve(keyframe.child_frame, sensorFrame(keyframe), wallNow());
}

void KeyframeProcessor::applyExtrinsic(QueuedKeyframe* keyframe) {
  if (resolveExtrinsic(*keyframe) == SensorExtrinsic::State::kKnown && extrinsic_) {
    keyframe->pose = keyframe->pose * extrinsic_->pose();
  }
}

void KeyframeProcessor::process(QueuedKeyframe keyframe) {
  const auto started = std::chrono::steady_clock::now();
  const ThreadUsage usage_at_start = ThreadUsage::now();
  const sensor_msgs::PointCloud2& msg = *keyframe.cloud;
  if (!keyframe.has_pose && !lookUpPose(&keyframe)) return;
  applyExtrinsic(&keyframe);
  if (!keyframe.pose.matrix().allFinite()) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its pose is not finite", msg.header.stamp.toSec());
    return;
  }
  PointView view;
  std::string why;
  if (!viewCloud(msg, &view, &why)) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe cloud at %.3f skipped: %s", msg.header.stamp.toSec(), why.c_str());
    return;
  }
  KeyframeInfo info;
  setKeyframeStamp(msg.header.stamp, &info);  // the database keeps the ROS stamp exactly (stored_keyframe.h)
  info.pose = keyframe.pose;
  // Keyframe selection, registered clouds back to the sensor frame, the voxel filter: in the core. The
  // points as described are wanted only while someone subscribes to them.
  pcl::PointCloud<pcl::PointXYZ> described;
  const bool cloud_listened = selected_ && selected_->cloudListened();
  const bool want_cloud = cloud_listened || team_ != nullptr;
  const auto detect_start = std::chrono::steady_clock::now();
  const Detection detection = pipeline_->process(view, info, want_cloud ? &described : nullptr);
  const auto detect_end = std::chrono::steady_clock::now();
  if (!detection.selected) return;
  if (!detection.accepted) {
    ++counters_->rejected;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: %s", info.stamp, detection.error.c_str());
    return;
  }
  if (detection.points_used == 0) {
    ROS_WARN_THROTTLE_NAMED(5.0, name_,
                            "keyframe %zu at %.3f has no usable point (%zu NaN/Inf or out of range): kept as a "
                            "keyframe that never matches",
                            detection.index, info.stamp, detection.points_skipped);
  }
  reportWorldTilt(detection);
  std::chrono::steady_clock::duration publishing{0};
  auto publish_start = std::chrono::steady_clock::now();
  // Stored: the keyframe goes out before its loops, so a backend knows it when they come.
  if (selected_) {
    selected_->publish(msg.header.stamp, keyframe.pose_frame, sensorFrame(keyframe), keyframe.pose,
                       cloud_listened ? &described : nullptr);
  }
  const Database& database = pipeline_->detector().database();
  if (team_) shareWithTeam(detection.index, keyframe, std::move(described));
  publishing += std::chrono::steady_clock::now() - publish_start;
  if (detection.new_session) {
    const double previous = keyframeStamp(database.keyframe(detection.index - 1).info).toSec();
    ROS_WARN_NAMED(name_,
                   "keyframe stamp %.3f is %.1f s before the previous keyframe's (a bag played again, a restarted "
                   "odometry?): session %u starts; the %zu keyframes before it stay candidates",
                   info.stamp, previous - info.stamp, database.session(), database.sessionStart());
    counters_->sessions = database.session() + 1;
  }
  counters_->database_size = database.size();
  followCloudStore();
  counters_->database_bytes_per_keyframe = database.bytesPerKeyframe();
  counters_->last_query_ms = (detection.descriptor_seconds + detection.query_seconds) * 1e3;
  counters_->loops_waiting = pipeline_->detector().consistency().waiting();
  publish_start = std::chrono::steady_clock::now();
  loops_->publishLoops(detection, keyframe.pose_frame, database);
  markers_->setFrame(keyframe.pose_frame);
  if (markers_->listened()) markers_->publish(database);
  publishing += std::chrono::steady_clock::now() - publish_start;

  // The keyframe's whole time on the worker, markers included.
  const auto ms = [](std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  // The CPU time is read before the wall clock, as it was read after it at the start, so that the
  // CPU interval lies within the wall one (read after the timing message was built, it also counted
  // that, and came out above the wall time now and then).
  const ThreadUsage usage = ThreadUsage::now();
  const double processing_ms = ms(std::chrono::steady_clock::now() - started);
  counters_->last_keyframe_ms = processing_ms;
  if (processing_ms > counters_->max_keyframe_ms.load()) counters_->max_keyframe_ms = processing_ms;
  const double cpu_ms = usage.cpu_ms - usage_at_start.cpu_ms;
  const long preemptions = std::max(0L, usage.preemptions - usage_at_start.preemptions);
  const double detect_ms = ms(detect_end - detect_start), publish_ms = ms(publishing);
  if (processing_ms > kSlowKeyframeMs) {
    ROS_WARN_THROTTLE_NAMED(
        10.0, name_,
        "keyframe %zu took %.1f ms on the worker (%.1f ms of its CPU, preempted %ld times): describe %.1f, "
        "query and add %.1f, verify %.1f, ground check %.1f, choose loops %.1f, rest of the core %.1f, "
        "publishing %.1f, other %.1f ms",
        detection.index, processing_ms, cpu_ms, preemptions, detection.descriptor_seconds * 1e3,
        detection.query_seconds * 1e3, detection.verify_seconds * 1e3, detection.ground_check_seconds * 1e3,
        detection.choose_seconds * 1e3, detect_ms - coreMs(detection), publish_ms,
        processing_ms - detect_ms - publish_ms);
  }
  if (!loops_->timingListened()) return;
  scan_context_loop::KeyframeTiming timing;
  timing.header.stamp = msg.header.stamp;
  timing.header.frame_id = keyframe.pose_frame;
  timing.keyframe_id = static_cast<std::uint32_t>(detection.index);
  timing.database_size = static_cast<std::uint32_t>(counters_->database_size.load());
  timing.queue_ms = ms(started - keyframe.queued);
  timing.processing_ms = processing_ms;
  timing.describe_query_ms = (detection.descriptor_seconds + detection.query_seconds) * 1e3;
  timing.verify_ms = detection.verify_seconds * 1e3;
  timing.ground_check_ms = detection.ground_check_seconds * 1e3;
  timing.choose_ms = detection.choose_seconds * 1e3;
  timing.detect_ms = detect_ms;
  timing.publish_ms = publish_ms;
  timing.queue_length = static_cast<std::uint32_t>(keyframe.queue_length);
  timing.cpu_ms = cpu_ms;
  timing.preemptions = static_cast<std::uint32_t>(preemptions);
  timing.page_faults = static_cast<std::uint32_t>(std::max(0L, usage.page_faults - usage_at_start.page_faults));
  loops_->publishTiming(timing);
}

void KeyframeProcessor::shareWithTeam(std::size_t index, const QueuedKeyframe& queued,
                                      pcl::PointCloud<pcl::PointXYZ> described) {
  team_frame_ = queued.pose_frame;
  team_->share(pipeline_->detector(), pipeline_, team_frame_);
  const Keyframe& stored = database().keyframe(index);
  auto own = std::make_shared<OwnKeyframe>();
  own->index = static_cast<std::uint32_t>(index);
  own->session = stored.session;
  own->path_length = stored.path_length;
  own->stamp = keyframeStamp(stored.info);
  own->frame = queued.pose_frame;
  own->pose = queued.pose;
  own->described = std::move(described);
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
