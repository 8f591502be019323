// The ROS adapter: subscribes to keyframe clouds and poses, runs the core detector on a worker thread
// and publishes loop-closure constraints, RViz markers and diagnostics. This class wires the parts
// together and owns them; each lives in its own file:
//   keyframe_input      subscriptions, synchronisation, the callbacks that queue keyframes, input checks
//   keyframe_queue      the worker's inbox (keyframes, service tasks, redraws, stop) and its lock
//   keyframe_worker     the worker thread: jobs in order behind the barrier; a keyframe goes
//                       source -> processor -> output
//   keyframe_source     the keyframe's pose (odometry or tf, the extrinsic), keyframes held for tf
//   keyframe_processor  one keyframe through the pipeline, which owns the database; the team's share
//   keyframe_timing     where a keyframe's time went (keyframe_timing)
//   node_output         every publisher: the selected keyframes (keyframe_publisher), the loops,
//                       rejections, lio_loop, relocalization (loop_publisher), the markers
//                       (marker_publisher), the timing
//   node_counters, node_diagnostics   the counters and the diagnostic task that reports them
//   database_services.cpp             the save / load / reset / relocalize services
//   database_saving.cpp               where saves go, the autosave and the shutdown save
//   database_paths      where saves may write (the map directory), the file beside a kept map
//   corrected_poses     a backend's corrected keyframe poses (corrected_path), kept for the saves
//   team_exchange, team_worker   several robots: keyframes shared with the team, loops into theirs
//
// Threads and locks:
//   - spinner threads run the input callbacks and timers, dynamic_reconfigure and the marker subscriber
//     callback; the services have a callback queue and a spinner thread of their own (a save waits for
//     its write there, never holding up the input callbacks); the worker thread runs every keyframe and
//     every service's work on the database; the writer's thread (DatabaseWriter) writes the snapshots the
//     worker takes, one write at a time (its own locks).
//   - KeyframeQueue's mutex guards the queue (keyframes, tasks, redraw and wake flags, stop).
//   - settings_mutex_ guards the settings dynamic_reconfigure accepted, on their way to the worker.
//   - reconfigure_mutex_ is dynamic_reconfigure's own (its Server's state).
//   - NodeCounters are atomics; the database, the markers' and loops' state and the held keyframes are
//     the worker's alone (the services reach them through tasks the worker runs).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "scan_context_loop/LoadDatabase.h"
#include "scan_context_loop/LoopClosureConfig.h"
#include "scan_context_loop/Relocalize.h"
#include "scan_context_loop/SaveDatabase.h"
#include "scan_context_loop/core/database_writer.h"
#include "loop_closure/corrected_poses.h"
#include "loop_closure/keyframe_input.h"
#include "loop_closure/keyframe_processor.h"
#include "loop_closure/keyframe_queue.h"
#include "loop_closure/keyframe_source.h"
#include "loop_closure/keyframe_worker.h"
#include "loop_closure/node_output.h"
#include "loop_closure/node_counters.h"
#include "loop_closure/node_diagnostics.h"
#include "shared/parameters.h"
#include "team/team_exchange.h"

namespace scan_context_loop {

class LoopClosureRos {
 public:
  /// `nh` resolves the topics (relative names), `pnh` the parameters; `name` prefixes the logs.
  LoopClosureRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name);
  /// Stops the worker (it finishes the keyframe in hand) and unsubscribes; never blocks for long.
  ~LoopClosureRos();

  /// Reads and validates the parameters, then subscribes, advertises and starts the worker. Returns
  /// false, having logged every problem as fatal, when the configuration is impossible.
  bool start();

