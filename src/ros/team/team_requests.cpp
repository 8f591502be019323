// TeamWorker's requests to the other robots' nodes: the records a robot missed and the registration
// data a match needs, each call bounded by team_request_timeout (ServiceDeadline); a node that lets one
// time out is asked nothing for kSlowPeerSeconds.
#include "team/team_worker.h"

#include <chrono>
#include <thread>

#include "scan_context_loop/GetKeyframeCloud.h"
#include "scan_context_loop/GetKeyframeRecords.h"
#include "scan_context_loop/core/crc32.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

void TeamWorker::fetch(const TeamKeyframeId& id) {
  const auto robot = robots_.find(id.robot);
  if (robot == robots_.end()) {
    matcher_.fetchFailed(id);
    ++counters_->team_fetch_failures;
    return;
  }
  const std::string node = robot->second.node;
  if (!client_.post([this, node, id] { requestCloud(node, id); })) onCloud(id, {}, "the request queue is full", true);
}

void TeamWorker::onCloud(const TeamKeyframeId& id, const std::vector<std::uint8_t>& data, const std::string& failure,
                         bool later) {
  std::string error = failure;
  if (error.empty() && !matcher_.attachCloud(id, data.data(), data.size(), &error)) {
    error = "refused: " + error;
  }
  if (error.empty()) {
    ++counters_->team_clouds_fetched;
  } else {
    if (later) {
      matcher_.fetchLater(id);
    } else {
      matcher_.fetchFailed(id);
    }
    ++counters_->team_fetch_failures;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "team: registration data of %s not fetched: %s", id.text().c_str(),
                            error.c_str());
  }
  // The keyframes that waited for nothing else are matched again.
  std::vector<Pending> ready;
  for (auto it = pending_.begin(); it != pending_.end();) {
    it->waiting_for.erase(id);
    if (it->waiting_for.empty()) {
      ready.push_back(std::move(*it));
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  for (Pending& p : ready) match(p.keyframe, p.rounds);
}

template <typename Service>
ServiceDeadline::Outcome TeamWorker::callPeer(const std::string& node, const std::string& service, Service* srv) {
  const ros::WallTime now = ros::WallTime::now();
  const auto slow = slow_until_.find(node);
  if (slow != slow_until_.end() && now < slow->second) return ServiceDeadline::Outcome::kTimedOut;
  ServiceDeadline::Outcome outcome = ServiceDeadline::Outcome::kFailed;
  try {
    outcome = deadline_.call(node + "/" + service, srv, options_.team_request_timeout);
  } catch (const std::exception& e) {  // roscpp throws on a name it cannot use
    ROS_WARN_THROTTLE_NAMED(10.0, name_, "team: %s/%s cannot be called: %s", peerText(node).c_str(), service.c_str(),
                            peerText(e.what()).c_str());
  }
  // A node that is not there costs the wait for its service each time: it is set aside as a slow one is.
  if (outcome == ServiceDeadline::Outcome::kNoService) {
    slow_until_[node] = ros::WallTime::now() + ros::WallDuration(kSlowPeerSeconds);
  }
  if (outcome == ServiceDeadline::Outcome::kTimedOut) {
    slow_until_[node] = ros::WallTime::now() + ros::WallDuration(kSlowPeerSeconds);
    ++counters_->team_requests_timed_out;
    ROS_WARN_THROTTLE_NAMED(10.0, name_,
                            "team: %s/%s gave no answer within team_request_timeout (%.1f s): that node is asked "
                            "nothing for %.0f s (%zu requests timed out)",
                            peerText(node).c_str(), service.c_str(), options_.team_request_timeout, kSlowPeerSeconds,
                            counters_->team_requests_timed_out.load());
  }
  return outcome;
}

void TeamWorker::requestRecords(const std::string& node, const Run& run, std::uint32_t first, std::uint32_t count) {
  scan_context_loop::GetKeyframeRecords call;
  call.request.run = run.second;
  call.request.first = first;
  call.request.count = count;
  const ServiceDeadline::Outcome outcome = callPeer(node, topic_names::kTeamRecords, &call);
  bool ok = outcome == ServiceDeadline::Outcome::kAnswered;
  if (ok) counters_->team_bytes_received += ros::serialization::serializationLength(call.response);
  if (ok && !call.response.ok) {
    if (call.response.message.find("busy") != std::string::npos) ++counters_->team_busy;
    ok = false;
  }
  if (!ok) {
    ++counters_->team_fetch_failures;
    ROS_WARN_THROTTLE_NAMED(10.0, name_, "team: records of %s from %s not fetched: %s", peerText(run.first).c_str(),
                            peerText(node).c_str(),
                            outcome == ServiceDeadline::Outcome::kAnswered ? peerText(call.response.message).c_str()
                                                                           : ServiceDeadline::describe(outcome));
    call.response.records.clear();
  }
  auto records = std::make_shared<std::vector<scan_context_loop::KeyframeRecord>>(std::move(call.response.records));
  // Beyond the queue's capacity: a flood of records must not lose the reply (refused only while stopping).
  matcher_thread_.post(
      [this, records, run] {
        for (const auto& record : *records) {
          if (record.robot == run.first && record.run == run.second) addRecord(record, "");
        }
        asking_.erase(run);
      },
      true);
}

void TeamWorker::requestCloud(const std::string& node, const TeamKeyframeId& id) {
  std::string failure;
  bool later = false;
  scan_context_loop::GetKeyframeCloud call;
  // A busy node (over its rate) is asked again a little later, a few times.
  for (int attempt = 0; attempt < 4 && !deadline_.stopped(); ++attempt) {
    call.request.run = id.run;
    call.request.keyframe = id.keyframe;
    const ServiceDeadline::Outcome outcome = callPeer(node, topic_names::kTeamCloud, &call);
    if (outcome != ServiceDeadline::Outcome::kAnswered) {
      failure = node + "/team_cloud: " + ServiceDeadline::describe(outcome);
      later = outcome != ServiceDeadline::Outcome::kFailed;  // slow, not there, or stopping
      break;
    }
    counters_->team_bytes_received += ros::serialization::serializationLength(call.response);
    if (call.response.ok) {
      failure.clear();
      break;
    }
    failure = call.response.message.empty() ? "refused" : peerText(call.response.message);
    later = call.response.message.find("busy") != std::string::npos;  // still busy at the end: asked again later
    if (!later) break;
    ++counters_->team_busy;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  auto data = std::make_shared<std::vector<std::uint8_t>>(std::move(call.response.data));
  matcher_thread_.post([this, id, data, failure, later] { onCloud(id, *data, failure, later); }, true);
}

}  // namespace scan_context_loop
