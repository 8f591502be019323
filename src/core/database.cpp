#include "scan_context_loop/core/database.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include <flann/flann.hpp>

namespace scan_context_loop {

/// k-nearest ring keys over a growing prefix of the database: a FLANN index over the keys it was last
/// built with, plus a brute-force scan over the keys added since (the tail). Up to `exact_limit` keys
/// the index is one balanced kd-tree (leaves of up to 10 keys) searched exactly; above it, kTrees
/// randomized kd-trees searched until kChecks keys have been compared, a cost that no longer grows
/// with the database.
///
/// Rebuilds run off the caller's thread. When the tail reaches startAt() keys, a builder thread
/// copies the index's keys and that tail prefix (the snapshot) and builds a new index over them; the
/// caller keeps answering from the old index and the whole tail meanwhile. The new index is swapped in
/// when the tail is about to pass swapAt() = 2 startAt() keys. Below exact_limit the caller waits for
/// the builder if it has not finished by then, so which index answers a query never depends on timing
/// and a run gives the same candidates every time. Above it (where the randomized trees of Debian's
/// FLANN shuffle with std::random_device whatever the seed, so runs may differ anyway) a late build is
/// not waited for: the tail grows on into the room reserved for it (2 swapAt() keys) and the index is
/// swapped in at the first call after it is done; only a build still unfinished when that room is full
/// is waited for. At 1,000,000 keys a build takes about two seconds: a node adding 20 keyframes a
/// second fills the tail's second half in minutes, the benchmark's loop adding thousands a second in
/// about one and a half seconds (one step waited 66 ms for a build before late builds went on). A batch
/// that would carry the tail past swapAt() with no build in flight (a loaded database joining) is
/// built at once on the caller's thread while the index stays exact; a batch that makes it approximate
/// is built by the builder like any other, the caller scanning the whole tail meanwhile (exact answers,
/// a few milliseconds a query at 1,000,000 keys) and swapping the index in at its first call after the
/// build is done: a node that loads a large database starts answering before its kd-tree is built.
///
/// Ownership while a build is in flight: the builder reads `current.keys` and the first `snapshot`
/// keys of `tail` and writes only `next`. The caller only reads `current` then, and appends to `tail`
/// within the capacity reserved at the start (`tail_room` keys: its first keys never move); it touches
/// `next` only after joining the builder (in finishBuild() or the destructor), which orders the
/// builder's writes before its reads. No mutex is needed.
///
/// The tail is a contiguous copy of its keys: scanned through the keyframes' own descriptors, each key
/// on a page of its own, a 5,000-key tail cost a TLB miss a key. It stays below 4 kMaxStart keys, so
/// its scan costs a fraction of a millisecond at any database size, except while a large batch's
/// build runs (above).
struct Database::Tree {
  static constexpr std::size_t kMinStart = 1024;
  static constexpr std::size_t kMaxStart = 8192;
  static constexpr int kTrees = 2;
  static constexpr int kChecks = 128;

  /// An index and the keys it was built over (it keeps pointers into them).
  struct Built {
    std::vector<float> keys;  // contiguous, in database order
    std::size_t count = 0;
    std::unique_ptr<flann::Index<flann::L2<float>>> index;
  };

  Tree(int dims, std::size_t exact_limit) : dims(dims), exact_limit(exact_limit) {}
  ~Tree() {
    if (builder.joinable()) builder.join();
  }

  std::size_t tailCount() const { return tail.size() / static_cast<std::size_t>(dims); }
  std::size_t size() const { return current.count + tailCount(); }
  /// The tail size at which a build starts, and the one it must not pass before the build is swapped in.
  std::size_t startAt() const { return std::clamp(current.count / 32, kMinStart, kMaxStart); }
  std::size_t swapAt() const { return 2 * startAt(); }
  bool building() const { return builder.joinable(); }

