// The keyframe database: descriptors, an incremental FLANN kd-tree over ring keys, exclusion rules.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/block_arena.h"
#include "scan_context_loop/core/chunked_log.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/descriptor.h"
#include "scan_context_loop/core/odometry_trust.h"

namespace scan_context_loop {

/// What the caller knows about a keyframe besides its cloud.
struct KeyframeInfo {
  double stamp = 0.0;                     ///< seconds; must not decrease from one keyframe to the next
  std::optional<Eigen::Isometry3d> pose;  ///< odometry pose of the sensor, if known
  std::int64_t tag = -1;                  ///< free for the caller (e.g. a sequence frame index)
};

/// One scored candidate.
struct Candidate {
  std::size_t index = 0;           ///< keyframe number in the database, 0-based in arrival order
  double ring_key_distance = 0.0;  ///< Euclidean distance between the ring keys
  Alignment alignment;             ///< full descriptor distance, shift and yaw prior
  /// The virtual viewpoint (query frame) it was scored from; zero for the real one (see LoopDetector).
  Eigen::Vector2d viewpoint = Eigen::Vector2d::Zero();
};

struct QueryResult {
  /// Scored candidates, best (lowest distance) first; at most Config::num_candidates.
  std::vector<Candidate> candidates;
  /// True when the best candidate's distance is below Config::distance_threshold.
  bool matched = false;
  /// Number of keyframes that were eligible (outside every exclusion window).
  std::size_t eligible = 0;

  const Candidate* best() const { return candidates.empty() ? nullptr : &candidates.front(); }
};

/// A stored keyframe.
struct Keyframe {
  KeyframeInfo info;
  Descriptor descriptor;
  double path_length = 0.0;  ///< odometry distance travelled up to this keyframe in its session [m]
  /// The session it was recorded in (0, 1, ...): a run of keyframes with one odometry frame and
  /// non-decreasing stamps. Poses, stamps and path lengths compare only within a session.
  std::uint32_t session = 0;
  /// Its pose is a backend's corrected pose (a database file saved with corrections, pose_corrections.h),
  /// in the frame of its session's other poses, not the odometry's; a save writes it so again.
  bool corrected_pose = false;
};

/// Not thread-safe: one owner thread (the ROS adapter's worker) calls every member. The kd-tree is
/// rebuilt on a thread the database owns (joined by the destructor), over a copy of the keys, while the
/// owner's queries use the previous index and scan the keys added since; see Tree in database.cpp.
///
/// Keyframes enter the ring-key index the moment they leave the exclusion windows (all three rules are
/// monotonic in arrival order, so the eligible keyframes are always a prefix of the database). The index
/// is a FLANN kd-tree plus a brute-force tail of the keys added since its last build (see Tree in
/// database.cpp), so there is no window in which recent keyframes are unsearchable. Search is exact up to
/// Config::exact_search_limit searchable keyframes and approximate, at a bounded cost, above it.
class Database {
 public:
  explicit Database(const Config& config);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  /// Appends a keyframe to the current session. Returns false and leaves the database unchanged when the
  /// stamp is earlier than the session's last keyframe's, the stamp or pose is not finite, the pose's
  /// rotation is not one (R^T R off the identity by more than 1e-3, or a mirror), or the descriptor's
  /// grid size differs from the configuration or it holds a non-finite value; `error` then says why.
  bool add(const KeyframeInfo& info, Descriptor descriptor, std::string* error = nullptr);

  /// Scores the nearest ring keys among the eligible keyframes for a query that has not been added yet
  /// (its stamp and pose decide the time and distance windows). An empty descriptor, or one add() would
  /// refuse, never matches.
  QueryResult query(const Descriptor& descriptor, const KeyframeInfo& info);

  /// Checks a new keyframe's info against the last one without changing anything.
  bool acceptable(const KeyframeInfo& info, std::string* error) const;

