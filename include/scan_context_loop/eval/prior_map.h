// The prior map of a relocalization evaluation (scan_context_evaluate --prior): a sequence whose
// keyframes go through the pipeline first, or a saved database (core/database_file.h) that joins it,
// with the true poses of its keyframes looked up by each keyframe's tag (the frame index
// scan_context_evaluate gives it) in the sequence the database was built from.
#pragma once

#include <string>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/prior_sessions.h"
#include "scan_context_loop/eval/sequence.h"

namespace scan_context_loop {
namespace eval {

struct DatabasePrior {
  std::string path;       ///< the database file
  std::string truth_dir;  ///< the sequence it was built from
  /// The keyframes as read from the file; evaluate() moves them into its pipeline.
  PriorSessions sessions;
  /// One entry per stored keyframe, in database order: frames = tags, truth = truth_dir's pose of that
  /// frame, odometry and stamps as stored; dir = truth_dir.
  Sequence keyframes;
};

/// Reads and checks the database at `path` against `config` (readDatabaseFile: its descriptor and
/// registration settings must be the configuration's) and looks each keyframe's tag up among the frames
/// of `truth_dir` (poses.txt, calib.txt). Refuses, naming the problem: an empty database, one of more
/// than one session (one sequence's frames cannot name two runs' keyframes), and a tag that is no frame
/// of `truth_dir` (a database whose keyframes were not tagged with frame indices, as the node's are not).
bool loadDatabasePrior(const std::string& path, const std::string& truth_dir, const Config& config,
                       DatabasePrior* prior, std::string* error);

struct PriorMap {
  enum class Kind { kNone, kSequence, kDatabase };
  Kind kind = Kind::kNone;
  Sequence sequence;       ///< kSequence
  DatabasePrior database;  ///< kDatabase
};

/// What `path` names: nothing (empty: Kind::kNone), a sequence directory (loaded with `options` over all
/// its frames: the same keyframe spacing and odometry source as the query's), or a database file
/// (loadDatabasePrior with `truth_dir`, which a database needs and a sequence refuses). False with
/// `error` naming the problem.
bool loadPriorMap(const std::string& path, const std::string& truth_dir, const SequenceOptions& options,
                  const Config& config, PriorMap* prior, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