  /// Takes the keys of the keyframes now eligible.
  void add(const std::vector<const float*>& added) {
    poll();
    if (building() && tailCount() + added.size() > swap_at) {
      // Late: above the exact limit the tail grows on into its room and the index is swapped in once
      // it is done; below it, or with the room full, the caller waits.
      if (approximate(size() + added.size()) && tailCount() + added.size() <= tail_room) {
        swap_when_built = true;
      } else {
        finishBuild();
      }
    }
    if (!building() && tailCount() + added.size() > swapAt() && approximate(size() + added.size())) {
      // A batch that makes the index approximate (a large database joining): built on the builder's
      // thread like any other, swapped in at the first call after it is done (runs above the exact
      // limit may differ anyway); meanwhile queries scan the whole tail, exactly.
      const std::size_t batch_swap_at = tailCount() + added.size() + swapAt();
      tail.reserve(batch_swap_at * static_cast<std::size_t>(dims));
      adviseHugePages(tail.data(), tail.capacity() * sizeof(float));
      for (const float* key : added) tail.insert(tail.end(), key, key + dims);
      ++builds.batches_behind;
      swap_when_built = true;
      startBuild(batch_swap_at, batch_swap_at);
      return;
    }
    if (!building() && tailCount() + added.size() > swapAt()) {
      // A batch below the exact limit (a small database joining, a wide query window): one build, here
      // and now, so that which index answers never depends on timing.
      tail.reserve(tail.size() + added.size() * static_cast<std::size_t>(dims));
      for (const float* key : added) tail.insert(tail.end(), key, key + dims);
      ++builds.at_once;
      Built built;
      built.keys.swap(current.keys);
      built.keys.insert(built.keys.end(), tail.begin(), tail.end());
      tail.clear();
      buildIndex(&built);
      current = std::move(built);
      return;
    }
    for (const float* key : added) tail.insert(tail.end(), key, key + dims);
    if (!building() && tailCount() >= startAt()) startBuild(swapAt(), 2 * swapAt());
  }

  /// A batch's build that has finished is swapped in (the caller's every call: add, query).
  void poll() {
    if (building() && swap_when_built && built_yet) finishBuild();
  }

  /// Starts a build over the whole tail, to be swapped in before the tail passes `swap_at_count` keys
  /// (when late, above the exact limit, before it passes `room_count`, the room reserved for the tail).
  void startBuild(std::size_t swap_at_count, std::size_t room_count) {
    swap_at = swap_at_count;
    tail_room = room_count;
    tail.reserve(tail_room * static_cast<std::size_t>(dims));
    snapshot = tailCount();
    const float* from = tail.data();
    const std::size_t values = snapshot * static_cast<std::size_t>(dims);
    ++builds.background;
    built_yet = false;
    builder = std::thread([this, from, values] {
      // What the last swap replaced, freed here rather than on the owner's thread.
      retired = Built();
      std::vector<float>().swap(retired_tail);
      next.keys.reserve(current.keys.size() + values);
      next.keys.assign(current.keys.begin(), current.keys.end());
      next.keys.insert(next.keys.end(), from, from + values);
      buildIndex(&next);
      built_yet = true;
    });
  }

  /// Waits for the builder and swaps its index in; the tail keeps the keys that came after the snapshot.
  void finishBuild() {
    if (!built_yet) ++builds.waited;
    builder.join();
    // The old index and its keys (at a million keyframes, 80 MB and the trees' nodes) are freed by the
    // next build's thread: unmapping them here cost the step that swapped.
    retired = std::move(current);
    current = std::move(next);
    next = Built();
    tail.erase(tail.begin(), tail.begin() + static_cast<long>(snapshot) * dims);
    swap_when_built = false;
    // A batch's tail held every key of it; keep no more room than the usual builds need.
    if (tail.capacity() > 2 * swapAt() * static_cast<std::size_t>(dims)) {
      std::vector<float> kept(tail.begin(), tail.end());
      retired_tail.swap(tail);  // the batch's room (80 MB at a million keys), freed by the next build
      tail.swap(kept);
    }
  }

  bool approximate(std::size_t count) const { return count > exact_limit; }
  bool approximate() const { return approximate(current.count); }

  void buildIndex(Built* built) const {
    built->count = built->keys.size() / static_cast<std::size_t>(dims);
    built->index.reset();
    if (built->count == 0) return;
    flann::Matrix<float> matrix(built->keys.data(), built->count, dims);
    if (approximate(built->count)) {
      static std::mutex seeded;  // std::rand's state is the process's: one seeded build at a time
      std::lock_guard<std::mutex> lock(seeded);
      flann::seed_random(1);  // the trees' random split choices
      built->index.reset(new flann::Index<flann::L2<float>>(matrix, flann::KDTreeIndexParams(kTrees)));
      built->index->buildIndex();
    } else {
      built->index.reset(new flann::Index<flann::L2<float>>(matrix, flann::KDTreeSingleIndexParams(10)));
      built->index->buildIndex();
    }
  }

