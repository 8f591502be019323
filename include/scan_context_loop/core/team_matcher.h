// Several robots, one map: the keyframes the other robots of a team share, and where this robot's
// keyframes meet them. ROS-free; the loop node's team exchange (ros/team_exchange.h) and the evaluator's
// team mode (eval/team_evaluation.h) both use it, so a team scores offline with the node's code.
//
// A robot shares each keyframe it stores as a record: a one-keyframe database image without registration
// data (keyframeRecord: the descriptor, stamp and odometry pose, in database_file.h's layout with its
// checksums and settings). The image carries the settings that make descriptors comparable, so a record
// made with others is refused with the setting named. The registration data of a keyframe travel only when
// a candidate needs them: keyframeCloud makes them (the same image with the data, LZ4-compressed), and
// attachCloud takes them in.
//
// Who finds a loop between two robots: the robot whose keyframe comes later. Each robot matches its own
// new keyframes against the records it holds (match), so every pair is looked at once, by one robot.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/detector.h"

namespace scan_context_loop {

/// A keyframe of a team: the robot that stored it, that robot's node run (drawn when the node starts or is
/// reset: keyframe numbers start again with it) and its number there.
struct TeamKeyframeId {
  std::string robot;
  std::uint64_t run = 0;
  std::uint32_t keyframe = 0;

  bool operator<(const TeamKeyframeId& o) const {
    return std::tie(robot, run, keyframe) < std::tie(o.robot, o.run, o.keyframe);
  }
  bool operator==(const TeamKeyframeId& o) const { return robot == o.robot && run == o.run && keyframe == o.keyframe; }
  /// "robot/run/keyframe", for logs.
  std::string text() const;
};

/// Keyframe `index` of `detector` as a record for the team (encodeDatabase of one keyframe, without
/// registration data), and the same with its registration data and gravity alignment (empty when
/// `index` is past the database).
std::vector<std::uint8_t> keyframeRecord(const LoopDetector& detector, std::size_t index);
std::vector<std::uint8_t> keyframeCloud(const LoopDetector& detector, std::size_t index);

/// A robot id as the team uses it in names (ROS namespaces, topic and file names): 1-64 characters of
/// [A-Za-z0-9_], the first a letter (a ROS name must not begin with a digit or an underscore).
bool validRobotId(const std::string& robot);
/// What validRobotId accepts, for messages.
extern const char* const kRobotIdRule;

/// Where one of this robot's keyframes meets the team's.
struct TeamMatch {
  /// LoopDetector::locate over the team's keyframes: candidates, verifications (indices are team indices).
  Detection detection;
  /// The accepted match, when detection.verified: its team index.
  std::size_t match = 0;
  /// Candidates worth registering whose registration data are not here and were not asked for yet:
  /// fetch them (each is now marked as asked for), then match the keyframe again.
  std::vector<TeamKeyframeId> to_fetch;
  /// Candidates whose data were asked for before and have not arrived (nor failed) yet.
  std::vector<TeamKeyframeId> waiting;
};

/// Not thread-safe: one owner thread.
class TeamMatcher {
 public:
  /// `config`: this robot's (the records must share its descriptor settings; verification runs with it).
  explicit TeamMatcher(const Config& config);

  enum class Added { kAdded, kDuplicate, kRefused };
  /// A record another robot shared: `image` from keyframeRecord; `session` the keyframe's session at its
  /// robot. A record already held is a duplicate (nothing changes); a bad image, one made with other
  /// descriptor settings, more than one keyframe or an invalid robot id is refused (`error` says why).
  Added add(const TeamKeyframeId& id, std::uint32_t session, const std::uint8_t* image, std::size_t size,
            std::string* error = nullptr);
  /// A candidate's registration data as its robot sent them (keyframeCloud). False when they do not fit
  /// (the image's own checks, other voxel settings, another keyframe's stamp) or the keyframe is unknown.
  bool attachCloud(const TeamKeyframeId& id, const std::uint8_t* image, std::size_t size, std::string* error = nullptr);
  /// Its data could not be fetched (the robot is gone, or refused): not asked for again.
  void fetchFailed(const TeamKeyframeId& id);
  /// Its data did not come this time (the robot's node was slow, busy or not there): not asked for again
  /// until retryLater(), so that the next candidates, another robot's among them, get their turn.
  void fetchLater(const TeamKeyframeId& id);
  /// The keyframes fetchLater() set aside may be asked for again.
  void retryLater();

  /// Where this robot's keyframe meets the others': `points` as it was described (the keyframe's
  /// voxel-filtered cloud in its sensor frame). At most `max_fetch` candidates go into to_fetch.
  TeamMatch match(const PointView& points, std::size_t max_fetch);

  std::size_t size() const { return ids_.size(); }
  const TeamKeyframeId& id(std::size_t index) const { return ids_.at(index); }
  std::uint32_t session(std::size_t index) const { return sessions_.at(index); }
  const Keyframe& keyframe(std::size_t index) const { return detector_.database().keyframe(index); }
  bool has(const TeamKeyframeId& id) const { return index_.count(id) != 0; }
  /// The lowest keyframe number below `count` of robot `robot`'s run `run` that is not held (count when
  /// all are): where filling a gap starts.
  std::uint32_t firstMissing(const std::string& robot, std::uint64_t run, std::uint32_t count) const;
  /// Keyframes whose registration data are held.
  std::size_t clouds() const { return clouds_; }
  /// Memory the records held take, as the database accounts its keyframes (Database::bytesPerKeyframe),
  /// plus the bookkeeping of their ids [bytes]; registration data are not counted (the cloud store's own
  /// budget, verify_max_bytes, bounds them).
  std::size_t recordBytes() const;
  const LoopDetector& detector() const { return detector_; }

 private:
  enum class Data : std::uint8_t { kNone, kAsked, kHeld, kFailed, kLater };
  LoopDetector detector_;
  std::vector<TeamKeyframeId> ids_;
  std::vector<std::uint32_t> sessions_;
  std::vector<Data> data_;
  std::vector<std::size_t> later_;  // the indices set to kLater
  std::map<TeamKeyframeId, std::size_t> index_;
  std::map<std::pair<std::string, std::uint64_t>, std::set<std::uint32_t>> held_;  // numbers held per run
  std::size_t clouds_ = 0;
};

}  // namespace scan_context_loop
