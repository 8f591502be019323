#include "scan_context_loop/core/file_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace scan_context_loop {

std::string directoryOf(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

namespace {

bool fail(std::string* error, const std::string& what) {
  if (error) *error = what + ": " + std::strerror(errno);
  return false;
}

/// Whether link(2) failed for want of hard links rather than for a fault: vfat and exFAT refuse every
/// link (EPERM), some network and FUSE file systems say they do not support it (EOPNOTSUPP, which is
/// ENOTSUP on Linux), and EXDEV (a bind mount) and EMLINK (a file at its link limit) leave no other way
/// either. The backup is then a copy.
bool withoutHardLinks(int error) { return error == EPERM || error == EOPNOTSUPP || error == EXDEV || error == EMLINK; }

/// Copies the file at `path` to the new file `name` with `mode` and flushes the copy to disk; the open
/// copy, or -1 with *error (nothing left at `name`). It stays locked (flock) while open, so that
/// removeAbandonedTemporaries() leaves it to this writer until it is renamed.
int copyForBackup(const std::string& path, const std::string& name, mode_t mode, std::string* error) {
  const int in = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) {
    fail(error, "cannot read " + path + " to keep a copy of it");
    return -1;
  }
  const int out = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (out < 0) {
    fail(error, "cannot create " + name);
    ::close(in);
    return -1;
  }
  ::flock(out, LOCK_EX | LOCK_NB);
  std::vector<char> buffer(std::size_t(1) << 20);
  bool ok = true;
  for (ssize_t got = 1; ok && got != 0;) {
    got = ::read(in, buffer.data(), buffer.size());
    if (got < 0 && errno != EINTR) ok = fail(error, "cannot read " + path + " to keep a copy of it");
    for (ssize_t done = 0; ok && done < got;) {
      const ssize_t n = ::write(out, buffer.data() + done, static_cast<std::size_t>(got - done));
      if (n >= 0)
        done += n;
      else if (errno != EINTR)
        ok = fail(error, "cannot write " + name);
    }
  }
  ::fchmod(out, mode);  // advisory: vfat has no modes to set
  if (ok && ::fsync(out) != 0) ok = fail(error, "cannot flush " + name);
  ::close(in);
  if (ok) return out;
  ::unlink(name.c_str());
  ::close(out);
  return -1;
}

/// Makes the file at `path` (if there is one) also `backup`: a hard link (or, on a file system without
/// them, a copy) under a temporary name renamed over `backup`, so that `backup` is at every moment a
/// whole file, the old backup or the new one.
bool linkBackup(const std::string& path, const std::string& backup, std::string* error) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return true;  // nothing to keep
  std::string name = backup + ".tmp.XXXXXX";
  const int fd = ::mkstemp(&name[0]);
  if (fd < 0) return fail(error, "cannot create a temporary file in " + directoryOf(backup));
  ::close(fd);
  ::unlink(name.c_str());
  int copy = -1;
  if (::link(path.c_str(), name.c_str()) != 0) {
    if (!withoutHardLinks(errno)) return fail(error, "cannot keep " + path + " as " + backup);
    copy = copyForBackup(path, name, st.st_mode & 07777, error);
    if (copy < 0) return false;
  }
  bool ok = true;
  if (::rename(name.c_str(), backup.c_str()) != 0) {
    ok = fail(error, "cannot rename " + name + " to " + backup);
    ::unlink(name.c_str());
  }
  if (copy >= 0) ::close(copy);  // after the rename: locked as long as it has a temporary name
  return ok;
}

/// Why a file of `mode` is not read (" is a directory", ...), or nullptr for a regular file.
const char* notRegular(mode_t mode) {
  if (S_ISREG(mode)) return nullptr;
  if (S_ISDIR(mode)) return " is a directory";
  if (S_ISFIFO(mode)) return " is a named pipe (FIFO), not a regular file";
  if (S_ISSOCK(mode)) return " is a socket, not a regular file";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return " is a device, not a regular file";
  return " is not a regular file";
}

}  // namespace