  /// The `want` nearest keys as (squared distance, index), nearest first.
  std::vector<std::pair<float, std::size_t>> nearest(const float* query, std::size_t want) const {
    std::vector<std::pair<float, std::size_t>> found;
    found.reserve(want + 1);
    const std::size_t built = current.count;
    if (current.index && built > 0) {
      std::vector<std::vector<std::size_t>> indices;
      std::vector<std::vector<float>> dists;
      std::vector<float> q(query, query + dims);
      flann::SearchParams params(approximate() ? kChecks : flann::FLANN_CHECKS_UNLIMITED);
      params.sorted = true;
      current.index->knnSearch(flann::Matrix<float>(q.data(), 1, dims), indices, dists, std::min(want, built), params);
      for (std::size_t i = 0; i < indices[0].size(); ++i) found.emplace_back(dists[0][i], indices[0][i]);
    }
    // The tail streams through a max-heap of the `want` nearest so far (by distance, then index: the
    // same keys a full sort would keep): no list of every tail key to sort, which cost 0.1-0.2 ms a
    // query at a 6,000-key tail.
    if (found.size() > want) found.resize(want);
    std::make_heap(found.begin(), found.end());
    // Eight keys at a time, each summed in ring order as one at a time would: eight independent sums
    // instead of one chain of dependent additions. A loaded batch's tail of a million keys (80 MB, read
    // at memory speed) takes about 6.5 ms a query while its kd-tree is built.
    constexpr std::size_t kBlock = 8;
    const std::size_t d = static_cast<std::size_t>(dims);
    const float* key = tail.data();
    for (std::size_t i = built; i < size(); i += kBlock, key += kBlock * d) {
      const std::size_t n = std::min(kBlock, size() - i);
      float d2[kBlock] = {};
      if (n == kBlock) {
        for (std::size_t r = 0; r < d; ++r) {
          for (std::size_t j = 0; j < kBlock; ++j) {
            const float diff = key[j * d + r] - query[r];
            d2[j] += diff * diff;
          }
        }
      } else {
        for (std::size_t j = 0; j < n; ++j) {
          for (std::size_t r = 0; r < d; ++r) {
            const float diff = key[j * d + r] - query[r];
            d2[j] += diff * diff;
          }
        }
      }
      for (std::size_t j = 0; j < n; ++j) offer({d2[j], i + j}, want, &found);
    }
    std::sort_heap(found.begin(), found.end());
    return found;
  }

  /// Keeps `entry` in the max-heap `found` of the `want` nearest (by distance, then index).
  static void offer(const std::pair<float, std::size_t>& entry, std::size_t want,
                    std::vector<std::pair<float, std::size_t>>* found) {
    if (found->size() < want) {
      found->push_back(entry);
      std::push_heap(found->begin(), found->end());
    } else if (want > 0 && entry < found->front()) {
      std::pop_heap(found->begin(), found->end());
      found->back() = entry;
      std::push_heap(found->begin(), found->end());
    }
  }

