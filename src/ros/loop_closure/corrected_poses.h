// The corrected keyframe poses a backend publishes (corrected_path, nav_msgs/Path): the callback keeps the
// newest path, the worker matches its poses to the keyframes this node recorded, by the ROS stamp each
// keyframe keeps in its tag (stored_keyframe.h), and keeps them beside the database (PoseCorrections) for
// the saves to write (DatabaseSnapshot::correctPoses).
//
// A path applies to one recorded session: the newest session that holds a keyframe at the first of the
// path's stamps naming a keyframe recorded here (a bag replayed makes a new session with the same stamps:
// the replay's, the one the backend is fed now, wins). Its poses replace that session's earlier
// corrections; poses at stamps that name a keyframe of another session, or no keyframe recorded here (as
// after a ~reset, which the backend does not see), are skipped and counted apart. Sessions loaded from a
// file are never corrected by a path (their poses are as the file gave them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <nav_msgs/Path.h>

#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/pose_corrections.h"
#include "loop_closure/node_counters.h"

namespace scan_context_loop {

/// offer() runs on a callback thread and locks mutex_, which guards pending_ and queued_; every other
/// member is the worker's (start() and the destructor too, before the worker starts and after it ended).
class CorrectedPoses {
 public:
  /// `counters` (corrected_keyframes, corrections_refused, corrections_unknown) must outlive this; `name`
  /// prefixes the logs.
  CorrectedPoses(const std::string& name, NodeCounters* counters) : name_(name), counters_(counters) {}

  /// Callback: keeps `path` as the newest (a path replaces the one still waiting). True when the worker has
  /// no task queued for it yet: the caller then queues one that calls applyNewest().
  bool offer(const nav_msgs::PathConstPtr& path);
  /// Worker: applies the newest path offered to the keyframes of `database`.
  void applyNewest(const Database& database);
  /// Worker: keyframes [first, database.size()) were loaded from a file: no path applies to their sessions.
  void loaded(const Database& database, std::size_t first);
  /// Worker: the database was emptied (~reset): every correction, and the frame, are forgotten.
  void reset();

  /// Worker: the corrections in force, shared with the snapshots being written (replaced, never changed);
  /// null while there are none.
  std::shared_ptr<const PoseCorrections> corrections() const { return corrections_; }
  /// Worker: how many paths changed the corrections so far (a save is due when it moved).
  std::size_t version() const { return version_; }
  /// Worker: the frame of the corrected poses (the first path's header.frame_id), empty before one.
  const std::string& frame() const { return frame_; }

 private:
  /// Indexes the keyframes recorded here that were added since the last call.
  void index(const Database& database);
  void apply(const nav_msgs::Path& path, const Database& database);
  /// Counts `count` refused poses (or one refused path), with a throttled error naming `why`.
  void refuse(std::size_t count, const std::string& why);
  /// Counts `count` poses at stamps that name no keyframe recorded here, with a throttled debug message.
  void unknown(std::size_t count);

  std::string name_;
  NodeCounters* counters_;

  std::mutex mutex_;  // guards pending_ and queued_
  nav_msgs::PathConstPtr pending_;
  bool queued_ = false;

  // The worker's.
  std::string frame_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_stamp_;   // recorded keyframes by stamp [ns]
  std::map<std::uint32_t, std::pair<std::size_t, std::size_t>> sessions_;  // recorded: [first, end) indices
  std::set<std::uint32_t> loaded_;                                         // sessions a file gave
  std::size_t indexed_ = 0;
  std::shared_ptr<const PoseCorrections> corrections_;
  std::size_t version_ = 0;
};

}  // namespace scan_context_loop
