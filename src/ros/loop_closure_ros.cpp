#include "scan_context_loop/ros/loop_closure_ros.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>

#include <pthread.h>
#include <sys/resource.h>
#include <time.h>

#include <std_msgs/Float64MultiArray.h>
#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_loop/LoopClosure.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/ros/cloud_input.h"
#include "scan_context_loop/ros/exception_barrier.h"
#include "scan_context_loop/ros/frame_ids.h"
#include "scan_context_loop/ros/heap_statistics.h"
#include "scan_context_loop/ros/live_settings.h"
#include "scan_context_loop/ros/loop_pair.h"
#include "scan_context_loop/ros/markers.h"
#include "scan_context_loop/ros/pose_input.h"

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

}  // namespace

LoopClosureRos::LoopClosureRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name)
    : nh_(nh), pnh_(pnh), name_(name) {}

LoopClosureRos::~LoopClosureRos() {
  // Stop the services (a call in progress completes, the worker still runs) and the inputs first so
  // nothing new is queued, then let the worker finish the keyframe in hand.
  for (auto* service : {&save_srv_, &load_srv_, &reset_srv_, &relocalize_srv_}) service->shutdown();
  cloud_sub_.unsubscribe();
  odom_sub_.unsubscribe();
  cloud_only_sub_.shutdown();
  sync_timer_.stop();
  input_timer_.stop();
  diagnostics_timer_.stop();
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    stop_ = true;
  }
  queue_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
  // Callbacks that lock queue_mutex_ (a new marker subscriber, a live reconfigure) end here, while the
  // mutex lives: declared after them, it is destroyed before them.
  marker_pub_.shutdown();
  reconfigure_server_.reset();
  if (pipeline_ && !options_.database_save.empty() && options_.mode != "relocalize") {
    SaveOptions save;
    save.include_clouds = options_.database_save_clouds;
    std::string error;
    if (saveDatabase(pipeline_->detector(), options_.database_save, save, &error)) {
      ROS_INFO_NAMED(name_, "database saved to %s (%zu keyframes)", options_.database_save.c_str(),
                     pipeline_->detector().database().size());
    } else {
      ROS_ERROR_NAMED(name_, "database not saved: %s", error.c_str());
    }
  }
}

