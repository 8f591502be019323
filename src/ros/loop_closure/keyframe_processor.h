// One keyframe through the core's pipeline (selection, description, query, verification, the database):
// the cloud checked, the keyframe stored, the counters that follow the database, and the keyframe shared
// with the team. Publishing is the output's (node_output.h).
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "loop_closure/keyframe_source.h"
#include "loop_closure/keyframe_timing.h"
#include "loop_closure/node_counters.h"
#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/keyframes.h"
#include "scan_context_loop/core/node_options.h"
#include "team/team_exchange.h"

namespace scan_context_loop {

/// What became of one keyframe.
struct KeyframeResult {
  bool stored = false;  ///< it entered the database (else: not selected, or unusable, counted and logged)
  Detection detection;
  pcl::PointCloud<pcl::PointXYZ> described;  ///< its points as described, when they were asked for
};

/// Worker-only: it owns the pipeline and with it the database, which only the worker thread touches
/// (start() and the destructor too, before the worker starts and after it ended). No lock.
class KeyframeProcessor {
 public:
  /// `config` and `options` are the worker's settings; `name` prefixes the logs. All must outlive this.
  KeyframeProcessor(const std::string& name, const Config& config, const NodeOptions& options, NodeCounters* counters);
  ~KeyframeProcessor();

  /// Several robots: every keyframe stored is shared with the team and matched against its keyframes.
  /// `team` must outlive this.
  void useTeam(TeamExchange* team) { team_ = team; }
  bool hasTeam() const { return team_ != nullptr; }

  KeyframePipeline& pipeline() { return *pipeline_; }
  const Database& database() const { return pipeline_->detector().database(); }
  /// What a save writes, taken now (DatabaseSnapshot); it keeps this pipeline's keyframes alive until
  /// it is released, even past a resetPipeline(), so it may be written on another thread.
  DatabaseSnapshot snapshot(bool include_clouds) const {
    return DatabaseSnapshot(pipeline_->detector(), include_clouds, pipeline_);
  }
  /// An empty pipeline with the settings in force (reset); the old one lives on while a snapshot of it does.
  void resetPipeline();
  /// Keyframes entered the database beside process() (a load, or one whose processing threw): the
  /// counters follow the database and the team is told.
  void followDatabase();

  /// Runs `keyframe` through the pipeline (`clock` times the core), its points as described kept when
  /// `want_cloud` or a team needs them.
  KeyframeResult process(const PosedKeyframe& keyframe, bool want_cloud, KeyframeClock* clock);
  /// Shares the keyframe `result` stored (and any loaded before it) and hands it to the team's matching.
  void shareWithTeam(const PosedKeyframe& keyframe, KeyframeResult* result);

 private:
  /// The cloud store's counters; warns when it halved its density since the last call.
  void followCloudStore();
  /// The counters after a keyframe was stored; warns when it started a session.
  void countStored(const Detection& detection, double stamp);
  /// Warns (throttled) while gravity alignment finds the odometry's world frame tilted from gravity (world_tilt.h).
  void reportWorldTilt(const Detection& detection);

  std::string name_;
  const Config& config_;
  const NodeOptions& options_;
  NodeCounters* counters_;
  std::shared_ptr<KeyframePipeline> pipeline_;  // shared with the snapshots being written
  TeamExchange* team_ = nullptr;
  std::string team_frame_;  // the pose frame of the keyframes shared last
};

}  // namespace scan_context_loop
