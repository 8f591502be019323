#include "scan_context_loop/core/team_matcher.h"

#include <algorithm>
#include <cmath>

#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/file_io.h"

namespace scan_context_loop {

std::string TeamKeyframeId::text() const { return robot + "/" + std::to_string(run) + "/" + std::to_string(keyframe); }

std::vector<std::uint8_t> keyframeRecord(const LoopDetector& detector, std::size_t index) {
  if (index >= detector.database().size()) return {};
  return encodeDatabase(DatabaseSnapshot(detector, false, nullptr, index, 1));
}

std::vector<std::uint8_t> keyframeCloud(const LoopDetector& detector, std::size_t index) {
  if (index >= detector.database().size()) return {};
  return encodeDatabase(DatabaseSnapshot(detector, true, nullptr, index, 1));
}

const char* const kRobotIdRule = "1-64 characters of [A-Za-z0-9_], the first a letter";

bool validRobotId(const std::string& robot) {
  const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  return !robot.empty() && robot.size() <= 64 && letter(robot.front()) &&
         std::all_of(robot.begin(), robot.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '_'; });
}

namespace {

/// Reads a one-keyframe image; false with the reason.
bool readOne(const std::uint8_t* image, std::size_t size, const std::string& name, const Config& config,
             PriorSessions* out, std::string* error) {
  MemoryReader reader(image, size);
  if (!readDatabase(&reader, name, config, out, error)) return false;
  if (out->keyframes.size() != 1) {
    if (error) *error = name + ": holds " + std::to_string(out->keyframes.size()) + " keyframes, not one";
    return false;
  }
  return true;
}

}  // namespace

TeamMatcher::TeamMatcher(const Config& config) : detector_(config) {}

TeamMatcher::Added TeamMatcher::add(const TeamKeyframeId& id, std::uint32_t session, const std::uint8_t* image,
                                    std::size_t size, std::string* error) {
  if (!validRobotId(id.robot)) {
    if (error) *error = "robot id \"" + id.robot.substr(0, 64) + "\" is not " + kRobotIdRule;
    return Added::kRefused;
  }
  if (has(id)) return Added::kDuplicate;
  PriorSessions record;
  if (!readOne(image, size, "keyframe " + id.text(), detector_.config(), &record, error)) return Added::kRefused;
  record.keyframes.front().session = 0;
  std::string why;
  if (!detector_.appendSessions(std::move(record), &why)) {
    if (error) *error = "keyframe " + id.text() + ": " + why;
    return Added::kRefused;
  }
  index_.emplace(id, ids_.size());
  held_[{id.robot, id.run}].insert(id.keyframe);
  ids_.push_back(id);
  sessions_.push_back(session);
  data_.push_back(Data::kNone);
  return Added::kAdded;
}

bool TeamMatcher::attachCloud(const TeamKeyframeId& id, const std::uint8_t* image, std::size_t size,
                              std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  const auto it = index_.find(id);
  if (it == index_.end()) return fail("registration data of " + id.text() + ", a keyframe not held");
  PriorSessions data;
  if (!readOne(image, size, "registration data of " + id.text(), detector_.config(), &data, error)) return false;
  const std::size_t index = it->second;
  if (data.clouds.empty() || !data.clouds.front())
    return fail("registration data of " + id.text() + ": none in the image");
  if (data.keyframes.front().info.stamp != keyframe(index).info.stamp) {
    return fail("registration data of " + id.text() + " belong to another keyframe (its stamp differs)");
  }
  std::string why;
  if (!detector_.attachCloud(index, data.gravity_alignment.front(), *data.clouds.front(), &why)) {
    return fail("registration data of " + id.text() + ": " + why);
  }
  if (data_[index] != Data::kHeld) ++clouds_;
  data_[index] = Data::kHeld;
  return true;
}

void TeamMatcher::fetchFailed(const TeamKeyframeId& id) {
  const auto it = index_.find(id);
  if (it != index_.end() && data_[it->second] != Data::kHeld) data_[it->second] = Data::kFailed;
}

void TeamMatcher::fetchLater(const TeamKeyframeId& id) {
  const auto it = index_.find(id);
  if (it == index_.end() || data_[it->second] != Data::kAsked) return;
  data_[it->second] = Data::kLater;
  later_.push_back(it->second);
}

void TeamMatcher::retryLater() {
  for (std::size_t i : later_) {
    if (data_[i] == Data::kLater) data_[i] = Data::kNone;
  }
  later_.clear();
}

std::size_t TeamMatcher::recordBytes() const {
  // An id: its text in the vector and the index (a map node), its session and state, and its number
  // in the per-run set (a set node).
  constexpr std::size_t kIdBytes = 2 * sizeof(TeamKeyframeId) + 64 + sizeof(std::uint32_t) + 1 + 48;
  return size() * (detector_.database().bytesPerKeyframe() + kIdBytes);
}

TeamMatch TeamMatcher::match(const PointView& points, std::size_t max_fetch) {
  TeamMatch out;
  out.detection = detector_.locate(points);
  if (out.detection.verified) out.match = out.detection.verifications.back().index;
  // The candidates verification would register (the descriptor distance below its threshold, as many as it
  // tries), whose data are not here.
  const VerificationConfig& verification = detector_.config().verification;
  for (const Candidate& c : out.detection.query.candidates) {
    if (!(c.alignment.distance < verification.threshold)) break;
    Data& data = data_[c.index];
    if (data == Data::kAsked) out.waiting.push_back(ids_[c.index]);
    if (data != Data::kNone || out.to_fetch.size() >= max_fetch) continue;
    data = Data::kAsked;
    out.to_fetch.push_back(ids_[c.index]);
  }
  return out;
}

std::uint32_t TeamMatcher::firstMissing(const std::string& robot, std::uint64_t run, std::uint32_t count) const {
  const auto it = held_.find({robot, run});
  if (it == held_.end()) return 0;
  std::uint32_t n = 0;
  for (std::uint32_t k : it->second) {
    if (k != n || n >= count) break;
    ++n;
  }
  return std::min(n, count);
}

}  // namespace scan_context_loop