bool LoopClosureRos::start() {
  std::vector<std::string> warnings;
  const auto problems = readParameters(pnh_, &config_, &options_, &warnings);
  for (const auto& w : warnings) ROS_WARN_NAMED(name_, "parameter: %s", w.c_str());
  if (!problems.empty()) {
    for (const auto& p : problems) ROS_FATAL_NAMED(name_, "invalid parameter: %s", p.c_str());
    ROS_FATAL_NAMED(name_, "not starting: fix the parameters above (see config/default.yaml)");
    return false;
  }
  normaliseFrameIds(&options_);  // tf1's "/odom" is tf2's "odom", in lookups and in what is published
  if (options_.mode == "relocalize") config_.prior_sessions_only = true;  // the map alone is searched
  pipeline_.reset(new KeyframePipeline(config_));
  if (!options_.database_load.empty()) {
    const std::string error = loadFile(options_.database_load);
    if (!error.empty()) ROS_ERROR_NAMED(name_, "database_load %s: %s", options_.database_load.c_str(), error.c_str());
  }
  if (options_.mode == "relocalize" && pipeline_->detector().database().size() == 0) {
    ROS_WARN_NAMED(name_, "mode relocalize without a map: nothing is published until ~load_database loads one");
  }

  loop_pub_ = nh_.advertise<scan_context_loop::LoopClosure>("loop_closures", 100);
  if (config_.verification.enabled) rejected_pub_ = nh_.advertise<scan_context_loop::LoopClosure>("loop_candidates_rejected", 100);
  // Markers go out incrementally; a new subscriber (RViz opened late) gets every marker once.
  marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>(
      "loop_markers", 1,
      [this](const ros::SingleSubscriberPublisher&) {
        {
          std::lock_guard<std::mutex> lock(queue_mutex_);
          redraw_markers_ = true;
        }
        queue_cv_.notify_all();
      },
      ros::SubscriberStatusCallback(), ros::VoidConstPtr(), true);
  if (options_.lio_sam_output) lio_pub_ = nh_.advertise<std_msgs::Float64MultiArray>("lio_loop", 100);
  pair_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("loop_closure_pairs", 200);
  array_pub_ = nh_.advertise<std_msgs::Float64MultiArray>("loop_closure_array", 100);
  timing_pub_ = nh_.advertise<scan_context_loop::KeyframeTiming>("keyframe_timing", 100);
  advertiseSessionServices();

  // The live settings: dynamic_reconfigure starts from the parameters just read (its first call
  // changes nothing) and calls back from the spinner thread.
  live_config_ = config_;
  live_options_ = options_;
  reconfigure_server_.reset(
      new dynamic_reconfigure::Server<scan_context_loop::LoopClosureConfig>(reconfigure_mutex_, pnh_));
  reconfigure_server_->setCallback(
      [this](scan_context_loop::LoopClosureConfig& values, std::uint32_t level) { onReconfigure(values, level); });

  if (options_.pose_source == "tf" || options_.sensor_extrinsic_from_tf) {
    tf_buffer_.reset(new tf2_ros::Buffer(ros::Duration(30.0)));
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh_));
  }
  if (options_.pose_source == "odom" && options_.sensor_extrinsic_from_tf) {
    extrinsic_.reset(new SensorExtrinsic(*tf_buffer_, name_, kExtrinsicWait, kExtrinsicRecheck));
  }
  start_wall_ = wallNow();
  if (options_.pose_source == "tf") {
    cloud_only_sub_ = nh_.subscribe("keyframe_cloud", options_.sync_queue_size, &LoopClosureRos::onCloudOnly, this);
  } else {
    cloud_sub_.subscribe(nh_, "keyframe_cloud", options_.sync_queue_size);
    odom_sub_.subscribe(nh_, "keyframe_odom", options_.sync_queue_size);
    cloud_sub_.registerCallback(&LoopClosureRos::onAnyCloud, this);
    odom_sub_.registerCallback(&LoopClosureRos::onAnyOdom, this);
    if (options_.approximate_sync) {
      approx_sync_.reset(new message_filters::Synchronizer<ApproxPolicy>(ApproxPolicy(options_.sync_queue_size),
                                                                         cloud_sub_, odom_sub_));
      approx_sync_->registerCallback(&LoopClosureRos::onCloudAndOdom, this);
    } else {
      exact_sync_.reset(new message_filters::Synchronizer<ExactPolicy>(ExactPolicy(options_.sync_queue_size),
                                                                       cloud_sub_, odom_sub_));
      exact_sync_->registerCallback(&LoopClosureRos::onCloudAndOdom, this);
    }
    sync_timer_ = nh_.createWallTimer(ros::WallDuration(1.0), &LoopClosureRos::checkSynchronisation, this);
  }

  input_timer_ = nh_.createWallTimer(ros::WallDuration(1.0), &LoopClosureRos::checkInputs, this);

  diagnostics_.reset(new diagnostic_updater::Updater(nh_, pnh_, name_));
  diagnostics_->setHardwareID("none");
  diagnostics_->add("loop closure", this, &LoopClosureRos::diagnose);
  diagnostics_timer_ = nh_.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { diagnostics_->update(); });

  worker_ = std::thread(&LoopClosureRos::work, this);
  ROS_INFO_NAMED(name_, "listening on %s with poses from %s; %d x %d Scan Context, threshold %.3f, ring key %s",
                 cloud_only_sub_ ? cloud_only_sub_.getTopic().c_str() : cloud_sub_.getTopic().c_str(),
                 options_.pose_source == "tf" ? ("tf (" + options_.fixed_frame + ")").c_str()
                                              : odom_sub_.getTopic().c_str(),
                 config_.num_rings, config_.num_sectors, config_.distance_threshold, ringKeyTypeName(config_.ring_key));
  return true;
}

