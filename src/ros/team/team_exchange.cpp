#include "team/team_exchange.h"

#include <random>

#include "scan_context_loop/core/team_matcher.h"
#include "shared/stored_keyframe.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

namespace {

/// A run number: random, never 0, so a restarted node's keyframes never pass for the last run's.
std::uint64_t newRun() {
  std::random_device device;
  std::uint64_t run = 0;
  while (run == 0) run = (std::uint64_t(device()) << 32) ^ device();
  return run;
}

template <typename M>
std::size_t bytesOf(const M& message) {
  return ros::serialization::serializationLength(message);
}

/// The answer to a request of another run than this node's.
std::string otherRun(std::uint64_t asked, std::uint64_t ours) {
  return "run " + std::to_string(asked) + " is not this node's (" + std::to_string(ours) +
         "): it was restarted or reset";
}

/// Bursts of this many seconds' worth of bytes pass the rate limit at once (a keyframe's registration data
/// are larger than a second's budget at low rates).
constexpr double kBurstSeconds = 4.0;

}  // namespace

TeamExchange::TeamExchange(const ros::NodeHandle& pnh, const std::string& name, const Config& config,
                           const NodeOptions& options, NodeCounters* counters, LoopPublisher* loops)
    : pnh_(pnh),
      team_nh_(options.team_namespace),
      name_(name),
      options_(options),
      counters_(counters),
      worker_(new TeamWorker(name, config, options, counters, loops)),
      run_(newRun()),
      limit_(options.team_max_bytes_per_second, options.team_max_bytes_per_second * kBurstSeconds) {
  std::tie(settings_text_, settings_crc_) = teamSettings(config);
  team_nh_.setCallbackQueue(&queue_);
}

TeamExchange::~TeamExchange() { stop(); }

void TeamExchange::start() {
  ros::NodeHandle services(pnh_);
  services.setCallbackQueue(&queue_);
  record_pub_ = team_nh_.advertise<scan_context_loop::KeyframeRecord>(topic_names::kTeamKeyframeRecords, 1000);
  member_pub_ = team_nh_.advertise<scan_context_loop::TeamMember>(topic_names::kTeamMembers, 10);
  // With the publisher's name (from the connection header), which binds a robot id to its node.
  record_sub_ = team_nh_.subscribe<scan_context_loop::KeyframeRecord>(
      topic_names::kTeamKeyframeRecords, 1000,
      boost::function<void(const ros::MessageEvent<const scan_context_loop::KeyframeRecord>&)>(
          [this](const ros::MessageEvent<const scan_context_loop::KeyframeRecord>& event) {
            const auto& record = event.getConstMessage();
            if (record->robot != options_.robot_id) {
              worker_->onRecord(record, bytesOf(*record), event.getPublisherName());
            }
          }));
  member_sub_ = team_nh_.subscribe<scan_context_loop::TeamMember>(
      topic_names::kTeamMembers, 100,
      boost::function<void(const ros::MessageEvent<const scan_context_loop::TeamMember>&)>(
          [this](const ros::MessageEvent<const scan_context_loop::TeamMember>& event) {
            const auto& member = event.getConstMessage();
            if (member->robot != options_.robot_id) {
              worker_->onMember(member, bytesOf(*member), event.getPublisherName());
            }
          }));
  records_srv_ = services.advertiseService(topic_names::kTeamRecords, &TeamExchange::onRecords, this);
  cloud_srv_ = services.advertiseService(topic_names::kTeamCloud, &TeamExchange::onCloud, this);
  announce_timer_ =
      team_nh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { announce(); });
  spinner_.reset(new ros::AsyncSpinner(1, &queue_));
  spinner_->start();
  ROS_INFO_NAMED(name_, "team: robot %s shares its keyframes on %s (run %llu)", options_.robot_id.c_str(),
                 record_pub_.getTopic().c_str(), static_cast<unsigned long long>(run_));
}

void TeamExchange::stop() {
  announce_timer_.stop();
  records_srv_.shutdown();
  cloud_srv_.shutdown();
  record_sub_.shutdown();
  member_sub_.shutdown();
  if (spinner_) spinner_->stop();
  worker_->stop();
}

bool TeamExchange::answer(std::size_t bytes, std::string* message) {
  if (!maySend(bytes)) {
    *message = "busy: over team_max_bytes_per_second";
    return false;
  }
  counters_->team_bytes_sent += bytes;
  return true;
}

