// A directory's files replaced as one set: the new set is made in a fresh directory beside it, then the
// two directories change places in one step (renameat2 RENAME_EXCHANGE), so that a reader, or a process
// killed at any moment, sees the old set whole or the new set whole, never a mix. ROS-free.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "scan_context_loop/core/file_io.h"

namespace scan_context_loop {

/// Not copyable. Destroyed without a successful commit(), it removes what it made.
class DirectorySwap {
 public:
  DirectorySwap() = default;
  ~DirectorySwap();
  DirectorySwap(const DirectorySwap&) = delete;
  DirectorySwap& operator=(const DirectorySwap&) = delete;

  /// Makes the directory the new set of `directory` (an existing directory) is written into:
  /// `<directory>.tmp.XXXXXX`, locked (flock) while it exists, holding hard links to `directory`'s regular
  /// files other than `replaced` (the new set's names and what it drops), so that they stay. False, with
  /// the reason in *error, where that cannot be had: no room beside `directory`, a `directory` that holds
  /// other than regular files, a file system without hard links; the caller then replaces file by file.
  bool open(const std::string& directory, const std::set<std::string>& replaced, std::string* error);
  /// Where the new set's files go.
  const std::string& staging() const { return staging_; }
  /// Flushes the new set's directory, puts it in `directory`'s place and removes the old set. On a file
  /// system that cannot exchange two directories (vfat, NFS) the new set's files are renamed into
  /// `directory` one by one instead (exchanged() is then false). False with *error when that fails.
  bool commit(std::string* error);
  /// Whether commit() swapped the directories (true) or moved the files one by one.
  bool exchanged() const { return exchanged_; }

 private:
  void discard();
  std::string directory_, staging_;
  int lock_ = -1;  // the staging directory, open and flock-ed
  std::set<std::string> replaced_;
  bool exchanged_ = false;
};

/// Removes what swaps of `directory` left when their process died: unlocked directories beside it named
/// `<directory>.tmp.XXXXXX` (a new set never swapped in, or the old set not yet removed), with the regular
/// files in them. Returns the files removed.
std::vector<AbandonedFile> removeAbandonedSwaps(const std::string& directory);

}  // namespace scan_context_loop