// ---- callbacks: copy the message pointers into the queue and return ----------------------------

void LoopClosureRos::onAnyCloud(const sensor_msgs::PointCloud2ConstPtr&) {
  ++clouds_received_;
  const double now = wallNow();
  last_cloud_wall_ = now;
  if (first_unpaired_wall_.load() == 0.0) first_unpaired_wall_ = now;
}

void LoopClosureRos::onAnyOdom(const nav_msgs::OdometryConstPtr&) { last_odom_wall_ = wallNow(); }

void LoopClosureRos::onCloudAndOdom(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                    const nav_msgs::OdometryConstPtr& odom) {
  ++clouds_paired_;
  last_pair_wall_ = wallNow();
  first_unpaired_wall_ = 0.0;
  Item item;
  std::string why;
  if (!poseFromMsg(odom->pose.pose, &item.pose, &why)) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its odometry pose is unusable: %s",
                             cloud->header.stamp.toSec(), why.c_str());
    return;
  }
  item.cloud = cloud;
  item.has_pose = true;
  item.pose_frame = normaliseFrameId(odom->header.frame_id);
  item.child_frame = normaliseFrameId(odom->child_frame_id);
  item.cloud_frame = normaliseFrameId(cloud->header.frame_id);
  enqueue(std::move(item));
}

void LoopClosureRos::onCloudOnly(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  ++clouds_received_;
  ++clouds_paired_;
  last_cloud_wall_ = wallNow();
  Item item;
  item.cloud = cloud;
  item.pose_frame = options_.fixed_frame;
  item.cloud_frame = normaliseFrameId(cloud->header.frame_id);
  enqueue(std::move(item));
}

void LoopClosureRos::enqueue(Item item) {
  item.queued = std::chrono::steady_clock::now();
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (queue_.size() >= static_cast<std::size_t>(options_.queue_size)) {
      ++dropped_;
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "worker queue full (%d keyframes): dropped %zu keyframes so far",
                              options_.queue_size, dropped_.load());
      return;
    }
    queue_.push_back(std::move(item));
    queue_length_ = queue_.size();
  }
  queue_cv_.notify_one();
}

void LoopClosureRos::checkSynchronisation(const ros::WallTimerEvent&) {
  const double now = wallNow();
  const double since = first_unpaired_wall_.load();
  if (since > 0.0 && now - since > options_.unsynchronised_warning && now - last_cloud_wall_.load() < 2.0) {
    ROS_WARN_THROTTLE_NAMED(10.0, name_,
                            "clouds on %s have found no matching pose on %s for %.0f s: are both published, "
                            "with matching stamps (approximate_sync: %s)?",
                            cloud_sub_.getTopic().c_str(), odom_sub_.getTopic().c_str(), now - since,
                            options_.approximate_sync ? "true" : "false");
  }
}

void LoopClosureRos::checkInputs(const ros::WallTimerEvent&) {
  // Repeated every no_input_warning seconds while it lasts.
  const double now = wallNow(), after = options_.no_input_warning, every = after;
  const double since_cloud = now - std::max(start_wall_, last_cloud_wall_.load());
  if (since_cloud >= after) {
    const bool tf = options_.pose_source == "tf";
    const std::string topic = tf ? cloud_only_sub_.getTopic() : cloud_sub_.getTopic();
    const std::uint32_t publishers = tf ? cloud_only_sub_.getNumPublishers() : cloud_sub_.getSubscriber().getNumPublishers();
    const std::string poses = tf ? " (poses come from tf, in " + options_.fixed_frame + ", at each cloud's stamp)" : "";
    ROS_WARN_THROTTLE_NAMED(every, name_, "no keyframe cloud on %s for %.0f s (%u publishers)%s", topic.c_str(),
                            since_cloud, publishers, poses.c_str());
  }
  if (options_.pose_source != "odom") return;
  const double since_odom = now - std::max(start_wall_, last_odom_wall_.load());
  if (since_odom >= after) {
    ROS_WARN_THROTTLE_NAMED(every, name_, "no keyframe odometry on %s for %.0f s (%u publishers)",
                            odom_sub_.getTopic().c_str(), since_odom, odom_sub_.getSubscriber().getNumPublishers());
  }
}

