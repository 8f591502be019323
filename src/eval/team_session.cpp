#include "scan_context_loop/eval/team_session.h"

#include "scan_context_loop/core/pcl_adapters.h"

namespace scan_context_loop {
namespace eval {

namespace {
/// Each robot's node runs once here: every keyframe of a robot is of this run.
constexpr std::uint64_t kRun = 1;
}  // namespace

TeamSession::TeamSession(const Config& config, const std::vector<std::string>& robots)
    : config_(config), robots_(robots) {
  for (std::size_t r = 0; r < robots.size(); ++r) {
    pipelines_.push_back(std::make_unique<KeyframePipeline>(config));
    matchers_.push_back(std::make_unique<TeamMatcher>(config));
    consistency_.push_back(std::make_unique<TeamConsistency>(config));
  }
}

long TeamSession::robotOf(const std::string& id) const {
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    if (robots_[r] == id) return static_cast<long>(r);
  }
  return -1;
}

bool TeamSession::fetch(std::size_t robot, const TeamKeyframeId& id, std::size_t* bytes) {
  TeamMatcher& matcher = *matchers_[robot];
  const long owner = robotOf(id.robot);
  const std::vector<std::uint8_t> data =
      owner < 0 ? std::vector<std::uint8_t>() : keyframeCloud(pipelines_[owner]->detector(), id.keyframe);
  *bytes = data.size();
  if (data.empty() || !matcher.attachCloud(id, data.data(), data.size())) {
    matcher.fetchFailed(id);
    return false;
  }
  return true;
}

TeamStep TeamSession::share(std::size_t robot, const Detection& detection,
                            const pcl::PointCloud<pcl::PointXYZ>& described) {
  TeamStep step;
  if (!detection.accepted) return step;
  TeamMatcher& matcher = *matchers_.at(robot);
  step.held = matcher.size();
  if (step.held > 0) {
    const PointView view = viewOf(described);
    const std::size_t max_fetch = static_cast<std::size_t>(config_.verification.max_candidates);
    for (int round = 0;; ++round) {
      const TeamMatch found = matcher.match(view, max_fetch);
      ++step.matches;
      if (found.detection.verified) {
        const VerifiedCandidate& v = found.detection.verifications.back();
        const Loop loop = v.toLoop(detection.index);
        const TeamKeyframeId& id = matcher.id(found.match);
        step.found = true;
        TeamLoop found_loop;
        found_loop.query_robot = robot;
        found_loop.match_robot = static_cast<std::size_t>(robotOf(id.robot));
        found_loop.query = detection.index;
        found_loop.match = id.keyframe;
        found_loop.relative = loop.relative();
        found_loop.covariance = loopCovariance(loop, config_);
        // As the node: reported once another loop between the same two frames agrees.
        const Keyframe& own = pipelines_[robot]->detector().database().keyframe(detection.index);
        const Keyframe& other = matcher.keyframe(found.match);
        TeamLoopOffer offer;
        offer.robot = id.robot;
        offer.run = id.run;
        offer.session = matcher.session(found.match);
        offer.own_session = own.session;
        offer.own_pose = own.info.pose.value_or(Eigen::Isometry3d::Identity());
        offer.other_pose = other.info.pose.value_or(Eigen::Isometry3d::Identity());
        offer.own_path = own.path_length;
        offer.other_path = other.path_length;
        offer.relative = found_loop.relative;
        offer.handle = next_handle_++;
        unconfirmed_.emplace(offer.handle, found_loop);
        const TeamRelease release = consistency_[robot]->offer(offer);
        for (std::size_t handle : release.report) {
          step.loops.push_back(unconfirmed_.at(handle));
          unconfirmed_.erase(handle);
        }
        for (std::size_t handle : release.dropped) unconfirmed_.erase(handle);
        step.dropped = release.dropped.size();
        break;
      }
      // Synchronous: whatever was asked for has come (or failed) by the next round; nothing waits.
      if (found.to_fetch.empty() || round >= kMaxRounds) break;
      for (const TeamKeyframeId& id : found.to_fetch) {
        std::size_t bytes = 0;
        if (fetch(robot, id, &bytes)) {
          ++step.fetched;
        } else {
          ++step.fetch_failures;
        }
        step.fetched_bytes += bytes;
      }
    }
  }
  const LoopDetector& own = pipelines_[robot]->detector();
  const std::vector<std::uint8_t> record = keyframeRecord(own, detection.index);
  step.record_bytes = record.size();
  const TeamKeyframeId id{robots_[robot], kRun, static_cast<std::uint32_t>(detection.index)};
  const std::uint32_t session = own.database().keyframe(detection.index).session;
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    if (r != robot && matchers_[r]->add(id, session, record.data(), record.size()) == TeamMatcher::Added::kRefused) {
      ++step.records_refused;
    }
  }
  return step;
}

}  // namespace eval
}  // namespace scan_context_loop