  /// Keyframes added from now on form a new session (a bag played again, a restarted odometry, another
  /// day): their stamps, poses and path lengths start afresh, the exclusion windows apply within the
  /// session only, and every keyframe of the earlier sessions is a candidate, never gated by odometry.
  /// Does nothing while the current session is empty.
  void startSession();
  /// Appends keyframes recorded elsewhere (a saved database, database_file.h) as earlier sessions, then
  /// starts a new session for the keyframes added from now on. Their `session` fields number their own
  /// sessions 0, 1, ... in order (each keyframe's is its predecessor's or one more). They are renumbered
  /// to follow this database's sessions: the first joins as session() + 1, or as session() when the
  /// current session is still empty (so an empty database keeps their numbers). Like every earlier
  /// session they are candidates at once, never gated by odometry; they enter the kd-tree now. Returns
  /// false and changes nothing when a descriptor does not fit the configuration, the session numbers
  /// are not as above, or a keyframe breaks what add() checks within its session (finite stamps and
  /// poses that are rotations, stamps that never decrease, finite descriptors); `error` then names the keyframe and the
  /// problem.
  ///
  /// With `values_checked` (PriorSessions::descriptors_checked: a database file's reader has checked each
  /// descriptor's values, descriptorImplausibility) the descriptors' grid sizes are checked but not their
  /// values again. A batch above Config::exact_search_limit keys has its kd-tree built on the database's
  /// thread; queries scan its keys meanwhile (see Tree in database.cpp).
  bool appendSessions(std::vector<Keyframe> keyframes, std::string* error = nullptr, bool values_checked = false);
  /// The current session's number, and its first keyframe.
  std::uint32_t session() const { return session_; }
  std::size_t sessionStart() const { return session_start_; }
  /// Whether keyframes a and b were recorded in one session (their odometry relates them).
  bool sameSession(std::size_t a, std::size_t b) const { return keyframe(a).session == keyframe(b).session; }

  std::size_t size() const { return keyframes_.size(); }
  /// Throws std::out_of_range past the end.
  const Keyframe& keyframe(std::size_t index) const;
  /// The keyframes [begin, end) (clamped) as they are now, readable on any thread while this database
  /// goes on adding (stored keyframes never change; the view shares the chunks of their addresses).
  ChunkedLog<const Keyframe*>::View keyframesView(std::size_t begin, std::size_t end) const {
    return keyframes_.view(begin, end);
  }
  const Config& config() const { return config_; }
  /// Takes new values of the live settings (Setting::live; KeyframePipeline::reconfigure checks that
  /// nothing else changed).
  void reconfigure(const Config& config) { config_ = config; }
  /// Keyframes currently in the kd-tree.
  std::size_t indexedCount() const { return indexed_; }
  /// How the kd-tree has been rebuilt so far.
  struct IndexBuilds {
    std::size_t background = 0;      ///< builds started on the database's thread
    std::size_t waited = 0;          ///< of those, swapped in only after the owner waited for the thread
    std::size_t at_once = 0;         ///< built on the owner's thread: a batch of keys within the exact limit
    std::size_t batches_behind = 0;  ///< of the background builds, a larger batch's (appendSessions): the
                                     ///< owner scanned its keys until the build was done
    bool in_flight = false;          ///< a build has started and is not swapped in yet
    bool finished = true;            ///< no build is running (one in flight may have finished, not swapped in)
  };
  IndexBuilds indexBuilds() const;
  /// Approximate memory per keyframe: descriptor, keys, bookkeeping and kd-tree share, the keys and
  /// kd-tree counted twice (a rebuild in flight holds a second copy; between builds, the copy the last
  /// one replaced waits for the next build's thread to free it).
  std::size_t bytesPerKeyframe() const;
  /// A confirmed loop T_query<-match = `relative`: the odometry checks trust the odometry from it on
  /// (odometry_trust.h).
  void addConfirmedLoop(std::size_t query, std::size_t match, const Eigen::Isometry3d& relative) {
    trust_.add(keyframe(query), keyframe(match), relative, config_);
  }
  const OdometryTrust& odometryTrust() const { return trust_; }

 private:
  /// Number of keyframes (a prefix) eligible for a query with this info.
  std::size_t eligibleCount(const KeyframeInfo& info) const;
  double pathLengthAt(const KeyframeInfo& info) const;
  /// Config::gate_odometry_distance / gate_odometry_drift: whether keyframe `index` may be a candidate
  /// of a query with this info and odometry path `path`.
  bool withinOdometryGate(const KeyframeInfo& info, double path, std::size_t index) const;
  void indexUpTo(std::size_t count);

  Config config_;
  // The keyframe records (their descriptors' arrays live elsewhere) in large blocks on huge pages: a new
  // process joining 100,000 loaded keyframes takes a few page faults for them instead of thousands.
  BlockArena::Handle records_ = BlockArena::create(std::size_t(32) << 20);
  // Each record is placed once in records_ and never moves; their addresses, in database order, are in
  // chunks a snapshot shares (keyframesView). A std::deque held the records before: its map, a pointer
  // a keyframe, was copied into new memory whenever it doubled (15-20 ms at 437k and 874k keyframes).
  ChunkedLog<const Keyframe*> keyframes_;
  /// Moves `keyframe` into records_.
  const Keyframe* place(Keyframe&& keyframe);
  std::size_t indexed_ = 0;
  std::uint32_t session_ = 0;
  std::size_t session_start_ = 0;  // index of the current session's first keyframe
  OdometryTrust trust_;
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace scan_context_loop
