// Where the node's database is saved and when: the file at database_save (or one beside it that keeps a
// map this run did not load), every database_autosave_seconds while it changes, and at shutdown within
// database_shutdown_seconds. The writes run on the writer's thread (DatabaseWriter).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <future>
#include <memory>

#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/file_io.h"
#include "loop_closure/loop_closure_ros.h"
#include "shared/database_paths.h"

namespace scan_context_loop {

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

std::string backupNote(const std::string& path, bool replacing) {
  return replacing ? "; the file it replaced is kept as " + path + ".bak" : "";
}

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
    ROS_WARN_NAMED(name_,
                   "the autosave in progress did not finish within database_shutdown_seconds (%.1f s): cancelled",
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
                    keyframes, path.c_str(), options_.database_shutdown_seconds, kept.c_str(),
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
  writer_.writeInBackground(
      std::move(snapshot), path, true, [this, path, now](const std::string& error, double seconds) {
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

}  // namespace scan_context_loop
