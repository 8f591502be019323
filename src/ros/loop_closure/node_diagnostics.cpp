#include "loop_closure/node_diagnostics.h"

namespace scan_context_loop {

NodeDiagnostics::NodeDiagnostics(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name,
                                 const NodeCounters& counters, bool extrinsic, bool lio_sam, bool team)
    : counters_(counters), extrinsic_(extrinsic), lio_sam_(lio_sam), team_(team) {
  updater_.reset(new diagnostic_updater::Updater(nh, pnh, name));
  updater_->setHardwareID("none");
  updater_->add("loop closure", this, &NodeDiagnostics::diagnose);
  timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { updater_->update(); });
}

void NodeDiagnostics::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const NodeCounters& c = counters_;
  const std::size_t dropped = c.dropped.load(), failures = c.failures.load();
  if (failures > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%zu keyframes or service calls failed with an exception (see the log)", failures);
  } else if (c.save_failures.load() > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%zu database saves failed (see the log)",
                    c.save_failures.load());
  } else if (dropped > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%zu keyframes dropped (queue full)", dropped);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  status.add("database size", c.database_size.load());
  status.add("database bytes per keyframe", c.database_bytes_per_keyframe.load());
  status.add("registration data [bytes]", c.registration_bytes.load());
  // The memory the registration data's arenas hold (outside the heap; see CloudStore).
  status.add("registration memory [bytes]", c.registration_memory.load());
  // After the budget (verify_max_bytes) was reached: one keyframe in this many keeps its data.
  status.add("registration data kept for one keyframe in", c.registration_stride.load());
  status.add("keyframes without registration data", c.keyframes_without_registration.load());
  // What the process holds allocated through malloc, and what malloc holds free (fragmentation): with the
  // resident memory, this tells a leak from a heap that keeps freed memory for reuse. Read by the worker
  // (HeapStatistics: reading them here, on another thread, stalled the worker's allocations).
  if (c.heap_allocated.load() >= 0) {
    status.add("heap allocated [bytes]", c.heap_allocated.load());
    status.add("heap free [bytes]", c.heap_free.load());
    status.add("heap statistics read in [ms]", c.heap_statistics_ms.load());
  }
  status.add("sessions", c.sessions.load());
  status.add("database saves", c.saves.load());
  status.add("database saves failed", c.save_failures.load());
  status.add("last save [keyframes]", c.last_save_keyframes.load());
  status.add("last save written in [s]", c.last_save_seconds.load());
  status.add("corrected keyframes", c.corrected_keyframes.load());
  status.add("corrected path poses refused", c.corrections_refused.load());
  status.add("corrected path stamps unknown", c.corrections_unknown.load());
  status.add("queue length", c.queue_length.load());
  status.add("last query time [ms]", c.last_query_ms.load());
  status.add("last keyframe time [ms]", c.last_keyframe_ms.load());
  status.add("longest keyframe time [ms]", c.max_keyframe_ms.load());
  status.add("loops found", c.loops_found.load());
  status.add("verified loops waiting for support", c.loops_waiting.load());
  status.add("clouds received", c.clouds_received.load());
  status.add("clouds paired with a pose", c.clouds_paired.load());
  status.add("keyframes dropped", dropped);
  if (extrinsic_) status.add("keyframes held for the tf extrinsic", c.held.load());
  status.add("keyframes rejected", c.rejected.load());
  status.add("keyframes and service calls failed (exception)", failures);
  if (team_) {
    status.add("team records sent", c.team_records_sent.load());
    status.add("team records not published (rate cap)", c.team_records_deferred.load());
    status.add("team records received", c.team_records_received.load());
    status.add("team records already held", c.team_records_duplicate.load());
    status.add("team records refused", c.team_records_refused.load());
    status.add("team keyframes held", c.team_keyframes.load());
    status.add("team registration data served", c.team_clouds_served.load());
    status.add("team registration data fetched", c.team_clouds_fetched.load());
    status.add("team requests failed", c.team_fetch_failures.load());
    status.add("team requests answered busy", c.team_busy.load());
    status.add("team loops", c.team_loops.load());
    status.add("team loops dropped (no agreeing loop)", c.team_loops_dropped.load());
    status.add("team bytes sent", c.team_bytes_sent.load());
    status.add("team bytes received", c.team_bytes_received.load());
    status.add("team claims refused (robot id bound to another node)", c.team_claims_refused.load());
    status.add("team requests timed out", c.team_requests_timed_out.load());
    status.add("team records refused (team_max_bytes)", c.team_records_over_limit.load());
    status.add("team records memory [bytes]", c.team_record_bytes.load());
  }
  if (lio_sam_) status.add("loops not sent to LIO-SAM (not verified, repeated or too soon)", c.lio_skipped.load());
}

}  // namespace scan_context_loop