void LoopClosureRos::onReconfigure(scan_context_loop::LoopClosureConfig& values, std::uint32_t) {
  dynamic_reconfigure::Config message;
  values.__toMessage__(message);
  std::lock_guard<std::mutex> lock(queue_mutex_);
  Config next = live_config_;
  RosOptions next_options = live_options_;
  std::string error;
  if (!applyLiveSettings(message, &next, &next_options, &error)) {
    ROS_ERROR_NAMED(name_, "dynamic_reconfigure: refused (%s); the settings in force stay", error.c_str());
    dynamic_reconfigure::Config in_force = liveSettingsMessage(live_config_, live_options_);
    values.__fromMessage__(in_force);
    return;
  }
  if (liveSettingsChanged(live_config_, live_options_, next, next_options).empty()) return;
  live_config_ = next;
  live_options_ = next_options;
  reconfigured_ = true;
  queue_cv_.notify_one();
}

void LoopClosureRos::takeReconfigured() {
  Config next;
  RosOptions next_options;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (!reconfigured_) return;
    reconfigured_ = false;
    next = live_config_;
    next_options = live_options_;
  }
  const std::string error = pipeline_->reconfigure(next);
  if (!error.empty()) {
    ROS_ERROR_NAMED(name_, "dynamic_reconfigure: not applied: %s", error.c_str());
    return;
  }
  std::string changes;
  for (const auto& c : liveSettingsChanged(config_, options_, next, next_options)) changes += (changes.empty() ? "" : ", ") + c;
  ROS_INFO_NAMED(name_, "settings changed from the next keyframe on: %s", changes.c_str());
  config_ = next;
  for (const auto& s : nodeSettings()) {
    if (s.live) s.set(&options_, s.get(next_options));
  }
}

// ---- worker ------------------------------------------------------------------------------------

void LoopClosureRos::work() {
  // Named for top -H, perf and the soak's per-thread CPU accounting (/proc/PID/task/TID/comm).
  pthread_setname_np(pthread_self(), "scl_loop_worker");
  HeapStatistics heap(options_.heap_statistics_interval);
  while (true) {
    Item item;
    std::function<void()> task;
    bool have_item = false, redraw = false;
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      const auto ready = [this] {
        return stop_ || !queue_.empty() || redraw_markers_ || reconfigured_ || !tasks_.empty();
      };
      // Keyframes held for the extrinsic: look at tf again every 50 ms (never waiting on it).
      if (held_.empty()) {
        queue_cv_.wait(lock, ready);
      } else {
        queue_cv_.wait_for(lock, std::chrono::milliseconds(50), ready);
      }
      if (stop_) return;
      if (!tasks_.empty()) {
        task = std::move(tasks_.front());
        tasks_.pop_front();
      }
      std::swap(redraw, redraw_markers_);
      if (!task && !queue_.empty()) {
        item = std::move(queue_.front());
        queue_.pop_front();
        queue_length_ = queue_.size();
        item.queue_length = queue_.size();
        have_item = true;
      }
    }
    takeReconfigured();
    if (task) task();
    if (redraw && !positions_.empty()) {
      markers_shown_ = MarkerState();
      publishMarkers(marker_frame_);
    }
    releaseHeld(&heap);
    if (have_item) processOrHold(std::move(item), &heap);
  }
}

void LoopClosureRos::processGuarded(Item item, HeapStatistics* heap) {
  char context[64];
  std::snprintf(context, sizeof context, "keyframe at %.3f", item.cloud->header.stamp.toSec());
  runGuarded(context, [&] { process(std::move(item)); });
  if (heap->afterKeyframe(queue_length_.load() == 0)) {
    heap_allocated_ = heap->allocatedBytes();
    heap_free_ = heap->freeBytes();
    heap_statistics_ms_ = heap->lastMs();
  }
}

