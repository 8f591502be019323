// The node's database services (save, load, reset), relocalization in a loaded map, and the database
// file at start, every database_autosave_seconds and at shutdown. The worker owns the database: each
// service hands it a task and waits; a save takes a snapshot on the worker and writes it off the worker.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <future>
#include <memory>

#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/file_io.h"
#include "scan_context_loop/ros/cloud_input.h"
#include "scan_context_loop/ros/database_paths.h"
#include "scan_context_loop/ros/loop_closure_ros.h"
#include "scan_context_loop/ros/loop_pair.h"
#include "scan_context_loop/ros/stored_keyframe.h"

namespace scan_context_loop {

void LoopClosureRos::advertiseSessionServices() {
  // Their own queue and thread: a call waits for the worker and a save for its write, and neither holds
  // up the input callbacks in the nodelet's queue meanwhile.
  ros::NodeHandle services(pnh_);
  services.setCallbackQueue(&service_queue_);
  save_srv_ = services.advertiseService("save_database", &LoopClosureRos::onSave, this);
  load_srv_ = services.advertiseService("load_database", &LoopClosureRos::onLoad, this);
  reset_srv_ = services.advertiseService("reset", &LoopClosureRos::onReset, this);
  if (options_.mode == "relocalize") {
    relocalize_srv_ = services.advertiseService("relocalize", &LoopClosureRos::onRelocalize, this);
  }
  service_spinner_.reset(new ros::AsyncSpinner(1, &service_queue_));
  service_spinner_->start();
}

std::string LoopClosureRos::runOnWorker(std::function<void()> task) {
  auto done = std::make_shared<std::promise<std::string>>();
  std::future<std::string> finished = done->get_future();
  const bool queued = queue_->pushTask([this, task, done] {
    std::string what;
    done->set_value(worker_->runGuarded("a service call", task, &what) ? "" : "failed: " + what);
  });
  if (!queued) return "the node is stopping";
  return finished.get();
}

std::string LoopClosureRos::loadFile(const std::string& path) {
  std::string error;
  const std::size_t before = processor_->database().size();
  if (!loadDatabase(path, &processor_->pipeline(), &error)) return error;
  corrected_->loaded(processor_->database(), before);
  processor_->followDatabase();
  ROS_INFO_NAMED(name_, "loaded %s: the database now holds %zu keyframes in %u sessions", path.c_str(),
                 processor_->database().size(), processor_->database().session() + 1);
  return "";
}

DatabaseSnapshot LoopClosureRos::takeSnapshot(bool include_clouds) {
  DatabaseSnapshot snapshot = processor_->snapshot(include_clouds);
  snapshot.correctPoses(corrected_->corrections());
  return snapshot;
}

std::string LoopClosureRos::saveTarget() {
  if (!beside_path_.empty()) return beside_path_;
  const std::string& path = options_.database_save;
  std::string why = keep_reason_;
  if (!sameFile(path, kept_file_)) why = reset_ && fileExists(path) ? "~reset emptied the database in this run" : "";
  if (why.empty()) return path;
  beside_path_ = besidePath(path, std::time(nullptr));
  ROS_WARN_NAMED(name_, "database_save %s is kept as it was (%s): this run's database goes beside it, to %s",
                 path.c_str(), why.c_str(), beside_path_.c_str());
  return beside_path_;
}

void LoopClosureRos::keepUnloadedSaveFile(bool loaded) {
  const std::string& path = options_.database_save;
  // A file there at start that this run's database does not hold is someone's map: database_load was
  // left empty, misspelt or names another file. Replacing it would lose it within two saves (the first
  // makes it the .bak, the second replaces that).
  if (options_.database_save_overwrite || !fileExists(path) || sameFile(path, kept_file_)) return;
  if (loaded && sameFile(path, options_.database_load)) return;
  kept_file_ = path;
  keep_reason_ = "this run did not load it (database_load: \"" + options_.database_load +
                 "\"); database_save_overwrite: true would replace it";
}

namespace {

/// How a save's log line ends when it replaced a file: where that file is kept.
std::string backupNote(const std::string& path, bool replacing) {
  return replacing ? "; the file it replaced is kept as " + path + ".bak" : "";
}

}  // namespace

void LoopClosureRos::removeAbandonedWrites(const std::string& path) {
  for (const AbandonedFile& file : removeAbandonedTemporaries(path)) {
    ROS_WARN_NAMED(name_, "removed %s (%.1f MB), left by a save of %s that never finished (the process died)",
                   file.path.c_str(), file.bytes / 1e6, path.c_str());
  }
}

void LoopClosureRos::saveAtShutdown() {
  // Within database_shutdown_seconds in all, the autosave in progress included: roslaunch follows SIGINT
  // with SIGTERM after 15 s, and a save cut off there leaves nothing but a temporary file. A write that
  // does not fit is cancelled (the file it would replace stays as it was) and the log says what the file
  // holds and what is lost.
  const auto started = std::chrono::steady_clock::now();
  const auto left = [&] {
    return options_.database_shutdown_seconds -
           std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  if (!writer_.waitFor(left())) {
    writer_.cancel();
    ROS_WARN_NAMED(name_, "the autosave in progress did not finish within database_shutdown_seconds (%.1f s): cancelled",
                   options_.database_shutdown_seconds);
  }
  const std::string path = saveTarget();
  const bool replacing = fileExists(path);
  std::size_t on_disk = 0;  // the keyframes the last save that landed wrote (or the map loaded at start)
  {
    std::lock_guard<std::mutex> lock(saved_mutex_);
    on_disk = saved_.size;
  }
  struct Outcome {
    std::mutex mutex;
    std::string error = "the write did not start";
  };
  const auto outcome = std::make_shared<Outcome>();
  DatabaseSnapshot snapshot = takeSnapshot(options_.database_save_clouds);
  const std::size_t keyframes = snapshot.size();
  writer_.writeInBackground(std::move(snapshot), path, true, [outcome](const std::string& error, double) {
    std::lock_guard<std::mutex> lock(outcome->mutex);
    outcome->error = error;
  });
  const bool in_time = writer_.waitFor(std::max(0.0, left()));
  if (!in_time) writer_.cancel();
  writer_.wait();
  std::string error;
  {
    std::lock_guard<std::mutex> lock(outcome->mutex);
    error = outcome->error;
  }
  const std::string kept = replacing ? "the file there holds the " + std::to_string(on_disk) + " keyframes it held"
                                     : "no file was written there";
  if (error.empty()) {
    ++counters_.saves;
    ROS_INFO_NAMED(name_, "database saved to %s (%zu keyframes) in %.1f s%s", path.c_str(), keyframes,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                   backupNote(path, replacing).c_str());
  } else if (!in_time) {
    ++counters_.save_failures;
    ROS_ERROR_NAMED(name_,
                    "database not saved at shutdown: writing %zu keyframes to %s did not finish within "
                    "database_shutdown_seconds (%.1f s) and was cancelled; %s, so %zu keyframes of this run are "
                    "lost. Raise database_shutdown_seconds (roslaunch sends SIGTERM 15 s after SIGINT) or lower "
                    "database_autosave_seconds",
                    keyframes, path.c_str(), options_.database_shutdown_seconds,
                    kept.c_str(),
                    keyframes > on_disk ? keyframes - on_disk : keyframes);
  } else {
    ++counters_.save_failures;
    ROS_ERROR_NAMED(name_, "database not saved: %s", error.c_str());
  }
}

void LoopClosureRos::requestAutosave() {
  if (writer_.busy() || autosave_queued_.exchange(true)) return;  // the last one is still on its way
  if (!queue_->pushTask([this] {
        autosave_queued_ = false;
        autosave();
      })) {
    autosave_queued_ = false;
  }
}

void LoopClosureRos::autosave() {
  const SavedState now{processor_->database().size(), resets_, corrected_->version()};
  {
    std::lock_guard<std::mutex> lock(saved_mutex_);
    if (now == saved_) return;  // nothing new since the last write that landed
  }
  const std::string path = saveTarget();
  DatabaseSnapshot snapshot = takeSnapshot(options_.database_save_clouds);
  // Only a write that succeeded marks the database saved: after a failure (a full disk, EIO) the next
  // autosave writes again, even when nothing changed meanwhile.
  writer_.writeInBackground(std::move(snapshot), path, true, [this, path, now](const std::string& error, double seconds) {
    if (!error.empty()) {
      ++counters_.save_failures;
      ROS_ERROR_THROTTLE_NAMED(60.0, name_, "autosave to %s failed: %s (%zu failures; the file there is as before)",
                               path.c_str(), error.c_str(), counters_.save_failures.load());
      return;
    }
    {
      std::lock_guard<std::mutex> lock(saved_mutex_);
      saved_ = now;
    }
    ++counters_.saves;
    counters_.last_save_keyframes = now.size;
    counters_.last_save_seconds = seconds;
    ROS_DEBUG_NAMED(name_, "autosaved %zu keyframes to %s in %.2f s", now.size, path.c_str(), seconds);
  });
  // When a write is still in progress nothing starts: the next autosave takes up what changed.
}

bool LoopClosureRos::onSave(scan_context_loop::SaveDatabase::Request& request,
                            scan_context_loop::SaveDatabase::Response& response) {
  std::string path, error;
  response.keyframes = static_cast<std::uint32_t>(counters_.database_size.load());  // refused: what there is
  response.success = servicePath(mapDirectory(options_), request.path, &path, &error);
  if (response.success) {
    removeAbandonedWrites(path);
    // The snapshot on the worker (milliseconds), the write here: detection goes on meanwhile.
    DatabaseSnapshot snapshot;
    const std::string failure =
        runOnWorker([&] { snapshot = takeSnapshot(request.include_clouds); });
    response.keyframes = static_cast<std::uint32_t>(snapshot.size());
    const bool replacing = fileExists(path);
    const auto started = std::chrono::steady_clock::now();
    response.success = failure.empty() && writer_.write(snapshot, path, true, &error);
    if (!failure.empty()) error = failure;
    if (response.success) {
      ++counters_.saves;
      counters_.last_save_keyframes = snapshot.size();
      counters_.last_save_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      response.message = "saved " + std::to_string(response.keyframes) + " keyframes to " + path +
                         backupNote(path, replacing);
      ROS_INFO_NAMED(name_, "save_database: %s", response.message.c_str());
      return true;
    }
  }
  response.message = error;
  ROS_ERROR_NAMED(name_, "save_database %s: %s", request.path.c_str(), response.message.c_str());
  return true;
}

bool LoopClosureRos::onLoad(scan_context_loop::LoadDatabase::Request& request,
                            scan_context_loop::LoadDatabase::Response& response) {
  const std::string failure = runOnWorker([&] {
    const std::string error = loadFile(request.path);
    response.success = error.empty();
    response.message = response.success ? "loaded" : error;
    response.keyframes = static_cast<std::uint32_t>(processor_->database().size());
    response.sessions = processor_->database().session() + 1;
  });
  if (!failure.empty()) response.message = failure;
  if (!response.success) ROS_ERROR_NAMED(name_, "load_database %s: %s", request.path.c_str(), response.message.c_str());
  return true;
}

bool LoopClosureRos::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  const std::string failure = runOnWorker([&] {
    processor_->resetPipeline();
    if (team_) team_->restart();  // the team hears of the reset even if a load refills the database at once
    corrected_->reset();
    counters_.database_size = 0;
    counters_.sessions = 1;
    counters_.loops_waiting = 0;
    markers_->clear();
    reset_ = true;
    ++resets_;
    response.success = true;
    response.message = "database cleared";
    // In relocalize mode the map is read-only: it comes back.
    if (options_.mode == "relocalize") {
      const std::string error = loadFile(options_.database_load);
      response.success = error.empty();
      response.message = error.empty() ? "database cleared, map reloaded" : "map not reloaded: " + error;
    }
  });
  if (!failure.empty()) {
    response.success = false;
    response.message = failure;
  }
  ROS_INFO_NAMED(name_, "reset: %s", response.message.c_str());
  return true;
}

bool LoopClosureRos::onRelocalize(scan_context_loop::Relocalize::Request& request,
                                  scan_context_loop::Relocalize::Response& response) {
  const std::string failure = runOnWorker([&] {
    PointView view;
    std::string why;
    if (!viewCloud(request.cloud, &view, &why)) {
      response.message = "cloud refused: " + why;
      return;
    }
    const Detection detection = processor_->pipeline().locate(view);
    if (!detection.verified) {
      response.message = detection.verifications.empty() ? "no candidate in the map"
                                                         : "no candidate verified: " +
                                                               detection.verifications.back().result.reason;
      return;
    }
    const VerifiedCandidate& place = detection.verifications.back();
    const Keyframe& match = processor_->database().keyframe(place.index);
    scan_context_loop::LoopClosure loop;
    loop.header.frame_id = options_.map_frame;
    loop.query_stamp = request.cloud.header.stamp;
    loop.match_stamp = keyframeStamp(match.info);
    loop.relative_pose = tf2::toMsg(place.result.relative);
    const Eigen::Matrix<double, 6, 6> covariance = loopCovariance(place.toLoop(detection.index), config_);
    for (int i = 0; i < 36; ++i) loop.covariance[i] = covariance(i / 6, i % 6);
    response.pose = loopPair(loop, keyframePose(match))[1];
    response.found = true;
    response.match_id = static_cast<std::uint32_t>(place.index);
    response.match_session = match.session;
    response.message = "verified (fitness " + std::to_string(place.result.fitness) + ")";
  });
  if (!failure.empty()) response.message = failure;
  return true;
}

}  // namespace scan_context_loop
