// Makes chosen file-system calls fail, to test what a save leaves on disk when the disk does not do its
// part (EIO from a failing disk, EPERM from link on vfat, ...). file_faults.cpp defines link, rename and
// renameat2, fsync, fdatasync, sync_file_range and pwrite; each fails with the errno chosen for it and otherwise calls
// the C library's. Two ways in:
// - linked into a test binary: its definitions take precedence over the C library's for the calls the
//   project's shared libraries make, and the test chooses with FileFaults::fail;
// - preloaded into a node (LD_PRELOAD=libscl_file_faults.so): while the file that the environment
//   variable SCL_FILE_FAULTS names exists, each of its lines "<call> <errno name>" ("fsync EIO") makes
//   that call fail, and "<call> DELAY<ms>" makes it wait that long first (a slow disk).
#pragma once

#include <string>

namespace scan_context_loop {
namespace test {

class FileFaults {
 public:
  /// Every later call of `call` ("link", "rename", "fsync", "fdatasync" or "sync_file_range") fails
  /// with `error` (EIO, EPERM, ...) until clear().
  static void fail(const std::string& call, int error);
  /// Every call works again, and the counts start from 0.
  static void clear();
  /// How many calls of `call` failed since the last clear().
  static int failures(const std::string& call);
  /// The n-th call of `call` after the last clear() kills the process (SIGKILL), as a power cut would
  /// stop it there; 0: none.
  static void killAt(const std::string& call, int n);
  /// How many calls of `call` were made since the last clear() (renameat2 counts as "rename").
  static int calls(const std::string& call);
};

}  // namespace test
}  // namespace scan_context_loop
