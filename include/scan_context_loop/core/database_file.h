// The database file: a detector's keyframes (descriptors, stamps, poses, tags, path lengths, sessions)
// and optionally their gravity alignment and registration data, saved for a later run to start from. The
// layout, its version and its checks are in doc/database_file.md.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/core/file_io.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/pose_corrections.h"
#include "scan_context_loop/core/prior_sessions.h"

namespace scan_context_loop {

/// The format version this build writes. It changes whenever the layout or the way descriptors are
/// computed changes. Version 1 files (unit columns as f32) are still read, their columns quantised as
/// they are read.
constexpr std::uint32_t kDatabaseFileVersion = 2;

struct SaveOptions {
  /// Also save each keyframe's gravity alignment rotation and registration data (the cloud store's
  /// VoxelClouds, LZ4-compressed), so that loaded keyframes can be verified. Without them a loaded
  /// keyframe is a candidate that verification reports as unverifiable.
  bool include_clouds = false;
  /// The file replaced (if any) is kept as `<path>.bak`, itself replaced atomically.
  bool keep_backup = false;
};

/// What a save writes, taken in a moment on the detector's thread and written later on any thread while
/// the detector goes on (a save that never holds up detection). Stored keyframes never change and only
/// new ones are appended, so the snapshot shares the chunks holding their addresses and gravity
/// alignments (ChunkedLog: appending goes on beside it, and a changed alignment is copied first) and the
/// registration data of the stored keyframes (CloudStore::share), which a later halving of the store
/// cannot free under it. Taking one costs a share per 2 MB chunk and per stored cloud, whatever the
/// database's size (a million keyframes: about twenty chunk shares plus the clouds the store holds).
///
/// The keyframes must live until the snapshot is written: either the caller keeps the detector alive, or
/// `owner` (a share of whatever owns the detector) does, so that replacing the detector (a reset) while a
/// snapshot of it is being written frees it only after the write.
class DatabaseSnapshot {
 public:
  DatabaseSnapshot() = default;
  DatabaseSnapshot(const LoopDetector& detector, bool include_clouds, std::shared_ptr<const void> owner = nullptr);
  /// Of the `count` keyframes from `first` only (clamped to the database), numbered afresh in the image as a
  /// file would number them (sessions from 0): one keyframe as a robot of a team shares it (team_matcher.h).
  DatabaseSnapshot(const LoopDetector& detector, bool include_clouds, std::shared_ptr<const void> owner,
                   std::size_t first, std::size_t count);

  std::size_t size() const { return keyframes_.size(); }
  bool includesClouds() const { return include_clouds_; }
  /// The write stores, for every session holding one of `corrections`, the corrected poses
  /// (correctedSessionPoses, computed by the write, not here) marked as corrected in the file; other
  /// sessions as they are. Shared, not copied: the caller replaces its table rather than changing it.
  void correctPoses(std::shared_ptr<const PoseCorrections> corrections) { corrections_ = std::move(corrections); }
  /// From now on holds its registration data weakly, for a snapshot kept long (the keyframes a robot of a
  /// team serves): a cloud the detector's store drops to stay within verify_max_bytes is freed all the
  /// same. Write strengthened() instead of this snapshot.
  void holdCloudsWeakly();
  /// A snapshot holding again the registration data still alive; *complete false when any was freed.
  DatabaseSnapshot strengthened(bool* complete) const;

 private:
  template <typename Sink>
  friend bool writeImage(const DatabaseSnapshot& snapshot, Sink* sink, std::string* error);
  Config config_;
  bool include_clouds_ = false;
  ChunkedLog<const Keyframe*>::View keyframes_;
  ChunkedLog<Eigen::Matrix3f>::View gravity_alignment_;  // with clouds: per keyframe
  // With clouds: the stored keyframes' data, by index in the snapshot, in order.
  std::vector<std::pair<std::size_t, std::shared_ptr<const VoxelCloud>>> clouds_;
  std::vector<std::pair<std::size_t, std::weak_ptr<const VoxelCloud>>> weak_clouds_;  // holdCloudsWeakly
  std::shared_ptr<const void> owner_;
  std::shared_ptr<const PoseCorrections> corrections_;  // null: none
};

/// Writes `snapshot` to `path` atomically, as saveDatabase does; `keep_backup` as SaveOptions::keep_backup.
/// Two writes to one path must not run at once (DatabaseWriter serialises them). Once `*cancel` is set the
/// write stops, leaving `path` as it was (AtomicFileWriter::cancelWhen).
bool writeDatabase(const DatabaseSnapshot& snapshot, const std::string& path, bool keep_backup, std::string* error,
                   const std::atomic<bool>* cancel = nullptr);

/// The bytes writeDatabase would write for `snapshot`, in memory (a small snapshot: a keyframe or a few).
std::vector<std::uint8_t> encodeDatabase(const DatabaseSnapshot& snapshot);

/// The settings a database (or a keyframe a robot shares) must agree on with the configuration that reads
/// it, as `key value` pairs separated by ", " in a fixed order (with `include_clouds`, the registration
/// data's voxel settings too): two configurations whose texts differ cannot compare keyframes.
std::string compatibilityText(const Config& config, bool include_clouds);

/// Writes every keyframe of `detector` to `path` atomically (AtomicFileWriter): a temporary file in
/// the same directory, flushed to disk, renamed over `path`; a file replaced keeps its mode. A file at
/// `path` that is not empty and does not begin with the database magic is never replaced. On failure,
/// `error` says why and an existing file at `path` is left as it was.
bool saveDatabase(const LoopDetector& detector, const std::string& path, const SaveOptions& options,
                  std::string* error);

/// Reads and checks the file at `path` against `config` without changing anything: magic, version,
/// header and payload checksums, size (truncation), the descriptor settings (and, with registration
/// data, the verification voxel settings) against `config`'s, counts and sizes (each bounded before
/// memory is set aside for it), values finite and such as a scan makes. A path that is not a regular
/// file (a FIFO, a socket, a device, a directory) is refused without blocking. Fills *sessions, or
/// returns false with `error` naming the path and the problem.
bool readDatabaseFile(const std::string& path, const Config& config, PriorSessions* sessions, std::string* error);

/// readDatabaseFile's parser and checks over any ByteSource (a file's bytes in memory: MemoryReader);
/// `name` stands for the path in errors.
bool readDatabase(ByteSource* source, const std::string& name, const Config& config, PriorSessions* sessions,
                  std::string* error);

/// readDatabaseFile, then appendSessions: the saved keyframes join after the current ones as earlier
/// sessions, and keyframes from now on form a new session. On any error nothing changes.
bool loadDatabase(const std::string& path, LoopDetector* detector, std::string* error);
bool loadDatabase(const std::string& path, KeyframePipeline* pipeline, std::string* error);

}  // namespace scan_context_loop