  int dims;
  std::size_t exact_limit;
  Built current;                    // the index queries use
  std::vector<float> tail;          // the keys added since `current` was built, contiguous, in database order
  std::thread builder;              // joinable while a build is in flight
  std::size_t snapshot = 0;         // tail keys the build in flight covers
  std::size_t swap_at = 0;          // the tail size it is swapped in before passing (below the exact limit)
  std::size_t tail_room = 0;        // the tail's reserved capacity [keys] while a build runs: never passed
  Built next;                       // the builder's result; the caller reads it only after joining
  Built retired;                    // swapped out by finishBuild; the next builder frees it (touched by one at a time)
  std::vector<float> retired_tail;  // a batch's tail room, likewise
  std::atomic<bool> built_yet{true};  // the builder has finished (it may not have returned yet)
  bool swap_when_built = false;       // the build in flight (a batch's, or a late one above the exact
                                      // limit) is swapped in at the first call after it is done
  IndexBuilds builds;
};

Database::Database(const Config& config)
    : config_(config), tree_(new Tree(config.num_rings, static_cast<std::size_t>(config.exact_search_limit))) {}

Database::~Database() {
  for (std::size_t i = 0; i < keyframes_.size(); ++i) {
    Keyframe* keyframe = const_cast<Keyframe*>(keyframes_[i]);  // placed by place(), owned here
    keyframe->~Keyframe();
    records_->deallocate(keyframe, sizeof(Keyframe), alignof(Keyframe));
  }
}

const Keyframe& Database::keyframe(std::size_t index) const {
  if (index >= keyframes_.size()) {
    throw std::out_of_range("keyframe " + std::to_string(index) + " of " + std::to_string(keyframes_.size()));
  }
  return *keyframes_[index];
}

const Keyframe* Database::place(Keyframe&& keyframe) {
  void* memory = records_->allocate(sizeof(Keyframe), alignof(Keyframe));
  return new (memory) Keyframe(std::move(keyframe));
}

namespace {

/// How far R^T R of a pose's rotation may stray from the identity (largest entry): poses read from
/// text with 7 digits or through float stay far below it; a scaled matrix (an unnormalised
/// quaternion's) does not.
constexpr double kRotationTolerance = 1e-3;

bool isRotation(const Eigen::Matrix3d& r) {
  const double stray = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  return stray <= kRotationTolerance && r.determinant() > 0.0;
}

/// Why a keyframe with `info` cannot follow `previous` (its session's last keyframe, or null) in a
/// session; empty when it can.
std::string infoProblem(const KeyframeInfo& info, const KeyframeInfo* previous) {
  // The text is made only for a problem, not a stream for every keyframe checked.
  if (!std::isfinite(info.stamp)) return "keyframe stamp is not finite";
  if (previous && info.stamp < previous->stamp) {
    std::ostringstream why;
    why.precision(17);
    why << "keyframe stamp " << info.stamp << " is earlier than the previous keyframe's " << previous->stamp;
    return why.str();
  }
  if (info.pose && !info.pose->matrix().allFinite()) return "keyframe pose is not finite";
  if (info.pose && !isRotation(info.pose->linear())) {
    return "keyframe pose's rotation is not a rotation (not orthonormal, or a mirror)";
  }
  return "";
}

bool fitsGrid(const Descriptor& d, const Config& config) {
  const auto rings = static_cast<std::size_t>(config.num_rings);
  const auto sectors = static_cast<std::size_t>(config.num_sectors);
  return d.num_rings == config.num_rings && d.num_sectors == config.num_sectors &&
         d.unit_columns.size() == rings * sectors && d.column_occupied.size() == sectors &&
         d.ring_key.size() == rings && d.sector_key.size() == sectors;
}

bool allFinite(const std::pmr::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

/// Why `d` can be neither stored nor queried: its grid differs from the configuration, or a value is
/// not finite (an infinite ring key would stay in the kd-tree for good); empty when it can.
std::string descriptorProblem(const Descriptor& d, const Config& config) {
  if (!fitsGrid(d, config)) return "descriptor grid size differs from the database configuration";
  if (!allFinite(d.ring_key) || !allFinite(d.sector_key)) {  // unit_columns are int8, always finite
    return "descriptor values are not finite";
  }
  return "";
}

}  // namespace

bool Database::acceptable(const KeyframeInfo& info, std::string* error) const {
  const std::string text = infoProblem(info, keyframes_.size() > session_start_ ? &keyframes_.back()->info : nullptr);
  if (error) *error = text;
  return text.empty();
}

bool Database::add(const KeyframeInfo& info, Descriptor descriptor, std::string* error) {
  if (!acceptable(info, error)) return false;
  const std::string problem = descriptorProblem(descriptor, config_);
  if (!problem.empty()) {
    if (error) *error = problem;
    return false;
  }
  Keyframe keyframe;
  keyframe.info = info;
  keyframe.path_length = pathLengthAt(info);
  keyframe.session = session_;
  keyframe.descriptor = std::move(descriptor);
  keyframes_.reserve(keyframes_.size() + 1);  // first: appending the placed record then cannot fail
  keyframes_.push_back(place(std::move(keyframe)));
  return true;
}

bool Database::appendSessions(std::vector<Keyframe> keyframes, std::string* error, bool values_checked) {
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const Keyframe& k = keyframes[i];
    const Keyframe* previous = i > 0 ? &keyframes[i - 1] : nullptr;
    const bool continues = previous && k.session == previous->session;
    std::string problem;
    if (!previous && k.session != 0) {
      problem = "the first keyframe is in session " + std::to_string(k.session) + ", not 0";
    } else if (previous && !continues && k.session != previous->session + 1) {
      problem = "session " + std::to_string(k.session) + " follows session " + std::to_string(previous->session) +
                " (sessions are numbered 0, 1, ... in order)";
    } else if (!(std::isfinite(k.path_length) && k.path_length >= 0.0)) {
      problem = "path length is not a finite non-negative number";
    } else {
      problem = !values_checked                   ? descriptorProblem(k.descriptor, config_)
                : fitsGrid(k.descriptor, config_) ? ""
                                                  : "descriptor grid size differs from the database configuration";
      if (problem.empty()) problem = infoProblem(k.info, continues ? &previous->info : nullptr);
    }
    if (!problem.empty()) {
      if (error) *error = "keyframe " + std::to_string(i) + ": " + problem;
      return false;
    }
  }
  if (keyframes.empty()) {
    startSession();
    return true;
  }
  const std::uint32_t first = keyframes_.size() == session_start_ ? session_ : session_ + 1;
  // The records' new memory is set up on another thread while they move in (place() takes each from
  // records_).
  const PageWarmer warmer({records_->reserve(keyframes.size() * sizeof(Keyframe) + alignof(std::max_align_t))});
  keyframes_.reserve(keyframes_.size() + keyframes.size());
  for (Keyframe& k : keyframes) {
    k.session += first;
    keyframes_.push_back(place(std::move(k)));
  }
  session_ = keyframes_.back()->session + 1;
  session_start_ = keyframes_.size();
  indexUpTo(keyframes_.size());
  return true;
}

void Database::startSession() {
  if (keyframes_.size() == session_start_) return;
  ++session_;
  session_start_ = keyframes_.size();
}

double Database::pathLengthAt(const KeyframeInfo& info) const {
  if (keyframes_.size() == session_start_) return 0.0;
  double length = keyframes_.back()->path_length;
  // Walk back to the session's latest keyframe with a pose, so keyframes without one do not break the
  // chain.
  if (info.pose) {
    for (std::size_t i = keyframes_.size(); i > session_start_; --i) {
      const Keyframe& k = *keyframes_[i - 1];
      if (k.info.pose) {
        length += (info.pose->translation() - k.info.pose->translation()).norm();
        break;
      }
    }
  }
  return length;
}

std::size_t Database::eligibleCount(const KeyframeInfo& info) const {
  // Earlier sessions are always eligible; the windows cut a suffix of the current one, along which stamps
  // and path lengths never decrease.
  if (config_.prior_sessions_only) return session_start_;
  const std::size_t in_session = keyframes_.size() - session_start_;
  const std::size_t frames = static_cast<std::size_t>(config_.exclude_recent_frames);
  std::size_t eligible = session_start_ + (in_session > frames ? in_session - frames : 0);
  // The first keyframe in [session_start_, eligible) whose value passes `latest` (upper bound).
  const auto firstAfter = [this, &eligible](double latest, double (*value)(const Keyframe&)) {
    std::size_t lo = session_start_, hi = eligible;
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (latest < value(*keyframes_[mid])) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
    return lo;
  };
  if (config_.exclude_recent_seconds > 0.0) {
    eligible = firstAfter(info.stamp - config_.exclude_recent_seconds, [](const Keyframe& k) { return k.info.stamp; });
  }
  if (config_.exclude_recent_distance > 0.0) {
    eligible = firstAfter(pathLengthAt(info) - config_.exclude_recent_distance,
                          [](const Keyframe& k) { return k.path_length; });
  }
  return eligible;
}

void Database::indexUpTo(std::size_t count) {
  if (count <= indexed_) return;
  std::vector<const float*> keys;
  keys.reserve(count - indexed_);
  for (std::size_t i = indexed_; i < count; ++i) keys.push_back(keyframes_[i]->descriptor.ring_key.data());
  tree_->add(keys);
  indexed_ = count;
}

QueryResult Database::query(const Descriptor& descriptor, const KeyframeInfo& info) {
  QueryResult result;
  if (descriptor.empty() || !descriptorProblem(descriptor, config_).empty()) return result;
  tree_->poll();
  const std::size_t eligible = eligibleCount(info);
  result.eligible = eligible;
  if (eligible == 0) return result;
  // The tree only grows; a query whose windows are wider than an earlier one's (a query-only call
  // with a later stamp came first) asks for more neighbours and drops the ones past its prefix.
  indexUpTo(std::max(indexed_, eligible));
  const std::size_t surplus = indexed_ - eligible;
  const std::size_t want = std::min(indexed_, static_cast<std::size_t>(config_.num_candidates) + surplus);

  const double path = pathLengthAt(info);
  for (const auto& [d2, index] : tree_->nearest(descriptor.ring_key.data(), want)) {
    if (index >= eligible) continue;
    if (result.candidates.size() >= static_cast<std::size_t>(config_.num_candidates)) break;
    if (!withinOdometryGate(info, path, index)) continue;
    Candidate c;
    c.index = index;
    c.ring_key_distance = std::sqrt(std::max(0.0f, d2));
    c.alignment = align(descriptor, keyframes_[index]->descriptor, config_);
    result.candidates.push_back(c);
  }
  std::stable_sort(result.candidates.begin(), result.candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.alignment.distance < b.alignment.distance; });
  result.matched =
      !result.candidates.empty() && result.candidates.front().alignment.distance < config_.distance_threshold;
  return result;
}