bool TeamExchange::maySend(std::size_t bytes) {
  std::lock_guard<std::mutex> lock(send_mutex_);
  return limit_.take(static_cast<double>(bytes), ros::WallTime::now().toSec());
}

void TeamExchange::share(const LoopDetector& detector, const std::shared_ptr<const void>& owner,
                         const std::string& frame) {
  const Database& database = detector.database();
  std::vector<scan_context_loop::KeyframeRecordPtr> fresh;
  {
    std::lock_guard<std::mutex> lock(served_mutex_);
    if (database.size() < served_.size()) {
      // Emptied by other means than restart(): the keyframe numbers start again, under a new run.
      served_.clear();
      run_ = newRun();
    }
    for (std::size_t i = served_.size(); i < database.size(); ++i) {
      auto record = boost::make_shared<scan_context_loop::KeyframeRecord>();
      record->robot = options_.robot_id;
      record->run = run_;
      record->keyframe = static_cast<std::uint32_t>(i);
      record->session = database.keyframe(i).session;
      record->stamp = keyframeStamp(database.keyframe(i).info);
      record->frame_id = frame;
      record->node = pnh_.getNamespace();
      record->settings = settings_crc_;
      record->data = keyframeRecord(detector, i);
      served_.push_back({record, DatabaseSnapshot(detector, true, owner, i, 1)});
      served_.back().data.holdCloudsWeakly();  // the cloud store's budget frees its data all the same
      fresh.push_back(record);
    }
  }
  for (const auto& record : fresh) {
    const std::size_t bytes = bytesOf(*record);
    if (!maySend(bytes)) {
      ++counters_->team_records_deferred;  // the others fetch it after the next announcement
      continue;
    }
    record_pub_.publish(record);
    ++counters_->team_records_sent;
    counters_->team_bytes_sent += bytes * std::max<std::size_t>(1, record_pub_.getNumSubscribers());
  }
}

void TeamExchange::restart() {
  std::lock_guard<std::mutex> lock(served_mutex_);
  served_.clear();
  run_ = newRun();
}

void TeamExchange::announce() {
  scan_context_loop::TeamMember member;
  member.robot = options_.robot_id;
  member.node = pnh_.getNamespace();
  member.settings_text = settings_text_;
  member.settings = settings_crc_;
  {
    std::lock_guard<std::mutex> lock(served_mutex_);
    member.run = run_;
    member.keyframes = static_cast<std::uint32_t>(served_.size());
  }
  member_pub_.publish(member);
  counters_->team_bytes_sent += bytesOf(member) * std::max<std::size_t>(1, member_pub_.getNumSubscribers());
}

bool TeamExchange::onRecords(scan_context_loop::GetKeyframeRecords::Request& request,
                             scan_context_loop::GetKeyframeRecords::Response& response) {
  {
    std::lock_guard<std::mutex> lock(served_mutex_);
    if (request.run != run_) {
      response.message = otherRun(request.run, run_);
      return true;
    }
    const std::size_t first = std::min<std::size_t>(request.first, served_.size());
    const std::size_t count = std::min<std::size_t>({request.count, 100, served_.size() - first});
    for (std::size_t i = first; i < first + count; ++i) response.records.push_back(*served_[i].record);
  }
  response.ok = answer(bytesOf(response), &response.message);
  if (!response.ok) response.records.clear();
  if (response.ok) counters_->team_records_sent += response.records.size();
  return true;
}

bool TeamExchange::onCloud(scan_context_loop::GetKeyframeCloud::Request& request,
                           scan_context_loop::GetKeyframeCloud::Response& response) {
  DatabaseSnapshot data;
  {
    std::lock_guard<std::mutex> lock(served_mutex_);
    if (request.run != run_) {
      response.message = otherRun(request.run, run_);
      return true;
    }
    if (request.keyframe >= served_.size()) {
      response.message =
          "no keyframe " + std::to_string(request.keyframe) + " (" + std::to_string(served_.size()) + " shared)";
      return true;
    }
    bool complete = true;
    data = served_[request.keyframe].data.strengthened(&complete);  // encoded outside the lock
    if (!complete) {
      response.message = "the registration data of keyframe " + std::to_string(request.keyframe) +
                         " are no longer kept here (verify_max_bytes)";
      return true;
    }
  }
  response.data = encodeDatabase(data);
  response.ok = answer(bytesOf(response), &response.message);
  if (!response.ok) response.data.clear();
  if (response.ok) ++counters_->team_clouds_served;
  return true;
}

}  // namespace scan_context_loop