void LoopClosureRos::processOrHold(Item item, HeapStatistics* heap) {
  if (held_.empty() && resolveExtrinsic(item) != SensorExtrinsic::State::kWaiting) {
    processGuarded(std::move(item), heap);
    return;
  }
  if (held_.size() >= static_cast<std::size_t>(options_.queue_size)) {
    held_.pop_front();
    ++dropped_;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "%zu keyframes held for the tf extrinsic: the oldest dropped (%zu dropped so far)",
                            held_.size(), dropped_.load());
  }
  held_.push_back(std::move(item));
  held_count_ = held_.size();
}

void LoopClosureRos::releaseHeld(HeapStatistics* heap) {
  if (held_.empty() || resolveExtrinsic(held_.front()) == SensorExtrinsic::State::kWaiting) return;
  while (!held_.empty()) {
    Item item = std::move(held_.front());
    held_.pop_front();
    held_count_ = held_.size();
    processGuarded(std::move(item), heap);
  }
}

bool LoopClosureRos::runGuarded(const std::string& context, const std::function<void()>& work, std::string* what) {
  std::string why;
  if (runCatching(work, &why)) return true;
  ++failures_;
  ROS_ERROR_THROTTLE_NAMED(5.0, name_, "%s dropped: it threw: %s (the database is kept; %zu failures so far)",
                           context.c_str(), why.c_str(), failures_.load());
  adoptDatabaseKeyframes();
  if (what) *what = why;
  return false;
}

bool LoopClosureRos::lookUpPose(Item* item) {
  // A registered cloud's frame is the fixed frame: the sensor's own frame must be named.
  const std::string& sensor = options_.sensor_frame.empty() ? item->cloud_frame : options_.sensor_frame;
  try {
    const auto t = tf_buffer_->lookupTransform(options_.fixed_frame, sensor, item->cloud->header.stamp,
                                               ros::Duration(options_.tf_timeout));
    std::string why;
    if (!poseFromMsg(t.transform, &item->pose, &why)) {
      ++rejected_;
      ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: the transform %s <- %s is unusable: %s",
                               item->cloud->header.stamp.toSec(), options_.fixed_frame.c_str(), sensor.c_str(),
                               why.c_str());
      return false;
    }
    item->has_pose = true;
    return true;
  } catch (const tf2::TransformException& e) {
    ++rejected_;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "keyframe skipped: no transform %s <- %s at its stamp: %s",
                            options_.fixed_frame.c_str(), sensor.c_str(), e.what());
    return false;
  }
}

SensorExtrinsic::State LoopClosureRos::resolveExtrinsic(const Item& item) {
  if (!extrinsic_ || item.child_frame.empty()) return SensorExtrinsic::State::kKnown;  // none needed
  // A registered cloud's own frame is the world's: only a named sensor_frame says where the sensor is.
  const std::string& sensor = !options_.sensor_frame.empty() ? options_.sensor_frame
                              : config_.cloud_in_world_frame ? item.child_frame
                                                             : item.cloud_frame;
  return extrinsic_->resolve(item.child_frame, sensor, wallNow());
}

void LoopClosureRos::applyExtrinsic(Item* item) {
  if (resolveExtrinsic(*item) == SensorExtrinsic::State::kKnown && extrinsic_) item->pose = item->pose * extrinsic_->pose();
}