FileReader::~FileReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool FileReader::open(const std::string& path, std::string* error) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  path_ = path;
  begin_ = end_ = 0;
  // The type is checked before opening (opening a FIFO waits for a writer, a device may act on open),
  // and again on what was opened, without blocking, in case the path changed in between.
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return fail(error, "cannot open " + path);
  if (const char* what = notRegular(st.st_mode)) {
    if (error) *error = path + what;
    return false;
  }
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd_ < 0) return fail(error, "cannot open " + path);
  if (::fstat(fd_, &st) != 0) return fail(error, "cannot stat " + path);
  if (const char* what = notRegular(st.st_mode)) {
    if (error) *error = path + what;
    return false;
  }
  // A regular file, which never blocks: reads need not see O_NONBLOCK.
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
  size_ = static_cast<std::uint64_t>(st.st_size);
  return true;
}

const std::uint8_t* FileReader::take(std::size_t n) {
  constexpr std::size_t kChunk = std::size_t(1) << 20;
  if (end_ - begin_ < n) {
    // Keep what is left at the front, then read until n bytes are there or the file ends.
    if (begin_ > 0) std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
    if (buffer_.size() < std::max(n, kChunk)) buffer_.resize(std::max(n, kChunk));
    while (end_ < n && fd_ >= 0) {
      const ssize_t got = ::read(fd_, buffer_.data() + end_, buffer_.size() - end_);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) read_error_ = "cannot read " + path_ + ": " + std::strerror(errno);
      if (got <= 0) return nullptr;
      end_ += static_cast<std::size_t>(got);
    }
    if (end_ < n) return nullptr;
  }
  const std::uint8_t* p = buffer_.data() + begin_;
  begin_ += n;
  return p;
}

AtomicFileWriter::~AtomicFileWriter() { discard(); }

void AtomicFileWriter::discard() {
  if (fd_ >= 0) ::close(fd_);
  if (!temporary_.empty()) ::unlink(temporary_.c_str());
  fd_ = -1;
  written_ = started_ = settled_ = 0;
  write_behind_error_ = 0;
  temporary_.clear();
}

bool AtomicFileWriter::open(const std::string& path, std::string* error) {
  discard();
  path_ = path;
  // Only a regular file is replaced: a directory, a FIFO, a socket or a device in its place is someone
  // else's, and renaming over it would take it away.
  struct stat st;
  const bool replacing = ::stat(path.c_str(), &st) == 0;
  if (const char* what = replacing ? notRegular(st.st_mode) : nullptr) {
    if (error) *error = "cannot write " + path + ": it" + what;
    return false;
  }
  std::string name = path + ".tmp.XXXXXX";
  fd_ = ::mkstemp(&name[0]);
  if (fd_ < 0) return fail(error, "cannot create a temporary file in " + directoryOf(path));
  temporary_ = name;
  // Locked until the rename: removeAbandonedTemporaries() leaves a locked temporary file alone.
  ::flock(fd_, LOCK_EX | LOCK_NB);
  // mkstemp makes the file private (0600): a new file is an ordinary data file, a replaced one keeps
  // the mode its owner gave it, but always readable and writable by its owner, so that the next run
  // can load and save it (a mode 000 file would otherwise stay unreadable).
  ::fchmod(fd_, replacing ? ((st.st_mode & 07777) | 0600) : 0644);
  return true;
}

bool AtomicFileWriter::cancelled(std::string* error) {
  if (cancel_ == nullptr || !cancel_->load()) return false;
  if (error) *error = "the write of " + path_ + " was cancelled; the file there is as it was";
  discard();
  return true;
}

bool AtomicFileWriter::write(const void* data, std::size_t size, std::string* error) {
  if (cancelled(error) || !writeAt(written_, data, size, error)) return false;
  written_ += size;
  if (written_ - started_ >= kWriteBehindBytes) writeBehind();
  return true;
}

