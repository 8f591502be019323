// Database saves off the detector's thread: a snapshot (database_file.h) taken on the detector's thread
// is written here, in the background or on the caller's thread, one write at a time.
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "scan_context_loop/core/database_file.h"

namespace scan_context_loop {

/// Thread-safe. write_mutex_ is held through each write, so writes never overlap (two saves to one file
/// never race for it); thread_mutex_ guards the background thread's handle.
class DatabaseWriter {
 public:
  /// Runs on the background thread when its write ended: "" or why it failed, and the write's wall time [s].
  using Done = std::function<void(const std::string& error, double seconds)>;

  DatabaseWriter() = default;
  /// Waits for the background write in progress.
  ~DatabaseWriter() { wait(); }
  DatabaseWriter(const DatabaseWriter&) = delete;
  DatabaseWriter& operator=(const DatabaseWriter&) = delete;

  /// Writes `snapshot` to `path` (writeDatabase) on the calling thread, once the background write in
  /// progress (which holds an earlier snapshot) ended.
  bool write(const DatabaseSnapshot& snapshot, const std::string& path, bool keep_backup, std::string* error);
  /// Starts writing `snapshot` to `path` on a thread of its own and returns at once; `done` runs on that
  /// thread after the write, and the snapshot (with what it keeps alive) is released there. Never waits:
  /// returns false, starting nothing, while an earlier background write is in progress or being waited for.
  bool writeInBackground(DatabaseSnapshot snapshot, const std::string& path, bool keep_backup, Done done);
  /// The background thread's nice value (it runs below the detector's thread when the CPU is short).
  static constexpr int kNice = 10;
  /// Whether a background write is in progress.
  bool busy() const { return busy_.load(); }
  /// Waits for the background write in progress, if any.
  void wait();
  /// Waits at most `seconds` for it; true when none is in progress (any more).
  bool waitFor(double seconds);
  /// Stops the background write in progress at its next piece (the file it would replace stays as it
  /// was; its Done reports the cancellation) and waits for its thread.
  void cancel();

 private:
  /// writeDatabase under write_mutex_ (the background thread's write, and write()'s after the wait).
  bool writeNow(const DatabaseSnapshot& snapshot, const std::string& path, bool keep_backup, std::string* error);

  std::mutex write_mutex_;
  std::mutex thread_mutex_;
  std::thread thread_;
  std::atomic<bool> busy_{false};
  std::atomic<bool> cancel_{false};  // set by cancel() while it stops the background write
};

}  // namespace scan_context_loop
