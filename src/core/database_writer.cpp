#include "scan_context_loop/core/database_writer.h"

#include <chrono>
#include <utility>

#include <pthread.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace scan_context_loop {

bool DatabaseWriter::write(const DatabaseSnapshot& snapshot, const std::string& path, bool keep_backup,
                           std::string* error) {
  wait();  // a background write taken earlier lands first
  return writeNow(snapshot, path, keep_backup, error);
}

bool DatabaseWriter::writeNow(const DatabaseSnapshot& snapshot, const std::string& path, bool keep_backup,
                              std::string* error) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  return writeDatabase(snapshot, path, keep_backup, error, &cancel_);
}

bool DatabaseWriter::writeInBackground(DatabaseSnapshot snapshot, const std::string& path, bool keep_backup,
                                       Done done) {
  // Never waits: while another thread waits for the last write (wait() holds the lock), none starts.
  std::unique_lock<std::mutex> lock(thread_mutex_, std::try_to_lock);
  if (!lock.owns_lock() || busy_.load()) return false;
  if (thread_.joinable()) thread_.join();  // the last write's thread, which has ended
  busy_ = true;
  thread_ = std::thread([this, snapshot = std::move(snapshot), path, keep_backup, done = std::move(done)]() mutable {
    // Named for top -H and perf, beside the worker's scl_loop_worker.
    pthread_setname_np(pthread_self(), "scl_db_writer");
    // Yields the CPU to the detector's thread when both want it (Linux sets a thread's nice value on
    // its own); a save that waits a little loses nothing, a keyframe that waits may be dropped.
    ::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), kNice);
    const auto started = std::chrono::steady_clock::now();
    std::string error;
    bool written = false;
    try {
      written = writeNow(snapshot, path, keep_backup, &error);
    } catch (const std::exception& e) {
      error = std::string("the write threw: ") + e.what();
    } catch (...) {
      error = "the write threw an unknown exception";
    }
    if (!written && error.empty()) error = "the write failed";
    snapshot = DatabaseSnapshot();  // released here, not on the thread that took it
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    try {
      if (done) done(written ? "" : error, seconds);
    } catch (...) {
      // A report that throws must not end the process (std::terminate); the write itself is done.
    }
    busy_ = false;
  });
  return true;
}

void DatabaseWriter::wait() {
  std::lock_guard<std::mutex> lock(thread_mutex_);
  if (thread_.joinable()) thread_.join();
}

bool DatabaseWriter::waitFor(double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (busy_.load() && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return !busy_.load();
}

void DatabaseWriter::cancel() {
  cancel_ = true;
  wait();
  cancel_ = false;
}

}  // namespace scan_context_loop
