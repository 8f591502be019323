// Whole-file reading (from a file or from memory) and atomic replacement of a file, with errors that
// name the path and the cause.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "scan_context_loop/core/byte_stream.h"

namespace scan_context_loop {

/// The directory part of `path`: "." for a bare name, "/" for a name at the root.
std::string directoryOf(const std::string& path);

/// Bytes read front to back, from a file (FileReader) or from memory (MemoryReader), so that a parser
/// reads both the same way.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  /// How many bytes there are in all.
  virtual std::uint64_t size() const = 0;
  /// The next `n` bytes, contiguous and valid until the next call; nullptr when the source ends before
  /// them or a read fails (readError() then says why).
  virtual const std::uint8_t* take(std::size_t n) = 0;
  /// Why the last take failed, or "" when the source simply ended.
  virtual const std::string& readError() const = 0;
};

/// A byte range in memory, which must outlive the reader.
class MemoryReader : public ByteSource {
 public:
  MemoryReader(const std::uint8_t* data, std::size_t size) : bytes_(data, size), size_(size) {}
  std::uint64_t size() const override { return size_; }
  const std::uint8_t* take(std::size_t n) override { return bytes_.take(n); }
  const std::string& readError() const override { return no_error_; }

 private:
  ByteReader bytes_;
  std::size_t size_;
  std::string no_error_;
};

/// Reads a regular file front to back through a buffer of about a megabyte, so that a large file is
/// never held in memory whole. Not copyable.
class FileReader : public ByteSource {
 public:
  FileReader() = default;
  ~FileReader() override;
  FileReader(const FileReader&) = delete;
  FileReader& operator=(const FileReader&) = delete;

  /// False, with the reason in *error (a missing file, no permission, a directory, a FIFO, a socket, a
  /// device), when `path` is not a regular file that can be read. Never blocks: a FIFO is refused
  /// without waiting for a writer.
  bool open(const std::string& path, std::string* error);
  /// The file's size when it was opened.
  std::uint64_t size() const override { return size_; }
  const std::uint8_t* take(std::size_t n) override;
  const std::string& readError() const override { return read_error_; }

 private:
  int fd_ = -1;
  std::string path_, read_error_;
  std::uint64_t size_ = 0;
  std::vector<std::uint8_t> buffer_;
  std::size_t begin_ = 0, end_ = 0;  // the buffered bytes not taken yet
};

/// Writes a file so that readers see either the old file or the whole new one: the data go to a
/// temporary file in the target's directory, which commit() flushes to disk (fsync) and renames over
/// the target. Until commit() succeeds the target is untouched; a writer destroyed without a successful
/// commit removes its temporary file, which stays locked (flock) while it exists, so that
/// removeAbandonedTemporaries() tells it from one a dead process left. Only a regular file is replaced.
/// A file replaced keeps its mode, with read and write for its owner added (a new one is 0644). A write
/// error the kernel reports during the write-behind fails commit(), as fsync's would. Not copyable.
class AtomicFileWriter {
 public:
  AtomicFileWriter() = default;
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  /// Creates the temporary file for `path`; false with *error when the directory does not exist or
  /// is not writable, or when `path` is something other than a regular file (a directory, a FIFO, a
  /// socket, a device: named in *error).
  bool open(const std::string& path, std::string* error);
  /// commit() first makes the file it replaces (if any) `backup`, itself replaced atomically: a hard
  /// link, or a copy flushed to disk where the file system has no hard links (vfat, exFAT).
  void keepBackup(const std::string& backup) { backup_ = backup; }
  /// Once `*cancel` is set, the next write() or commit() fails ("cancelled") and removes the temporary
  /// file: the target stays as it was. `cancel` must outlive the writer; null: never cancelled.
  void cancelWhen(const std::atomic<bool>* cancel) { cancel_ = cancel; }
  /// Appends to the temporary file. Every kWriteBehindBytes appended go to disk while the next are
  /// written (write-behind), so commit() has little left to flush.
  bool write(const void* data, std::size_t size, std::string* error);
  static constexpr std::size_t kWriteBehindBytes = std::size_t(8) << 20;
  /// Overwrites bytes already written, at `offset` (a header whose fields are known only at the end).
  bool writeAt(std::size_t offset, const void* data, std::size_t size, std::string* error);
  /// fsync, rename over the target, fsync of the directory (so the rename survives a power cut).
  bool commit(std::string* error);

 private:
  void discard();
  /// Starts the write of [started_, written_) to disk and waits for [settled_, started_).
  void writeBehind();
  /// Keeps the first real error of a sync_file_range that returned `result` for commit().
  void keepError(int result);
  /// Whether cancelWhen's flag is set; then the write is discarded and *error says so.
  bool cancelled(std::string* error);
  std::string path_, temporary_, backup_;
  int fd_ = -1;
  std::size_t written_ = 0;
  std::size_t started_ = 0, settled_ = 0;  // bytes whose write to disk was started / is done
  int write_behind_error_ = 0;             // the first errno of writeBehind, 0 when none
  const std::atomic<bool>* cancel_ = nullptr;
};

/// A file removeAbandonedTemporaries() removed, and its size.
struct AbandonedFile {
  std::string path;
  std::size_t bytes = 0;
};

/// Removes what writes of `path` left behind when their process died before the rename: the regular
/// files of this user beside it named as AtomicFileWriter names its temporary files (`path`.tmp.XXXXXX,
/// and `path`.bak.tmp.XXXXXX of the backup's link) that no live writer holds locked. Returns what it
/// removed; anything it cannot read or remove stays.
std::vector<AbandonedFile> removeAbandonedTemporaries(const std::string& path);

}  // namespace scan_context_loop
