#include "team/team_worker.h"

#include <chrono>
#include <thread>

#include "scan_context_loop/GetKeyframeCloud.h"
#include "scan_context_loop/GetKeyframeRecords.h"
#include "scan_context_loop/core/crc32.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "shared/stored_keyframe.h"

namespace scan_context_loop {

std::pair<std::string, std::uint32_t> teamSettings(const Config& config) {
  // The registration data's voxel settings too: a candidate's data made otherwise cannot be verified here.
  const std::string text = compatibilityText(config, true);
  return {text, crc32(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())};
}

namespace {

/// The settings of `theirs` that differ from `ours` ("key value, ..." texts), as "key theirs (ours here)".
std::string differences(const std::string& theirs, const std::string& ours) {
  const auto split = [](const std::string& text) {
    std::map<std::string, std::string> pairs;
    std::size_t start = 0;
    while (start < text.size()) {
      std::size_t end = text.find(", ", start);
      if (end == std::string::npos) end = text.size();
      const std::string item = text.substr(start, end - start);
      const std::size_t space = item.find(' ');
      pairs[item.substr(0, space)] = space == std::string::npos ? "" : item.substr(space + 1);
      start = end + 2;
    }
    return pairs;
  };
  const auto a = split(theirs), b = split(ours);
  std::string out;
  for (const auto& [key, value] : b) {
    const auto it = a.find(key);
    const std::string other = it == a.end() ? "(none)" : it->second;
    if (other != value) out += (out.empty() ? "" : ", ") + key + " " + other + " (" + value + " here)";
  }
  return out.empty() ? "their settings text differs from ours" : out;
}

}  // namespace

std::string peerText(const std::string& text) {
  constexpr std::size_t kMax = 64;
  std::string out = text.substr(0, kMax);
  for (char& c : out) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return text.size() > kMax ? out + "..." : out;
}

namespace {

/// Whether `node` can name a node's services: an absolute, valid ROS name of reasonable length.
bool validNodeName(const std::string& node) {
  std::string error;
  return node.size() > 1 && node.size() <= 256 && node.front() == '/' && ros::names::validate(node, error);
}

}  // namespace

TeamWorker::TeamWorker(const std::string& name, const Config& config, const NodeOptions& options,
                       NodeCounters* counters, LoopPublisher* loops)
    : name_(name),
      config_(config),
      options_(options),
      counters_(counters),
      loops_(loops),
      matcher_(config),
      consistency_(config) {
  std::tie(settings_text_, settings_crc_) = teamSettings(config);
}

TeamWorker::~TeamWorker() { stop(); }

void TeamWorker::stop() {
  deadline_.stop();  // a call in progress ends now: the client's thread is free to stop
  client_.stop();
  matcher_thread_.stop();
}

void TeamWorker::onRecord(const scan_context_loop::KeyframeRecordConstPtr& record, std::size_t bytes,
                          const std::string& publisher) {
  counters_->team_bytes_received += bytes;
  if (!matcher_thread_.post([this, record, publisher] { addRecord(*record, publisher); })) {
    ROS_WARN_THROTTLE_NAMED(10.0, name_, "team: a record of robot %s dropped: the team's queue is full",
                            peerText(record->robot).c_str());
  }
}

void TeamWorker::onMember(const scan_context_loop::TeamMemberConstPtr& member, std::size_t bytes,
                          const std::string& publisher) {
  counters_->team_bytes_received += bytes;
  matcher_thread_.post([this, member, publisher] { takeMember(*member, publisher); });
}

bool TeamWorker::claim(const std::string& robot, const std::string& node, const std::string& publisher) {
  std::string why;
  const auto bound = robots_.find(robot);
  if (!validNodeName(node)) {
    why = "its node name is not a valid ROS name";
  } else if (bound == robots_.end()) {
    if (robots_.size() < kMaxRobots) {
      robots_[robot] = {node, publisher};
      return true;
    }
    why = "this node already knows " + std::to_string(kMaxRobots) + " robots";
  } else if (bound->second.node == node && (publisher.empty() || bound->second.publisher == publisher)) {
    return true;
  } else {
    why = "the id is bound to node " + bound->second.node + " (published by " + bound->second.publisher + ")";
  }
  ++counters_->team_claims_refused;
  ROS_WARN_THROTTLE_NAMED(10.0, name_,
                          "team: robot id %s claimed by node %s (published by %s) refused: %s (%zu refused)",
                          peerText(robot).c_str(), peerText(node).c_str(), peerText(publisher).c_str(), why.c_str(),
                          counters_->team_claims_refused.load());
  return false;
}

void TeamWorker::onOwnKeyframe(std::shared_ptr<const OwnKeyframe> keyframe) {
  if (!matcher_thread_.post([this, keyframe] { match(keyframe, 0); })) {
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "team: keyframe %u not matched against the other robots' (queue full)",
                            keyframe->index);
  }
}