namespace {

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

void LoopClosureRos::process(Item item) {
  const auto started = std::chrono::steady_clock::now();
  const ThreadUsage usage_at_start = ThreadUsage::now();
  const sensor_msgs::PointCloud2& msg = *item.cloud;
  if (!item.has_pose && !lookUpPose(&item)) return;
  applyExtrinsic(&item);
  if (!item.pose.matrix().allFinite()) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its pose is not finite", msg.header.stamp.toSec());
    return;
  }
  PointView view;
  std::string why;
  if (!viewCloud(msg, &view, &why)) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe cloud at %.3f skipped: %s", msg.header.stamp.toSec(), why.c_str());
    return;
  }
  KeyframeInfo info;
  info.stamp = msg.header.stamp.toSec();
  info.pose = item.pose;
  // Keyframe selection, registered clouds back to the sensor frame, the voxel filter: in the core.
  const Detection detection = pipeline_->process(view, info);
  if (!detection.selected) return;
  if (!detection.accepted) {
    ++rejected_;
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
  if (detection.new_session) {
    const Database& database = pipeline_->detector().database();
    ROS_WARN_NAMED(name_,
                   "keyframe stamp %.3f is %.1f s before the previous keyframe's (a bag played again, a restarted "
                   "odometry?): session %u starts; the %zu keyframes before it stay candidates",
                   info.stamp, stamps_.back().toSec() - info.stamp, database.session(), database.sessionStart());
    sessions_count_ = database.session() + 1;
  }
  positions_.push_back(item.pose.translation());
  sessions_.push_back(pipeline_->detector().database().session());
  poses_.push_back(item.pose);
  stamps_.push_back(msg.header.stamp);
  database_size_ = pipeline_->detector().database().size();
  registration_bytes_ = pipeline_->detector().cloudStore().bytes();
  registration_memory_ = pipeline_->detector().cloudStore().memoryBytes();
  database_bytes_per_keyframe_ = pipeline_->detector().database().bytesPerKeyframe();
  last_query_ms_ = (detection.descriptor_seconds + detection.query_seconds) * 1e3;
  loops_waiting_ = pipeline_->detector().consistency().waiting();
  publishLoops(detection, item.pose_frame);
  marker_frame_ = item.pose_frame;
  if (marker_pub_.getNumSubscribers() > 0) publishMarkers(item.pose_frame);

  // The keyframe's whole time on the worker, markers included.
  const auto ms = [](std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  const double processing_ms = ms(std::chrono::steady_clock::now() - started);
  last_keyframe_ms_ = processing_ms;
  if (processing_ms > max_keyframe_ms_.load()) max_keyframe_ms_ = processing_ms;
  if (timing_pub_.getNumSubscribers() > 0) {
    scan_context_loop::KeyframeTiming timing;
    timing.header.stamp = msg.header.stamp;
    timing.header.frame_id = item.pose_frame;
    timing.keyframe_id = static_cast<std::uint32_t>(detection.index);
    timing.database_size = static_cast<std::uint32_t>(database_size_.load());
    timing.queue_ms = ms(started - item.queued);
    timing.processing_ms = processing_ms;
    timing.describe_query_ms = (detection.descriptor_seconds + detection.query_seconds) * 1e3;
    timing.verify_ms = detection.verify_seconds * 1e3;
    timing.queue_length = static_cast<std::uint32_t>(item.queue_length);
    const ThreadUsage usage = ThreadUsage::now();
    timing.cpu_ms = usage.cpu_ms - usage_at_start.cpu_ms;
    timing.preemptions = static_cast<std::uint32_t>(std::max(0L, usage.preemptions - usage_at_start.preemptions));
    timing.page_faults = static_cast<std::uint32_t>(std::max(0L, usage.page_faults - usage_at_start.page_faults));
    timing_pub_.publish(timing);
  }
}

scan_context_loop::LoopClosure LoopClosureRos::makeLoop(const Loop& found, const std::string& frame) const {
  scan_context_loop::LoopClosure loop;
  loop.header.stamp = stamps_[found.query];
  loop.header.frame_id = frame;
  loop.query_id = static_cast<std::uint32_t>(found.query);
  loop.match_id = static_cast<std::uint32_t>(found.match);
  loop.query_stamp = stamps_[found.query];
  loop.match_stamp = stamps_[found.match];
  loop.query_session = sessions_[found.query];
  loop.match_session = sessions_[found.match];
  loop.distance = found.alignment.distance;
  loop.yaw = found.alignment.yaw;
  loop.shift = found.alignment.shift;
  loop.relative_pose = tf2::toMsg(found.relative());
  loop.support = static_cast<std::uint32_t>(found.support);
  const Eigen::Matrix<double, 6, 6> covariance = loopCovariance(found, config_);
  for (int i = 0; i < 36; ++i) loop.covariance[i] = covariance(i / 6, i % 6);
  if (found.verified || !found.verification.reason.empty()) {
    // The registration's T_query<-match and covariance (row-major, x y z roll pitch yaw); for a
    // rejected candidate, where registration left it.
    loop.relative_pose = tf2::toMsg(found.verification.relative);
    // A verified loop's yaw is the registered one (the descriptor's prior may have been a wrong
    // column that another yaw hypothesis corrected).
    if (found.verified) {
      loop.yaw = std::atan2(found.verification.relative(1, 0), found.verification.relative(0, 0));
    }
    loop.verified = found.verified;
    loop.fitness = found.verification.fitness;
    if (!found.verified) {
      loop.rejected_by = found.verification.rejected_by;
      loop.rejection_value = found.verification.rejection_value;
      loop.rejection_limit = found.verification.rejection_limit;
      loop.rejection_reason = found.verification.reason;
    }
    return loop;
  }
  // T_query<-match from the descriptor prior (yaw, and the viewpoint's offset), large variances.
  loop.verified = false;
  loop.fitness = 0.0;
  return loop;
}

void LoopClosureRos::reportWorldTilt(const Detection& detection) {
  if (detection.world_tilt_deg < LoopDetector::kLevellingSuspectDeg) return;
  ROS_WARN_THROTTLE_NAMED(300.0, name_,
                          "levelling: the odometry's world frame is %.1f deg off gravity (from %zu ground fits; A-LOAM "
                          "and FAST-LIO start it at the first scan's frame, tilted as the sensor was): keyframes are "
                          "levelled by that attitude, the same within this session; a database saved now does not "
                          "match a session started at another tilt (doc/odometry_checks.md)",
                          detection.world_tilt_deg, pipeline_->detector().worldTilt().fits());
}

void LoopClosureRos::publishRejected(const Loop& rejected, const std::string& frame) {
  rejected_edges_.push_back({rejected.query, rejected.match, rejected.alignment.distance});
  if (rejected_pub_.getNumSubscribers() > 0) rejected_pub_.publish(makeLoop(rejected, frame));
}

void LoopClosureRos::publishLoops(const Detection& detection, const std::string& frame) {
  // Candidates that verification turned down, and verified loops the consistency check dropped, for
  // diagnosis and RViz.
  for (const auto& v : detection.verifications) {
    // One that needs support waits in the consistency check: it is published as a loop or as dropped.
    if (!v.result.accepted && !v.result.needs_support && !v.result.odometry_contradicted) publishRejected(v.toLoop(detection.index), frame);
  }
  for (Loop dropped : detection.dropped) {
    dropped.verified = false;
    dropped.verification.reason = "no consistent loop within consistency_window keyframes";
    dropped.verification.rejected_by = "consistency";
    dropped.verification.rejection_value = dropped.support;
    dropped.verification.rejection_limit =
        config_.consistency_min_support + (dropped.verification.odometry_contradicted ? 1 : 0);
    publishRejected(dropped, frame);
  }
  for (const Loop& found : detection.loops) {
    const scan_context_loop::LoopClosure loop = makeLoop(found, frame);
    ++loops_found_;
    edges_.push_back({loop.query_id, loop.match_id, loop.distance});
    loop_pub_.publish(loop);
    if (array_pub_.getNumSubscribers() > 0) array_pub_.publish(loopArray(loop));
    if (pair_pub_.getNumSubscribers() > 0) {
      for (const auto& pose : loopPair(loop, poses_[found.match])) pair_pub_.publish(pose);
    }
    const double apart = (positions_[found.query] - positions_[found.match]).norm();
    if (loop.verified) {
      ROS_INFO_THROTTLE_NAMED(1.0, name_,
                              "loop %u -> %u: %.1f m apart by odometry, yaw %.1f deg, distance %.3f, verified "
                              "(fitness %.4f m^2, support %u)",
                              loop.query_id, loop.match_id, apart, loop.yaw * 180.0 / M_PI, loop.distance,
                              loop.fitness, loop.support);
    } else {
      ROS_INFO_THROTTLE_NAMED(1.0, name_, "loop %u -> %u: %.1f m apart by odometry, yaw %.1f deg, distance %.3f",
                              loop.query_id, loop.match_id, apart, loop.yaw * 180.0 / M_PI, loop.distance);
    }
    if (options_.lio_sam_output) sendToLioSam(loop);
    if (options_.mode == "relocalize") publishRelocalization(loop);
  }
}

void LoopClosureRos::sendToLioSam(const scan_context_loop::LoopClosure& loop) {
  // LIO-SAM reads its loop hook one message at a time, once per loop-closure cycle (1 Hz by default):
  // send only verified loops (all when verification is off), one per keyframe, at most one per
  // lio_sam_min_interval; the rest are skipped and counted.
  const ros::Time now = ros::Time::now();
  const bool due = lio_last_sent_.isZero() || (now - lio_last_sent_).toSec() >= options_.lio_sam_min_interval;
  if ((config_.verification.enabled && !loop.verified) || loop.query_id == lio_last_query_ || !due) {
    ++lio_skipped_;
    return;
  }
  std_msgs::Float64MultiArray hook;
  hook.data = {loop.query_stamp.toSec(), loop.match_stamp.toSec()};
  lio_pub_.publish(hook);
  lio_last_sent_ = now;
  lio_last_query_ = loop.query_id;
}

void LoopClosureRos::publishMarkers(const std::string& frame) {
  const auto update = makeLoopMarkers(positions_, sessions_, edges_, rejected_edges_, frame, stamps_.back(),
                                      config_.distance_threshold, &markers_shown_);
  if (!update.markers.empty()) marker_pub_.publish(update);
}

void LoopClosureRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const std::size_t dropped = dropped_.load(), failures = failures_.load();
  if (failures > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%zu keyframes or service calls failed with an exception (see the log)", failures);
  } else if (dropped > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%zu keyframes dropped (queue full)", dropped);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  status.add("database size", database_size_.load());
  status.add("database bytes per keyframe", database_bytes_per_keyframe_.load());
  status.add("registration data [bytes]", registration_bytes_.load());
  // The memory the registration data's arenas hold (outside the heap; see CloudStore).
  status.add("registration memory [bytes]", registration_memory_.load());
  // What the process holds allocated through malloc, and what malloc holds free (fragmentation): with the
  // resident memory, this tells a leak from a heap that keeps freed memory for reuse. Read by the worker
  // (HeapStatistics: reading them here, on another thread, stalled the worker's allocations).
  if (heap_allocated_.load() >= 0) {
    status.add("heap allocated [bytes]", heap_allocated_.load());
    status.add("heap free [bytes]", heap_free_.load());
    status.add("heap statistics read in [ms]", heap_statistics_ms_.load());
  }
  status.add("sessions", sessions_count_.load());
  status.add("queue length", queue_length_.load());
  status.add("last query time [ms]", last_query_ms_.load());
  status.add("last keyframe time [ms]", last_keyframe_ms_.load());
  status.add("longest keyframe time [ms]", max_keyframe_ms_.load());
  status.add("loops found", loops_found_.load());
  status.add("verified loops waiting for support", loops_waiting_.load());
  status.add("clouds received", clouds_received_.load());
  status.add("clouds paired with a pose", clouds_paired_.load());
  status.add("keyframes dropped", dropped);
  if (extrinsic_) status.add("keyframes held for the tf extrinsic", held_count_.load());
  status.add("keyframes rejected", rejected_.load());
  status.add("keyframes and service calls failed (exception)", failures);
  if (options_.lio_sam_output) status.add("loops not sent to LIO-SAM (not verified, repeated or too soon)", lio_skipped_.load());
}

}  // namespace scan_context_loop
