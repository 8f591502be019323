// The node's own settings (ROS input, threading, publishing), ROS-free so that the evaluator knows
// their keys (settings.h) and accepts a node's configuration file.
#pragma once

#include <string>

namespace scan_context_loop {

/// Where keyframe poses come from: keyframe_odom messages, or tf lookups at the cloud's stamp.
enum class PoseSource { kOdom, kTf };
/// What the node does: find loops within and across sessions, or relocalize in a loaded map.
enum class NodeMode { kDetect, kRelocalize };

inline const char* poseSourceName(PoseSource s) { return s == PoseSource::kTf ? "tf" : "odom"; }
inline bool parsePoseSource(const std::string& text, PoseSource* out) {
  if (text != "odom" && text != "tf") return false;
  *out = text == "tf" ? PoseSource::kTf : PoseSource::kOdom;
  return true;
}
inline const char* nodeModeName(NodeMode m) { return m == NodeMode::kRelocalize ? "relocalize" : "detect"; }
inline bool parseNodeMode(const std::string& text, NodeMode* out) {
  if (text != "detect" && text != "relocalize") return false;
  *out = text == "relocalize" ? NodeMode::kRelocalize : NodeMode::kDetect;
  return true;
}

struct NodeOptions {
  PoseSource pose_source = PoseSource::kOdom;  ///< odom: keyframe_odom messages; tf: look the pose up
  std::string fixed_frame = "odom";            ///< tf mode: the frame poses are looked up in
  double tf_timeout = 0.1;                     ///< tf mode: how long to wait for a transform [s]
  std::string sensor_frame;                    ///< the sensor's tf frame (empty: the cloud's frame_id)
  /// Odometry whose child frame is not the sensor's: move the poses to the sensor with the extrinsic
  /// child <- sensor from tf (looked up without waiting; keyframes wait for it a few seconds, then a
  /// warning names both frames and the poses are used as they are).
  bool sensor_extrinsic_from_tf = true;
  bool approximate_sync = true;  ///< approximate (true) or exact time synchronisation
  int sync_queue_size = 20;      ///< message_filters queue per input
  int queue_size = 20;           ///< keyframes waiting for the worker; more are dropped and counted
  /// Keyframes between reads of malloc's statistics for the diagnostics (on the worker, when its queue
  /// is empty; glibc's mallinfo2 walks the whole heap); 0 never.
  int heap_statistics_interval = 1000;
  bool lio_sam_output = false;          ///< also publish std_msgs/Float64MultiArray [query, match stamps]
  double lio_sam_min_interval = 1.0;    ///< lio_loop: at most one message per this many seconds
  double unsynchronised_warning = 5.0;  ///< warn when clouds come without poses for this long [s]
  /// Warn, naming the topic, when no cloud (or, with pose_source odom, no odometry) has arrived for this
  /// long since the start or the last one [s].
  double no_input_warning = 10.0;
  /// "detect": loops within and across sessions; "relocalize": a prior map (database_load) read-only,
  /// each keyframe's verified place in it published on `relocalization` (sets prior_sessions_only).
  NodeMode mode = NodeMode::kDetect;
  std::string map_frame = "map";  ///< relocalize: the frame of the loaded map's poses
  std::string database_load;      ///< a database file loaded at start as prior sessions ("": none)
  std::string database_save;      ///< the database saved here at shutdown ("": not saved)
  /// With database_save: a file already there that this run did not load (database_load empty, misspelt
  /// or another file) is replaced only when true; else this run's database is saved beside it.
  bool database_save_overwrite = false;
  bool database_save_clouds = true;  ///< saves include the registration clouds (needed to verify later)
  /// With database_save: the database is also written there every this many seconds (wall time) while
  /// it changes, on a thread of its own, so a crash loses at most that much; 0 saves at shutdown only.
  double database_autosave_seconds = 300.0;
  /// The shutdown save, with the autosave in progress, takes at most this long; what does not fit is
  /// cancelled, the file at database_save stays as the last save left it, and the log says what is lost [s].
  double database_shutdown_seconds = 10.0;
  /// The map directory ~save_database writes in ("": that of database_save, else of database_load, else
  /// $ROS_HOME/scan_context_loop).
  std::string database_directory;
  /// Several robots (doc/multi_robot.md): this robot's id, [A-Za-z0-9_]+ starting with a letter ("": no team). With
  /// one, the node shares its keyframes with the other robots' nodes and finds loops into theirs.
  std::string robot_id;
  /// The namespace the team's nodes share: its keyframe_records and members topics.
  std::string team_namespace = "/team";
  /// What the node sends to the team (records, and the records and registration data it serves), at most
  /// this many bytes a second on average [B/s]; records over it are not published live (the others fetch
  /// them later) and requests over it are answered busy.
  double team_max_bytes_per_second = 1e6;
  /// How long a request to another robot's node may take before it counts as failed [s]; a node that lets
  /// one time out is asked nothing for 30 s.
  double team_request_timeout = 2.0;
  /// Memory the other robots' keyframe records may take [bytes]: records past it are refused and counted
  /// (their registration data, fetched on demand, live in the cloud store under verify_max_bytes).
  double team_max_bytes = 268435456.0;
};

}  // namespace scan_context_loop
