// The fault interposer of file_faults.h: link, rename, fsync, fdatasync and sync_file_range, each
// failing when FileFaults or the SCL_FILE_FAULTS file says so, else passed to the next definition
// (the C library's), found with dlsym(RTLD_NEXT).
#include "file_faults.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace scan_context_loop {
namespace test {
namespace {

enum Call { kLink, kRename, kFsync, kFdatasync, kSyncFileRange, kPwrite, kCalls };
const char* const kCallNames[kCalls] = {"link", "rename", "fsync", "fdatasync", "sync_file_range", "pwrite"};

// Atomic: the calls come from any thread (a save runs on a writer thread of its own).
std::atomic<int> chosen[kCalls];
std::atomic<int> failed[kCalls];
std::atomic<int> made[kCalls];     // calls since the last clear()
std::atomic<int> kill_at[kCalls];  // the call (counted in made) that kills the process; 0: none

Call callNamed(const std::string& name) {
  for (int c = 0; c < kCalls; ++c) {
    if (name == kCallNames[c]) return static_cast<Call>(c);
  }
  throw std::invalid_argument("FileFaults: no fault for a call named " + name);
}

/// The errno names a fault file may give (a table: strerrorname_np is glibc 2.32's, newer than Ubuntu
/// 20.04's).
struct ErrnoName {
  const char* name;
  int value;
};
const ErrnoName kErrnoNames[] = {
    {"EIO", EIO},       {"ENOSPC", ENOSPC}, {"EDQUOT", EDQUOT},         {"EROFS", EROFS},
    {"EPERM", EPERM},   {"EACCES", EACCES}, {"EOPNOTSUPP", EOPNOTSUPP}, {"EXDEV", EXDEV},
    {"EMLINK", EMLINK}, {"ENOSYS", ENOSYS}, {"EINVAL", EINVAL},         {"ESPIPE", ESPIPE}};

/// The errno that the SCL_FILE_FAULTS file chooses for `call` (a name of kErrnoNames, such as
/// EIO), 0 when there is no such file or no line for it; for "DELAY<ms>" (a slow disk: the call
/// waits, then works), minus the milliseconds. Read at every call, so that a test starts and ends the
/// fault by writing and removing the file.
int chosenByFile(Call call) {
  const char* path = std::getenv("SCL_FILE_FAULTS");
  if (!path || !*path) return 0;
  FILE* file = std::fopen(path, "re");
  if (!file) return 0;
  int chosen_errno = 0;
  char name[64], error[64];
  while (chosen_errno == 0 && std::fscanf(file, "%63s %63s", name, error) == 2) {
    if (std::strcmp(name, kCallNames[call]) != 0) continue;
    if (std::strncmp(error, "DELAY", 5) == 0) chosen_errno = -std::max(1, std::atoi(error + 5));
    for (const auto& known : kErrnoNames) {
      if (chosen_errno == 0 && std::strcmp(known.name, error) == 0) chosen_errno = known.value;
    }
  }
  std::fclose(file);
  return chosen_errno;
}

/// True, with errno set, when `call` is to fail now.
bool injected(Call call) {
  if (const int n = ++made[call]; kill_at[call] > 0 && n == kill_at[call]) ::raise(SIGKILL);
  const int saved = errno;
  int error = chosen[call].load();
  if (error == 0) error = chosenByFile(call);
  if (error < 0) ::usleep(static_cast<useconds_t>(-error) * 1000u);  // slow, then as usual
  if (error <= 0) {
    errno = saved;
    return false;
  }
  ++failed[call];
  errno = error;
  return true;
}

template <typename Function>
Function* next(const char* name) {
  return reinterpret_cast<Function*>(::dlsym(RTLD_NEXT, name));
}

}  // namespace

void FileFaults::fail(const std::string& call, int error) { chosen[callNamed(call)] = error; }

void FileFaults::clear() {
  for (int c = 0; c < kCalls; ++c) chosen[c] = failed[c] = made[c] = kill_at[c] = 0;
}

int FileFaults::failures(const std::string& call) { return failed[callNamed(call)].load(); }

void FileFaults::killAt(const std::string& call, int n) { kill_at[callNamed(call)] = n; }

int FileFaults::calls(const std::string& call) { return made[callNamed(call)].load(); }

}  // namespace test
}  // namespace scan_context_loop

using scan_context_loop::test::injected;
using scan_context_loop::test::next;

// The C library's declarations, exception specifications included (link and rename are __THROW).
extern "C" {

int link(const char* from, const char* to) __THROW {
  static auto* real = next<int(const char*, const char*)>("link");
  return injected(scan_context_loop::test::kLink) ? -1 : real(from, to);
}

int rename(const char* from, const char* to) __THROW {
  static auto* real = next<int(const char*, const char*)>("rename");
  return injected(scan_context_loop::test::kRename) ? -1 : real(from, to);
}

// A rename too (a directory exchange), counted and failed as "rename".
int renameat2(int from_dir, const char* from, int to_dir, const char* to, unsigned int flags) __THROW {
  static auto* real = next<int(int, const char*, int, const char*, unsigned int)>("renameat2");
  return injected(scan_context_loop::test::kRename) ? -1 : real(from_dir, from, to_dir, to, flags);
}

int fsync(int fd) {
  static auto* real = next<int(int)>("fsync");
  return injected(scan_context_loop::test::kFsync) ? -1 : real(fd);
}

int fdatasync(int fd) {
  static auto* real = next<int(int)>("fdatasync");
  return injected(scan_context_loop::test::kFdatasync) ? -1 : real(fd);
}

ssize_t pwrite(int fd, const void* data, size_t size, off_t offset) {
  static auto* real = next<ssize_t(int, const void*, size_t, off_t)>("pwrite");
  return injected(scan_context_loop::test::kPwrite) ? -1 : real(fd, data, size, offset);
}

int sync_file_range(int fd, __off64_t offset, __off64_t count, unsigned int flags) {
  static auto* real = next<int(int, __off64_t, __off64_t, unsigned int)>("sync_file_range");
  return injected(scan_context_loop::test::kSyncFileRange) ? -1 : real(fd, offset, count, flags);
}

}  // extern "C"
