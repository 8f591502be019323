// The node's database services (save, load, reset), relocalization in a loaded map, and the database
// file at start and shutdown. The worker owns the database: each service hands it a task and waits.
#include <ctime>
#include <future>
#include <memory>

#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/ros/cloud_input.h"
#include "scan_context_loop/ros/database_paths.h"
#include "scan_context_loop/ros/loop_closure_ros.h"
#include "scan_context_loop/ros/loop_pair.h"
#include "scan_context_loop/ros/stored_keyframe.h"

namespace scan_context_loop {

void LoopClosureRos::advertiseSessionServices() {
  save_srv_ = pnh_.advertiseService("save_database", &LoopClosureRos::onSave, this);
  load_srv_ = pnh_.advertiseService("load_database", &LoopClosureRos::onLoad, this);
  reset_srv_ = pnh_.advertiseService("reset", &LoopClosureRos::onReset, this);
  if (options_.mode == "relocalize") {
    relocalize_srv_ = pnh_.advertiseService("relocalize", &LoopClosureRos::onRelocalize, this);
  }
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
  if (!loadDatabase(path, &processor_->pipeline(), &error)) return error;
  processor_->followDatabase();
  ROS_INFO_NAMED(name_, "loaded %s: the database now holds %zu keyframes in %u sessions", path.c_str(),
                 processor_->database().size(), processor_->database().session() + 1);
  return "";
}

void LoopClosureRos::saveAtShutdown() {
  std::string path = options_.database_save;
  std::string why = keep_reason_;
  if (!sameFile(path, kept_file_)) why = reset_ && fileExists(path) ? "~reset emptied the database in this run" : "";
  if (!why.empty()) {
    path = besidePath(options_.database_save, std::time(nullptr));
    ROS_WARN_NAMED(name_, "database_save %s is kept as it was (%s): this run's database goes beside it, to %s",
                   options_.database_save.c_str(), why.c_str(), path.c_str());
  }
  SaveOptions save;
  save.include_clouds = options_.database_save_clouds;
  save.keep_backup = true;
  const std::string backup = fileExists(path) ? "; the file it replaced is kept as " + path + ".bak" : "";
  std::string error;
  if (saveDatabase(processor_->pipeline().detector(), path, save, &error)) {
    ROS_INFO_NAMED(name_, "database saved to %s (%zu keyframes)%s", path.c_str(), processor_->database().size(),
                   backup.c_str());
  } else {
    ROS_ERROR_NAMED(name_, "database not saved: %s", error.c_str());
  }
}

bool LoopClosureRos::onSave(scan_context_loop::SaveDatabase::Request& request,
                            scan_context_loop::SaveDatabase::Response& response) {
  const std::string failure = runOnWorker([&] {
    SaveOptions save;
    save.include_clouds = request.include_clouds;
    save.keep_backup = true;
    std::string path, error;
    response.keyframes = static_cast<std::uint32_t>(processor_->database().size());
    response.success = servicePath(mapDirectory(options_), request.path, &path, &error);
    const bool replacing = response.success && fileExists(path);
    response.success = response.success && saveDatabase(processor_->pipeline().detector(), path, save, &error);
    if (!response.success) {
      response.message = error;
      return;
    }
    response.message = "saved " + std::to_string(response.keyframes) + " keyframes to " + path +
                       (replacing ? "; the file it replaced is kept as " + path + ".bak" : "");
    ROS_INFO_NAMED(name_, "save_database: %s", response.message.c_str());
  });
  if (!failure.empty()) response.message = failure;
  if (!response.success) ROS_ERROR_NAMED(name_, "save_database %s: %s", request.path.c_str(), response.message.c_str());
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
    counters_.database_size = 0;
    counters_.sessions = 1;
    counters_.loops_waiting = 0;
    markers_->clear();
    reset_ = true;
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