void AtomicFileWriter::writeBehind() {
  // Start writing the newest piece to disk, then wait for the piece before it and drop it from the page
  // cache. At most two pieces are ever dirty, so the final fsync has little left to flush and other
  // processes' disk work never waits behind the whole file: a 1.2 GB save flushed at once by fsync
  // stalled a small write-and-rename elsewhere on the disk for up to 1.2 s.
  // An error is kept for commit(): since Linux 4.14 the call that reports a writeback error (EIO) also
  // clears it, so the final fsync would succeed on a file with lost pages.
  keepError(::sync_file_range(fd_, static_cast<off_t>(started_), static_cast<off_t>(written_ - started_),
                              SYNC_FILE_RANGE_WRITE));
  if (started_ > settled_) {
    const auto begin = static_cast<off_t>(settled_), length = static_cast<off_t>(started_ - settled_);
    keepError(::sync_file_range(fd_, begin, length,
                                SYNC_FILE_RANGE_WAIT_BEFORE | SYNC_FILE_RANGE_WRITE | SYNC_FILE_RANGE_WAIT_AFTER));
    ::posix_fadvise(fd_, begin, length, POSIX_FADV_DONTNEED);
  }
  settled_ = started_;
  started_ = written_;
}

void AtomicFileWriter::keepError(int result) {
  // ENOSYS, EINVAL and ESPIPE say that sync_file_range is not supported here (a kernel or a file system
  // without it): nothing was lost, and commit's fsync does the work.
  if (result == 0 || write_behind_error_ != 0 || errno == ENOSYS || errno == EINVAL || errno == ESPIPE) return;
  write_behind_error_ = errno;
}

bool AtomicFileWriter::writeAt(std::size_t offset, const void* data, std::size_t size, std::string* error) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  while (size > 0) {
    const ssize_t n = ::pwrite(fd_, p, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const bool ok = fail(error, "cannot write " + temporary_);
      discard();
      return ok;
    }
    p += n;
    offset += static_cast<std::size_t>(n);
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

bool AtomicFileWriter::commit(std::string* error) {
  if (fd_ < 0) {
    if (error) *error = "nothing to commit for " + path_;
    return false;
  }
  if (cancelled(error)) return false;
  if (write_behind_error_ != 0) {
    errno = write_behind_error_;
    const bool ok = fail(error, "cannot write " + temporary_ + " to disk");
    discard();
    return ok;
  }
  if (::fsync(fd_) != 0) {
    const bool ok = fail(error, "cannot flush " + temporary_);
    discard();
    return ok;
  }
  if (!backup_.empty() && !linkBackup(path_, backup_, error)) {
    discard();
    return false;
  }
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const bool ok = fail(error, "cannot rename " + temporary_ + " to " + path_);
    discard();
    return ok;
  }
  temporary_.clear();
  ::close(fd_);  // after the rename, so the temporary file is locked as long as it exists; flushed already
  fd_ = -1;
  const int dir = ::open(directoryOf(path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  return true;
}

namespace {

/// Whether `name` is `base` + ".tmp." + the six letters or digits mkstemp adds.
bool isTemporaryOf(const std::string& name, const std::string& base) {
  const std::string prefix = base + ".tmp.";
  if (name.size() != prefix.size() + 6 || name.compare(0, prefix.size(), prefix) != 0) return false;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; });
}

}  // namespace

std::vector<AbandonedFile> removeAbandonedTemporaries(const std::string& path) {
  std::vector<AbandonedFile> removed;
  const std::string directory = directoryOf(path);
  const std::size_t slash = path.rfind('/');
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  DIR* dir = ::opendir(directory.c_str());
  if (!dir) return removed;
  const std::string prefix = directory == "/" ? "/" : directory + "/";
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (!isTemporaryOf(name, base) && !isTemporaryOf(name, base + ".bak")) continue;
    const std::string file = prefix + name;
    struct stat st;
    if (::lstat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) continue;
    const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    // A writer alive holds its lock until its rename; one that died left the file unlocked.
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::unlink(file.c_str()) == 0) {
      removed.push_back({file, static_cast<std::size_t>(st.st_size)});
    }
    ::close(fd);
  }
  ::closedir(dir);
  return removed;
}

}  // namespace scan_context_loop
