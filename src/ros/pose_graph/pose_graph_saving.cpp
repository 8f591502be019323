// PoseGraphRos's map files: the ~save_map service and the save at shutdown (map_save). The worker owns
// the graph and the map: a save takes a copy on the worker (solving first if a solve is due) and
// writes it off the worker (graph/map_files.h), so that the graph goes on meanwhile.
#include <atomic>
#include <chrono>
#include <future>
#include <memory>

#include "shared/database_paths.h"
#include "shared/exception_barrier.h"
#include "pose_graph/pose_graph_ros.h"

namespace scan_context_loop {

namespace {

/// A service waits this long for the worker's copy (a solve in hand, a long queue before it) [s].
constexpr double kWorkerTimeout = 60.0;

/// map_directory as the node uses it: the parameter, else $ROS_HOME/scan_context_loop/maps.
std::string mapDirectoryOf(const PoseGraphOptions& options) {
  return options.map_directory.empty() ? rosHome() + "/scan_context_loop/maps" : options.map_directory;
}

}  // namespace

void PoseGraphRos::advertiseSaveMap() {
  ros::NodeHandle services(pnh_);
  services.setCallbackQueue(&service_queue_);
  save_srv_ = services.advertiseService("save_map", &PoseGraphRos::onSaveMap, this);
  service_spinner_.reset(new ros::AsyncSpinner(1, &service_queue_));
  service_spinner_->start();
}

std::string PoseGraphRos::runOnWorker(std::function<void()> task) {
  // Shared with the task: a call that timed out leaves it nothing dangling to write into. `state`
  // decides who has the task: the worker when it starts it (kQueued -> kStarted), or a call that timed
  // out first (kQueued -> kCancelled), whose task the worker then skips (no solve, no map for nobody).
  enum State { kQueued, kStarted, kCancelled };
  auto done = std::make_shared<std::promise<std::string>>();
  auto state = std::make_shared<std::atomic<int>>(kQueued);
  std::future<std::string> finished = done->get_future();
  Event event;
  event.task = [this, task, done, state] {
    int queued = kQueued;
    if (!state->compare_exchange_strong(queued, kStarted)) return;  // its caller gave up on it
    std::string what;
    done->set_value(runCatching(task, &what) ? "" : "it threw: " + what);
  };
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (stop_) return "the node is stopping";
    queue_.push_back(std::move(event));  // past queue_size: a service call is never dropped
  }
  queue_cv_.notify_one();
  if (finished.wait_for(std::chrono::duration<double>(kWorkerTimeout)) != std::future_status::ready) {
    int queued = kQueued;
    const bool cancelled = state->compare_exchange_strong(queued, kCancelled);
    return "the worker did not answer within " + std::to_string(static_cast<int>(kWorkerTimeout)) + " s" +
           (cancelled ? " (the request is withdrawn)" : " (it is still at it; its result is dropped)");
  }
  return finished.get();
}

bool PoseGraphRos::mapTarget(const std::string& requested, std::string* directory, std::string* error) const {
  std::string path = requested.empty() ? options_.map_save : requested;
  if (path.empty()) {
    *error = "no path given, and map_save is not set";
    return false;
  }
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  // map_save is the user's own setting: an absolute one is taken as it is; everything else must lie
  // in map_directory.
  if (requested.empty() && path.front() == '/') {
    *directory = path;
    return true;
  }
  return servicePath(mapDirectoryOf(options_), path, directory, error, "map_directory");
}

MapFiles PoseGraphRos::snapshotMap() {
  if (solve_pending_) solveAndPublish(true);  // the loops that came are in the map saved
  std::vector<std::string> ids;               // by chain; none for the single robot (its files keep their names)
  for (const GraphRobot& robot : robots_) {
    if (team_) ids.push_back(robot.id);
  }
  MapFiles files = mapFilesOf(*graph_, stampsByIndex(*graph_, robots_), ids);
  if (options_.build_map) {
    files.cloud = map_->assemble(files.corrected, unjoinedKeyframes(*graph_, robots_));  // the map's robots only
    files.has_cloud = true;
    files.voxel = map_config_.voxel;
  }
  return files;
}

bool PoseGraphRos::writeMap(const std::string& directory, const MapFiles& files, MapFilesReport* report,
                            std::string* error) {
  if (files.stamps_ns.empty()) {
    *error = "the graph holds no keyframes yet: nothing saved";
    ++save_failures_;
    return false;
  }
  const bool written = writeMapFiles(directory, files, report, error);
  for (const AbandonedFile& file : report->abandoned) {
    ROS_WARN_NAMED(name_, "removed %s (%.1f MB), left by a save that never finished (the process died)",
                   file.path.c_str(), file.bytes / 1e6);
  }
  ++(written ? saves_ : save_failures_);
  return written;
}

bool PoseGraphRos::onSaveMap(scan_context_loop::SaveMap::Request& request,
                             scan_context_loop::SaveMap::Response& response) {
  std::string directory, error;
  auto files = std::make_shared<MapFiles>();
  MapFilesReport report;
  response.success = mapTarget(request.path, &directory, &error);
  if (response.success) {
    const std::string failure = runOnWorker([this, files] { *files = snapshotMap(); });
    if (!failure.empty()) error = "the map was not copied: " + failure;
    response.success = failure.empty() && writeMap(directory, *files, &report, &error);
  } else {
    ++save_failures_;
  }
  if (!response.success) {
    response.message = error;
    ROS_ERROR_NAMED(name_, "save_map %s: %s (the graph goes on)", request.path.c_str(), error.c_str());
    return true;
  }
  response.files = report.files;
  response.message = "saved " + report.summary();
  ROS_INFO_NAMED(name_, "save_map: %s", response.message.c_str());
  return true;
}

void PoseGraphRos::saveAtShutdown() {
  if (options_.map_save.empty() || !graph_) return;
  std::string directory, error, what;
  MapFiles files;
  MapFilesReport report;
  // The worker has stopped: its state is this thread's now.
  bool saved = mapTarget("", &directory, &error);
  if (saved && !runCatching([&] { files = snapshotMap(); }, &what)) {
    saved = false;
    error = "copying the map threw: " + what;
  }
  if (saved) saved = writeMap(directory, files, &report, &error);
  if (saved) {
    ROS_INFO_NAMED(name_, "map saved at shutdown (map_save) to %s", report.summary().c_str());
  } else {
    ROS_ERROR_NAMED(name_, "map_save %s: map not saved at shutdown: %s", options_.map_save.c_str(), error.c_str());
  }
}

}  // namespace scan_context_loop
