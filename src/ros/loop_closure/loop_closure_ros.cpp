#include "loop_closure/loop_closure_ros.h"

#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/settings.h"
#include "shared/database_paths.h"
#include "shared/exception_barrier.h"
#include "shared/frame_ids.h"
#include "loop_closure/live_settings.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

LoopClosureRos::LoopClosureRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name)
    : nh_(nh), pnh_(pnh), name_(name) {}

LoopClosureRos::~LoopClosureRos() {
  // Stop the autosaves and the services (a call in progress completes while the worker still runs) and
  // the inputs first, so nothing new is queued, then let the worker finish the keyframe in hand.
  autosave_timer_.stop();
  for (auto* service : {&save_srv_, &load_srv_, &reset_srv_, &relocalize_srv_}) service->shutdown();
  if (service_spinner_) service_spinner_->stop();
  if (input_) input_->stop();
  corrected_sub_.shutdown();
  if (diagnostics_) diagnostics_->stop();
  if (queue_) {
    const std::size_t discarded = queue_->stop();
    if (discarded > 0) {
      counters_.dropped += discarded;
      ROS_WARN_NAMED(name_, "%zu keyframes still queued at shutdown were not processed (%zu dropped in all)", discarded,
                     counters_.dropped.load());
    }
  }
  if (worker_) worker_->join();
  if (team_) team_->stop();  // after the worker: nothing shares or matches any more
  // Callbacks that reach the queue or settings_mutex_ (a new marker subscriber, a live reconfigure) end
  // here, while both live.
  if (output_) output_->shutdown();
  reconfigure_server_.reset();
  if (processor_ && !options_.database_save.empty() && options_.mode != NodeMode::kRelocalize) {
    // A destructor must not throw: a failed allocation while saving is logged, and the file on disk stays
    // whole (the save writes a temporary file and renames it over the old one only when complete).
    std::string why;
    if (!runCatching([this] { saveAtShutdown(); }, &why)) {
      ROS_ERROR_NAMED(name_, "database not saved at shutdown: it threw: %s", why.c_str());
    }
  }
  writer_.wait();  // an autosave still being written (there is none when the shutdown save ran)
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
  if (options_.mode == NodeMode::kRelocalize) config_.prior_sessions_only = true;  // the map alone is searched

  queue_.reset(new KeyframeQueue(static_cast<std::size_t>(options_.queue_size), &counters_.queue_length));
  source_.reset(new KeyframeSource(name_, config_, options_, &counters_));
  processor_.reset(new KeyframeProcessor(name_, config_, options_, &counters_));
  output_.reset(new LoopClosureOutput(name_, config_, options_, &counters_));
  worker_.reset(new KeyframeWorker(name_, {queue_.get(), source_.get(), processor_.get(), output_.get(), &counters_},
                                   options_.heap_statistics_interval, [this] { takeReconfigured(); }));
  corrected_.reset(new CorrectedPoses(name_, &counters_));
  bool loaded = false;
  if (!options_.database_load.empty()) {
    std::string error;
    try {
      error = loadFile(options_.database_load);
    } catch (const std::exception& e) {
      error = std::string("the load threw: ") + e.what();
    } catch (...) {
      error = "the load threw an unknown exception";
    }
    loaded = error.empty();
    if (!loaded) {
      ROS_ERROR_NAMED(name_, "database_load %s: %s", options_.database_load.c_str(), error.c_str());
      // The file may be a map this build cannot read (other settings, another version, a read error):
      // the run goes on with an empty database, and the shutdown save never replaces that file.
      if (fileExists(options_.database_load)) {
        kept_file_ = options_.database_load;
        keep_reason_ = "its load at start failed";
      }
    }
  }
  saved_.size = processor_->database().size();  // the map as loaded is on disk already
  if (!options_.database_save.empty() && options_.mode != NodeMode::kRelocalize) {
    keepUnloadedSaveFile(loaded);
    removeAbandonedWrites(options_.database_save);
  }
  if (options_.mode == NodeMode::kRelocalize && processor_->database().size() == 0) {
    ROS_WARN_NAMED(name_, "mode relocalize without a map: nothing is published until ~load_database loads one");
  }

  KeyframeQueue* queue = queue_.get();
  output_->advertise(nh_, [queue] { queue->requestRedraw(); });
  advertiseDatabaseServices();

  // The live settings: dynamic_reconfigure starts from the parameters just read (its first call
  // changes nothing) and calls back from the spinner thread.
  live_config_ = config_;
  live_options_ = options_;
  reconfigure_server_.reset(
      new dynamic_reconfigure::Server<scan_context_loop::LoopClosureConfig>(reconfigure_mutex_, pnh_));
  reconfigure_server_->setCallback(
      [this](scan_context_loop::LoopClosureConfig& values, std::uint32_t level) { onReconfigure(values, level); });

  if (options_.pose_source == PoseSource::kTf || options_.sensor_extrinsic_from_tf) {
    tf_buffer_.reset(new tf2_ros::Buffer(ros::Duration(30.0)));
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh_));
    source_->useTf(*tf_buffer_);
  }
  input_.reset(new KeyframeInput(nh_, name_, options_, queue_.get(), &counters_));
  input_->start();
  if (options_.mode != NodeMode::kRelocalize) {
    corrected_sub_ =
        nh_.subscribe<nav_msgs::Path>(topic_names::kCorrectedPath, 1, [this](const nav_msgs::PathConstPtr& path) {
          if (corrected_->offer(path)) queue_->pushTask([this] { corrected_->applyNewest(processor_->database()); });
        });
  }
  diagnostics_.reset(new NodeDiagnostics(nh_, pnh_, name_, counters_, source_->hasExtrinsic(), options_.lio_sam_output,
                                         !options_.robot_id.empty()));

  if (!options_.robot_id.empty()) {
    team_.reset(new TeamExchange(pnh_, name_, config_, options_, &counters_, &output_->loops()));
    processor_->useTeam(team_.get());
    processor_->followDatabase();  // a loaded map is shared too
    team_->start();
  }
  worker_->start();
  if (!options_.database_save.empty() && options_.mode != NodeMode::kRelocalize &&
      options_.database_autosave_seconds > 0) {
    autosave_timer_ = nh_.createWallTimer(ros::WallDuration(options_.database_autosave_seconds),
                                          [this](const ros::WallTimerEvent&) { requestAutosave(); });
    ROS_INFO_NAMED(name_, "the database is saved to %s every %.0f s while it changes, and at shutdown",
                   options_.database_save.c_str(), options_.database_autosave_seconds);
  }
  ROS_INFO_NAMED(name_, "listening on %s with poses from %s; %d x %d Scan Context, threshold %.3f, ring key %s",
                 input_->cloudTopic().c_str(), input_->poseSource().c_str(), config_.num_rings, config_.num_sectors,
                 config_.distance_threshold, ringKeyTypeName(config_.ring_key));
  return true;
}