void TeamWorker::addRecord(const scan_context_loop::KeyframeRecord& record, const std::string& publisher) {
  const Run run{record.robot, record.run};
  if (record.robot == options_.robot_id) return;  // this robot's own, echoed
  ++counters_->team_records_received;
  if (refused_.count(run) || record.settings != settings_crc_) {
    ++counters_->team_records_refused;
    ROS_ERROR_THROTTLE_NAMED(10.0, name_,
                             "team: keyframes of robot %s refused: its descriptor settings differ from ours (see "
                             "its announcement on %s/members)",
                             peerText(record.robot).c_str(), options_.team_namespace.c_str());
    return;
  }
  if (!validRobotId(record.robot) || !claim(record.robot, record.node, publisher)) {
    ++counters_->team_records_refused;
    return;
  }
  const TeamKeyframeId id{record.robot, record.run, record.keyframe};
  if (!matcher_.has(id) && matcher_.recordBytes() >= static_cast<std::size_t>(options_.team_max_bytes)) {
    ++counters_->team_records_over_limit;
    ROS_WARN_THROTTLE_NAMED(30.0, name_,
                            "team: the other robots' records take %.1f MB, team_max_bytes: %zu more refused so far",
                            matcher_.recordBytes() / 1e6, counters_->team_records_over_limit.load());
    return;
  }
  std::string error;
  switch (matcher_.add(id, record.session, record.data.data(), record.data.size(), &error)) {
    case TeamMatcher::Added::kAdded:
      counters_->team_keyframes = matcher_.size();
      counters_->team_record_bytes = matcher_.recordBytes();
      break;
    case TeamMatcher::Added::kDuplicate:
      ++counters_->team_records_duplicate;
      break;
    case TeamMatcher::Added::kRefused:
      ++counters_->team_records_refused;
      ROS_ERROR_THROTTLE_NAMED(5.0, name_, "team: a record of robot %s refused: %s", peerText(record.robot).c_str(),
                               error.c_str());
      break;
  }
}

