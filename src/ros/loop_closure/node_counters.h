// The loop-closure node's counters and gauges: written by the input callbacks and the worker, read by the
// diagnostics and the input checks. Each is an atomic on its own, so no lock guards them; a reader may
// see one updated before another.
#pragma once

#include <atomic>
#include <cstddef>

namespace scan_context_loop {

struct NodeCounters {
  // Keyframes lost or refused: queue full or held too long (dropped), unusable (rejected), or a
  // keyframe or service call that threw (failures).
  std::atomic<std::size_t> dropped{0}, rejected{0}, failures{0};
  // The worker's view of the database and the detector.
  std::atomic<std::size_t> loops_found{0}, database_size{0}, loops_waiting{0}, lio_skipped{0}, sessions{1};
  std::atomic<std::size_t> registration_bytes{0}, registration_memory{0}, database_bytes_per_keyframe{0};
  // The cloud store's density (one keyframe in registration_stride keeps its data) and the keyframes
  // whose data it does not hold (with verification on).
  std::atomic<std::size_t> registration_stride{1}, keyframes_without_registration{0};
  std::atomic<std::size_t> queue_length{0};  ///< keyframes waiting in the queue
  std::atomic<std::size_t> held{0};          ///< keyframes the worker holds for the tf extrinsic
  // Clouds that reached the node, and those that became keyframes (paired with a pose, or taken alone
  // with tf poses): a cloud lost before the node (roscpp's subscriber queue of sync_queue_size) is in
  // neither; one whose pose never came is in the first only.
  std::atomic<std::size_t> clouds_received{0}, clouds_paired{0};
  // Database saves written (autosaves, ~save_database, the shutdown save) and failed, and the last one's
  // keyframes and wall time [s] (written by the threads that write them).
  std::atomic<std::size_t> saves{0}, save_failures{0}, last_save_keyframes{0};
  std::atomic<double> last_save_seconds{0.0};
  // Keyframes with a corrected pose from corrected_path (a save writes their session corrected), the
  // poses (or whole paths) of corrected_path refused, and its poses at stamps of no keyframe recorded here.
  std::atomic<std::size_t> corrected_keyframes{0}, corrections_refused{0}, corrections_unknown{0};
  // Several robots (team_exchange.h): records of this robot's keyframes sent (published, or served on
  // request) and not published for the rate cap; the others' records taken, already held, refused; their
  // keyframes held; registration data served and fetched, fetches failed, requests answered busy, loops
  // into the others' keyframes, and the bytes sent and received (serialised messages and responses).
  std::atomic<std::size_t> team_records_sent{0}, team_records_deferred{0}, team_records_received{0};
  std::atomic<std::size_t> team_records_duplicate{0}, team_records_refused{0}, team_keyframes{0};
  std::atomic<std::size_t> team_clouds_served{0}, team_clouds_fetched{0}, team_fetch_failures{0}, team_busy{0};
  std::atomic<std::size_t> team_loops{0}, team_loops_dropped{0}, team_bytes_sent{0}, team_bytes_received{0};
  // Peers that misbehave: claims to a robot id bound to another node (or with an invalid node name)
  // refused, requests that got no answer in time, records refused over team_max_bytes, and the memory the
  // records held take [bytes].
  std::atomic<std::size_t> team_claims_refused{0}, team_requests_timed_out{0}, team_records_over_limit{0};
  std::atomic<std::size_t> team_record_bytes{0};
  std::atomic<long long> heap_allocated{-1}, heap_free{-1};  ///< malloc's statistics at the worker's last read
  std::atomic<double> heap_statistics_ms{0.0};
  std::atomic<double> last_query_ms{0.0}, last_keyframe_ms{0.0}, max_keyframe_ms{0.0};
  // Wall times [s] of the last cloud, pose pair and odometry, and of the first cloud still unpaired (0:
  // none), for the input checks.
  std::atomic<double> last_cloud_wall{0.0}, last_pair_wall{0.0}, first_unpaired_wall{0.0}, last_odom_wall{0.0};
};

}  // namespace scan_context_loop
