#include "scan_context_loop/graph/map_set.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace scan_context_loop {

namespace {

bool failed(std::string* error, const std::string& what) {
  if (error) *error = what + ": " + std::strerror(errno);
  return false;
}

std::string withoutTrailingSlashes(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

/// The names in `directory` (not . and ..); false when it cannot be read.
bool namesIn(const std::string& directory, std::vector<std::string>* names) {
  DIR* dir = ::opendir(directory.c_str());
  if (!dir) return false;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") names->push_back(name);
  }
  ::closedir(dir);
  return true;
}

/// Removes `directory`'s regular files (appended to *removed with their sizes) and then it.
void removeFlat(const std::string& directory, std::vector<AbandonedFile>* removed) {
  std::vector<std::string> names;
  namesIn(directory, &names);
  for (const std::string& name : names) {
    const std::string path = directory + "/" + name;
    struct stat st;
    if (::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::unlink(path.c_str()) == 0 && removed) {
      removed->push_back({path, static_cast<std::size_t>(st.st_size)});
    }
  }
  ::rmdir(directory.c_str());
}

void syncDirectory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

DirectorySwap::~DirectorySwap() { discard(); }

void DirectorySwap::discard() {
  if (!staging_.empty()) removeFlat(staging_, nullptr);
  if (lock_ >= 0) ::close(lock_);
  lock_ = -1;
  staging_.clear();
}

bool DirectorySwap::open(const std::string& directory, const std::set<std::string>& replaced, std::string* error) {
  discard();
  directory_ = withoutTrailingSlashes(directory);
  replaced_ = replaced;
  std::vector<std::string> names;
  if (!namesIn(directory_, &names)) return failed(error, "cannot read " + directory_);
  for (const std::string& name : names) {
    struct stat st;
    if (::lstat((directory_ + "/" + name).c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
      if (error) *error = directory_ + "/" + name + " is not a regular file";
      return false;
    }
  }
  std::string name = directory_ + ".tmp.XXXXXX";
  if (!::mkdtemp(&name[0])) return failed(error, "cannot create a directory beside " + directory_);
  staging_ = name;
  lock_ = ::open(staging_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lock_ < 0 || ::flock(lock_, LOCK_EX | LOCK_NB) != 0) {
    const bool ok = failed(error, "cannot lock " + staging_);
    discard();
    return ok;
  }
  ::fchmod(lock_, 0755);  // mkdtemp makes it private; the map directory is an ordinary one
  struct stat st;
  if (::stat(directory_.c_str(), &st) == 0) ::fchmod(lock_, st.st_mode & 07777);
  for (const std::string& kept : names) {
    if (replaced.count(kept)) continue;
    if (::link((directory_ + "/" + kept).c_str(), (staging_ + "/" + kept).c_str()) != 0) {
      const bool ok = failed(error, "cannot keep " + directory_ + "/" + kept + " in the new set");
      discard();
      return ok;
    }
  }
  return true;
}

bool DirectorySwap::commit(std::string* error) {
  if (staging_.empty()) {
    if (error) *error = "nothing to swap in for " + directory_;
    return false;
  }
  syncDirectory(staging_);  // the new set's names are on disk before they become the directory's
  exchanged_ = ::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, directory_.c_str(), RENAME_EXCHANGE) == 0;
  if (!exchanged_) {
    if (errno != EINVAL && errno != ENOTSUP && errno != EOPNOTSUPP && errno != ENOSYS) {
      const bool ok = failed(error, "cannot exchange " + staging_ + " and " + directory_);
      discard();
      return ok;
    }
    // No exchange here: each file renamed over its old one (whole files, not a whole set).
    for (const std::string& name : replaced_) {
      const std::string from = staging_ + "/" + name;
      if (::access(from.c_str(), F_OK) != 0) continue;
      if (::rename(from.c_str(), (directory_ + "/" + name).c_str()) != 0) {
        const bool ok = failed(error, "cannot rename " + from + " into " + directory_);
        discard();
        return ok;
      }
    }
    syncDirectory(directory_);
    discard();
    return true;
  }
  // The staging name now holds the old set.
  syncDirectory(directory_.find('/') == std::string::npos ? "." : directoryOf(directory_));
  const std::string old = staging_;
  staging_.clear();
  removeFlat(old, nullptr);
  if (lock_ >= 0) ::close(lock_);
  lock_ = -1;
  return true;
}

std::vector<AbandonedFile> removeAbandonedSwaps(const std::string& directory) {
  std::vector<AbandonedFile> removed;
  const std::string path = withoutTrailingSlashes(directory);
  const std::string parent = path.find('/') == std::string::npos ? "." : directoryOf(path);
  const std::size_t slash = path.rfind('/');
  const std::string prefix = (slash == std::string::npos ? path : path.substr(slash + 1)) + ".tmp.";
  std::vector<std::string> names;
  if (!namesIn(parent, &names)) return removed;
  for (const std::string& name : names) {
    if (name.size() != prefix.size() + 6 || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string candidate = (parent == "/" ? "" : parent) + "/" + name;
    struct stat st;
    if (::lstat(candidate.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid()) continue;
    const int fd = ::open(candidate.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) removeFlat(candidate, &removed);  // a live swap holds its lock
    ::close(fd);
  }
  return removed;
}

}  // namespace scan_context_loop
