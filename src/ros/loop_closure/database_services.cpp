// The node's database services (save, load, reset) and relocalization in a loaded map. The worker owns
// the database: each service hands it a task and waits; a save takes a snapshot on the worker and writes
// it off the worker. Where saves go and the autosave: database_saving.cpp.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <future>
#include <memory>

#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/file_io.h"
#include "shared/cloud_input.h"
#include "shared/database_paths.h"
#include "loop_closure/loop_closure_ros.h"
#include "loop_closure/loop_pair.h"
#include "shared/stored_keyframe.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

void LoopClosureRos::advertiseDatabaseServices() {
  // Their own queue and thread: a call waits for the worker and a save for its write, and neither holds
  // up the input callbacks in the nodelet's queue meanwhile.
  ros::NodeHandle services(pnh_);
  services.setCallbackQueue(&service_queue_);
  save_srv_ = services.advertiseService(topic_names::kSaveDatabase, &LoopClosureRos::onSave, this);
  load_srv_ = services.advertiseService(topic_names::kLoadDatabase, &LoopClosureRos::onLoad, this);
  reset_srv_ = services.advertiseService(topic_names::kReset, &LoopClosureRos::onReset, this);
  if (options_.mode == NodeMode::kRelocalize) {
    relocalize_srv_ = services.advertiseService(topic_names::kRelocalize, &LoopClosureRos::onRelocalize, this);
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
  output_->forgetShownMarkers();  // drawn afresh with the loaded keyframes
  ROS_INFO_NAMED(name_, "loaded %s: the database now holds %zu keyframes in %u sessions", path.c_str(),
                 processor_->database().size(), processor_->database().session() + 1);
  return "";
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
    const std::string failure = runOnWorker([&] { snapshot = takeSnapshot(request.include_clouds); });
    response.keyframes = static_cast<std::uint32_t>(snapshot.size());
    const bool replacing = fileExists(path);
    const auto started = std::chrono::steady_clock::now();
    response.success = failure.empty() && writer_.write(snapshot, path, true, &error);
    if (!failure.empty()) error = failure;
    if (response.success) {
      ++counters_.saves;
      counters_.last_save_keyframes = snapshot.size();
      counters_.last_save_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      response.message =
          "saved " + std::to_string(response.keyframes) + " keyframes to " + path + backupNote(path, replacing);
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
    output_->clearMarkers();
    reset_ = true;
    ++resets_;
    response.success = true;
    response.message = "database cleared";
    // In relocalize mode the map is read-only: it comes back.
    if (options_.mode == NodeMode::kRelocalize) {
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
      response.message = detection.verifications.empty()
                             ? "no candidate in the map"
                             : "no candidate verified: " + detection.verifications.back().result.reason;
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