void TeamWorker::takeMember(const scan_context_loop::TeamMember& member, const std::string& publisher) {
  // This node's own announcement, or another run of this robot's node (before a restart): not ours to take.
  if (member.robot == options_.robot_id) return;
  const Run run{member.robot, member.run};
  if (!validRobotId(member.robot)) {
    ROS_ERROR_THROTTLE_NAMED(10.0, name_, "team: an announcement with an invalid robot id ignored");
    return;
  }
  if (!claim(member.robot, member.node, publisher)) return;
  // Data set aside after a slow node are asked for again once it has had time to recover.
  const ros::WallTime now = ros::WallTime::now();
  if ((now - last_retry_).toSec() >= kSlowPeerSeconds) {
    matcher_.retryLater();
    last_retry_ = now;
  }
  if (member.settings != settings_crc_ || member.settings_text != settings_text_) {
    if (refused_.size() >= kMaxRefused) refused_.clear();  // remembered to log once, and only so many
    if (refused_.insert(run).second) {
      ROS_ERROR_THROTTLE_NAMED(10.0, name_,
                               "team: robot %s (node %s) is refused: its keyframes cannot be compared with ours: %s. "
                               "Give every robot of a team the same descriptor and verification voxel settings",
                               peerText(member.robot).c_str(), peerText(member.node).c_str(),
                               differences(member.settings_text, settings_text_).substr(0, 400).c_str());
    }
    return;
  }
  const std::uint32_t first = matcher_.firstMissing(member.robot, member.run, member.keyframes);
  if (first >= member.keyframes) return;
  // A request under way is waited for; one whose answer never came back (a full queue) is forgotten.
  const auto asked = asking_.find(run);
  if (asked != asking_.end() && (now - asked->second).toSec() < 4.0 * options_.team_request_timeout + 10.0) return;
  asking_[run] = now;
  const std::uint32_t count = std::min(kRecordsPerRequest, member.keyframes - first);
  const std::string node = member.node;
  if (!client_.post([this, node, run, first, count] { requestRecords(node, run, first, count); })) asking_.erase(run);
}

void TeamWorker::match(std::shared_ptr<const OwnKeyframe> keyframe, int rounds) {
  const PointView view = viewOf(keyframe->described);
  const TeamMatch found = matcher_.match(view, static_cast<std::size_t>(config_.verification.max_candidates));
  if (found.detection.verified) {
    publishLoop(*keyframe, found);
    return;
  }
  for (const TeamKeyframeId& id : found.to_fetch) fetch(id);
  if (rounds >= kMaxRounds || (found.to_fetch.empty() && found.waiting.empty())) return;
  Pending pending{keyframe, {}, rounds + 1};
  pending.waiting_for.insert(found.to_fetch.begin(), found.to_fetch.end());
  pending.waiting_for.insert(found.waiting.begin(), found.waiting.end());
  if (pending_.size() >= kMaxPending) pending_.erase(pending_.begin());  // the oldest gives way
  pending_.push_back(std::move(pending));
}

void TeamWorker::publishLoop(const OwnKeyframe& keyframe, const TeamMatch& found) {
  const VerifiedCandidate& v = found.detection.verifications.back();
  const Loop loop = v.toLoop(keyframe.index);
  Keyframe query;
  setKeyframeStamp(keyframe.stamp, &query.info);
  query.info.pose = keyframe.pose;
  query.session = keyframe.session;
  Keyframe match;
  match.info = matcher_.keyframe(found.match).info;
  match.session = matcher_.session(found.match);
  scan_context_loop::LoopClosure message = loopMessage(loop, keyframe.frame, query, match, config_);
  const TeamKeyframeId& id = matcher_.id(found.match);
  message.query_id = keyframe.index;
  message.match_id = id.keyframe;
  message.query_robot = options_.robot_id;
  message.match_robot = id.robot;
  // Reported once another loop between the same two odometry frames agrees (team_consistency.h).
  TeamLoopOffer offer;
  offer.robot = id.robot;
  offer.run = id.run;
  offer.session = match.session;
  offer.own_session = keyframe.session;
  offer.own_pose = keyframe.pose;
  offer.other_pose = match.info.pose.value_or(Eigen::Isometry3d::Identity());
  offer.own_path = keyframe.path_length;
  offer.other_path = matcher_.keyframe(found.match).path_length;
  offer.relative = v.result.relative;
  offer.handle = next_handle_++;
  message.support = config_.consistency_min_support > 0 ? 1 : 0;
  unconfirmed_.emplace(offer.handle, std::move(message));
  const TeamRelease release = consistency_.offer(offer);
  for (std::size_t handle : release.report) {
    loops_->publishTeamLoop(unconfirmed_.at(handle));
    unconfirmed_.erase(handle);
  }
  for (std::size_t handle : release.dropped) {
    ++counters_->team_loops_dropped;
    unconfirmed_.erase(handle);
  }
}

}  // namespace scan_context_loop
