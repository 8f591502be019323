#include "scan_context_loop/eval/prior_map.h"

#include <sys/stat.h>

#include "scan_context_loop/core/database_file.h"

namespace scan_context_loop {
namespace eval {

bool loadDatabasePrior(const std::string& path, const std::string& truth_dir, const Config& config,
                       DatabasePrior* prior, std::string* error) {
  DatabasePrior p;
  p.path = path;
  p.truth_dir = truth_dir;
  if (!readDatabaseFile(path, config, &p.sessions, error)) return false;
  const std::vector<Keyframe>& keyframes = p.sessions.keyframes;
  if (keyframes.empty()) {
    *error = path + ": the database holds no keyframe";
    return false;
  }
  if (keyframes.back().session != 0) {
    *error = path + ": the database holds " + std::to_string(keyframes.back().session + 1) +
             " sessions; a prior with its truth (--prior-truth) must be one sequence's keyframes";
    return false;
  }
  std::vector<Eigen::Isometry3d> truth;
  std::string why;
  if (!readTruePoses(truth_dir, &truth, &why)) {
    *error = "the truth of " + path + ": " + why;
    return false;
  }
  Sequence& s = p.keyframes;
  s.dir = truth_dir;
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const KeyframeInfo& info = keyframes[i].info;
    if (info.tag < 0 || info.tag >= static_cast<std::int64_t>(truth.size())) {
      *error = path + ": keyframe " + std::to_string(i) + " has tag " + std::to_string(info.tag) + ", no frame of " +
               truth_dir + " (poses.txt has " + std::to_string(truth.size()) +
               " frames); the tags must be the frame indices of the sequence the database was built from";
      return false;
    }
    s.frames.push_back(static_cast<int>(info.tag));
    s.truth.push_back(truth[info.tag]);
    s.odometry.push_back(info.pose.value_or(Eigen::Isometry3d::Identity()));
    s.stamps.push_back(info.stamp);
  }
  *prior = std::move(p);
  return true;
}

bool loadPriorMap(const std::string& path, const std::string& truth_dir, const SequenceOptions& options,
                  const Config& config, PriorMap* prior, std::string* error) {
  prior->kind = PriorMap::Kind::kNone;
  if (path.empty()) {
    if (truth_dir.empty()) return true;
    *error = "a truth sequence (--prior-truth " + truth_dir + ") without a prior database";
    return false;
  }
  struct stat st;
  if (stat(path.c_str(), &st) != 0) {
    *error = "prior " + path + ": no such file or directory";
    return false;
  }
  if (S_ISDIR(st.st_mode)) {
    if (!truth_dir.empty()) {
      *error = "prior " + path + " is a sequence, its own truth: a truth sequence (--prior-truth " + truth_dir +
               ") goes with a database file only";
      return false;
    }
    SequenceOptions whole = options;
    whole.first = 0;
    whole.last = -1;
    if (!loadSequence(path, whole, &prior->sequence, error)) return false;
    prior->kind = PriorMap::Kind::kSequence;
    return true;
  }
  if (truth_dir.empty()) {
    *error = "prior " + path +
             " is a database file: its keyframes' true poses need the sequence it was built "
             "from (--prior-truth SEQ_DIR: its poses.txt and calib.txt, looked up by each keyframe's tag)";
    return false;
  }
  if (!loadDatabasePrior(path, truth_dir, config, &prior->database, error)) return false;
  prior->kind = PriorMap::Kind::kDatabase;
  return true;
}

}  // namespace eval
}  // namespace scan_context_loop