 private:
  // Database services and relocalization (database_services.cpp), saving (database_saving.cpp). Each service hands its
  // work to the worker, which owns the database, and waits for it.
  bool onSave(scan_context_loop::SaveDatabase::Request& request, scan_context_loop::SaveDatabase::Response& response);
  bool onLoad(scan_context_loop::LoadDatabase::Request& request, scan_context_loop::LoadDatabase::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onRelocalize(scan_context_loop::Relocalize::Request& request, scan_context_loop::Relocalize::Response& response);
  /// Runs `task` on the worker between keyframes and waits for it; "" when it ran, else why not (the
  /// node is stopping, or it threw).
  std::string runOnWorker(std::function<void()> task);
  /// Loads a database file into the pipeline (worker, or start() before the worker runs); "" or why not.
  std::string loadFile(const std::string& path);
  /// Where this run's database is saved (worker, or after it ended): `database_save`, or a file beside
  /// it when that is a map this run's database does not hold: one that was there at start and not
  /// loaded (unless database_save_overwrite), one whose start-up load failed, or one a ~reset emptied
  /// (keep_reason_, reset_): the same file beside it all run, named in one warning.
  std::string saveTarget();
  /// start(), after database_load (`loaded`: it loaded): keeps a file at database_save that this run did
  /// not load, unless database_save_overwrite.
  void keepUnloadedSaveFile(bool loaded);
  /// Removes, with a warning, the temporary files that writes of `path` left when their process died.
  void removeAbandonedWrites(const std::string& path);
  /// The database to saveTarget() at shutdown, after the autosave in progress.
  void saveAtShutdown();
  /// Autosave timer: asks the worker for a snapshot, unless one is queued or still being written.
  void requestAutosave();
  /// Worker: hands a snapshot of the database, if it changed since the last save, to the writer.
  void autosave();
  /// Worker (or after it ended): what a save writes now, with the corrected poses (corrected_path) in force.
  DatabaseSnapshot takeSnapshot(bool include_clouds);
  void advertiseDatabaseServices();
  /// dynamic_reconfigure: checks the live settings and hands them to the worker (applied before its
  /// next keyframe); a refused change is logged and the values in force are reported back.
  void onReconfigure(scan_context_loop::LoopClosureConfig& values, std::uint32_t level);
  /// Worker: takes the settings onReconfigure accepted, if any.
  void takeReconfigured();

  ros::NodeHandle nh_, pnh_;
  std::string name_;
  // Set by start() and the worker; read by the destructor after the worker stopped. A file that a
  // save must not replace (the map whose start-up load failed, or a database_save file not loaded), and
  // why; after a ~reset, database_save's file is not replaced either.
  std::string kept_file_, keep_reason_;
  bool reset_ = false;
  // The worker's: the file beside database_save once saveTarget() chose one, and the ~resets so far.
  std::string beside_path_;
  std::size_t resets_ = 0;
  /// The database as a save saw it: its size, the ~resets and the corrections' version then.
  struct SavedState {
    std::size_t size = 0, resets = 0, corrections = 0;
    bool operator==(const SavedState& o) const {
      return size == o.size && resets == o.resets && corrections == o.corrections;
    }
  };
  // What the last autosave that succeeded wrote, so that an unchanged database is not written again and
  // a failed write is retried. Set by the writer's thread when a write lands, read by the worker.
  std::mutex saved_mutex_;
  SavedState saved_;
  // Read in start(); then config_ is the worker's, and options_ is read by callbacks too, so the worker
  // changes only its live members, which callbacks never read (takeReconfigured).
  Config config_;
  NodeOptions options_;
  NodeCounters counters_;

  // The parts, made in start() (none when the configuration was refused).
  std::unique_ptr<KeyframeQueue> queue_;
  std::unique_ptr<KeyframeSource> source_;
  std::unique_ptr<KeyframeProcessor> processor_;
  std::unique_ptr<LoopClosureOutput> output_;
  std::unique_ptr<KeyframeWorker> worker_;
  std::unique_ptr<KeyframeInput> input_;
  std::unique_ptr<NodeDiagnostics> diagnostics_;
  std::unique_ptr<CorrectedPoses> corrected_;
  std::unique_ptr<TeamExchange> team_;  // with robot_id: the exchange with the other robots' nodes

  // Set up in start(), used from callbacks (ROS handles are thread-safe).
  ros::ServiceServer save_srv_, load_srv_, reset_srv_, relocalize_srv_;
  ros::Subscriber corrected_sub_;                       // corrected_path (detect mode): queues a task for the worker
  ros::CallbackQueue service_queue_;                    // the services' (thread-safe)
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;  // its thread
  DatabaseWriter writer_;                               // thread-safe
  ros::WallTimer autosave_timer_;
  std::atomic<bool> autosave_queued_{false};  // an autosave task waits in the queue
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  boost::recursive_mutex reconfigure_mutex_;  // dynamic_reconfigure's own (guards its Server's state)
  std::unique_ptr<dynamic_reconfigure::Server<scan_context_loop::LoopClosureConfig>> reconfigure_server_;

  // settings_mutex_ guards the three below: dynamic_reconfigure's accepted settings (all keys; only live
  // ones ever differ from config_), and whether the worker has yet to take them.
  std::mutex settings_mutex_;
  Config live_config_;
  NodeOptions live_options_;
  bool reconfigured_ = false;
};

}  // namespace scan_context_loop