// ---- live settings: dynamic_reconfigure hands them over, the worker takes them -------------------

void LoopClosureRos::onReconfigure(scan_context_loop::LoopClosureConfig& values, std::uint32_t) {
  dynamic_reconfigure::Config message;
  values.__toMessage__(message);
  {
    std::lock_guard<std::mutex> lock(settings_mutex_);
    Config next = live_config_;
    NodeOptions next_options = live_options_;
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
  }
  queue_->wake();
}

void LoopClosureRos::takeReconfigured() {
  Config next;
  NodeOptions next_options;
  {
    std::lock_guard<std::mutex> lock(settings_mutex_);
    if (!reconfigured_) return;
    reconfigured_ = false;
    next = live_config_;
    next_options = live_options_;
  }
  const std::string error = processor_->pipeline().reconfigure(next);
  if (!error.empty()) {
    ROS_ERROR_NAMED(name_, "dynamic_reconfigure: not applied: %s", error.c_str());
    return;
  }
  std::string changes;
  for (const auto& c : liveSettingsChanged(config_, options_, next, next_options))
    changes += (changes.empty() ? "" : ", ") + c;
  ROS_INFO_NAMED(name_, "settings changed from the next keyframe on: %s", changes.c_str());
  config_ = next;
  for (const auto& s : nodeSettings()) {
    if (s.live) s.set(&options_, s.get(next_options));
  }
}

}  // namespace scan_context_loop