bool Database::withinOdometryGate(const KeyframeInfo& info, double path, std::size_t index) const {
  if (!(config_.gate_odometry_distance > 0.0 || config_.gate_odometry_drift > 0.0)) return true;
  const Keyframe& candidate = *keyframes_[index];
  // Nothing to gate on: no pose, or another session's odometry frame.
  if (!info.pose || !candidate.info.pose || candidate.session != session_) return true;
  // Where the odometry puts the candidate directly, or through the nearest confirmed loop: either will
  // do. From a loop the odometry is relied on over a shorter path, but a stretch where it lost its
  // way (a slip along a featureless street) may lie in between.
  const double direct_path = std::max(0.0, path - candidate.path_length);
  const double direct = (info.pose->translation() - candidate.info.pose->translation()).norm();
  if (direct <= gateRadius(config_, trust_, direct_path)) return true;
  const OdometryPrediction predicted = trust_.predict(*info.pose, path, session_, candidate);
  return predicted.anchored && predicted.relative.translation().norm() <= gateRadius(config_, trust_, predicted.path);
}

Database::IndexBuilds Database::indexBuilds() const {
  IndexBuilds builds = tree_->builds;
  builds.in_flight = tree_->building();
  builds.finished = tree_->built_yet;
  return builds;
}

std::size_t Database::bytesPerKeyframe() const {
  // Descriptor heap storage plus the Keyframe record itself and its address, plus the tree's share: the contiguous key
  // copy and FLANN's per-point index and node share, twice: while a build is in flight (at 1,000,000
  // keyframes, most of the time) the new index and its key copy exist beside the old ones.
  std::size_t descriptor_bytes = 0;
  if (!keyframes_.empty()) {
    descriptor_bytes = keyframes_.back()->descriptor.bytes();
  } else {
    descriptor_bytes = static_cast<std::size_t>(config_.num_rings) * config_.num_sectors * sizeof(std::int8_t) +
                       (config_.num_rings + config_.num_sectors) * sizeof(float) + config_.num_sectors;
  }
  // FLANN's share: the single exact tree ~32 bytes a key; the randomized trees of a larger database a
  // point pointer plus, per tree, two 32-byte nodes (leaves hold one key) and an index.
  const std::size_t index_bytes = tree_->approximate() ? sizeof(float*) + Tree::kTrees * (2 * 32 + sizeof(int)) : 32;
  const std::size_t key_bytes = static_cast<std::size_t>(config_.num_rings) * sizeof(float);
  return descriptor_bytes + sizeof(Keyframe) + sizeof(const Keyframe*) + 2 * (key_bytes + index_bytes);
}

}  // namespace scan_context_loop
