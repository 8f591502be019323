// The registration data of every keyframe, kept for later verification within a byte budget.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "scan_context_loop/core/block_arena.h"
#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {

/// Keeps the prepared registration data of every keyframe for later verification, within a byte
/// budget. When a new keyframe would exceed it, the store keeps only every second keyframe (then every
/// fourth, ...), old and new alike: the whole map stays verifiable at a uniform, coarser spacing instead
/// of its oldest part vanishing, which matters because loop candidates are old keyframes. A candidate
/// whose data is not kept is reported as unverifiable. At 1 m voxels and 40 m an HDL-64E keyframe keeps
/// about 8,000 voxels (130 KB): the default 1 GiB holds about 8,000 keyframes at full density.
///
/// The clouds' arrays are not on the heap: each keyframe's go into the arena of its level, the number
/// of halvings that keep it (the trailing zero bits of its index: odd keyframes are level 0, the first
/// to go). A halving drops one whole level, so its arena goes back to the system whole once its clouds
/// are freed, and the heap never holds the holes that freeing half the store in place left (they slowed
/// every later keyframe and stayed resident: doc/testing.md, the soak). An arena maps 2 MB blocks of
/// ordinary pages, so what is resident exceeds bytes() by less than a page a level (memoryBytes(), what
/// is mapped, by less than 2 MB a level).
class CloudStore {
 public:
  explicit CloudStore(std::size_t max_bytes) : max_bytes_(max_bytes) {}
  /// Stores keyframe `index` if the current density keeps it (in any order: a team's fetched clouds come
  /// as they are asked for; a keyframe stored again replaces its data).
  void add(std::size_t index, const VoxelCloud& cloud);
  /// The data of keyframe `index`, or nullptr when it was never stored or was dropped.
  const VoxelCloud* get(std::size_t index) const;
  /// A share of the data of keyframe `index` (null as get()): a stored cloud never changes, and a share
  /// keeps it (and the arena memory it holds) alive after the store dropped it, on any thread
  /// (DatabaseSnapshot writes clouds while the store goes on).
  std::shared_ptr<const VoxelCloud> share(std::size_t index) const;
  /// Shares of the data of every stored keyframe in [begin, end), by index, in order.
  std::vector<std::pair<std::size_t, std::shared_ptr<const VoxelCloud>>> share(std::size_t begin,
                                                                               std::size_t end) const;
  /// Bytes of the voxels kept (what the budget counts).
  std::size_t bytes() const { return bytes_; }
  /// Bytes of memory the kept keyframes' arenas hold (bytes() plus each level's unused block end).
  std::size_t memoryBytes() const;
  /// Keyframes whose data are kept (counted as they come and go: the node reads it every keyframe).
  std::size_t stored() const { return stored_; }
  std::size_t dropped() const { return dropped_; }
  /// Data are kept for the keyframe numbers that are multiples of this (1 until the budget is reached;
  /// doubled by each halving).
  std::size_t stride() const { return stride_; }
  std::size_t maxBytes() const { return max_bytes_; }
  /// Dropped clouds still to be freed: halving the density takes them out at once (get() no longer
  /// serves them, bytes() no longer counts them) but frees at most kReleasedPerAdd of them in each later
  /// add(), so no single keyframe pays for freeing half the store; their level's memory goes back to the
  /// system with the last of them.
  std::size_t releasing() const { return releasing_.size(); }
  static constexpr std::size_t kReleasedPerAdd = 64;
  /// The level of keyframe `index`: its data stay while the stride is at most 2^level.
  static int levelOf(std::size_t index);
  /// The block size of each level's arena.
  static constexpr std::size_t kLevelBlockBytes = std::size_t(2) << 20;

 private:
  std::size_t max_bytes_;
  std::size_t bytes_ = 0;
  std::size_t dropped_ = 0;
  std::size_t stored_ = 0;
  std::size_t stride_ = 1;  // data are kept for keyframe numbers that are multiples of this
  // By keyframe index, the stored ones only: a store holds a few thousand of a database's keyframes,
  // and a save shares them without walking a slot for each of a million keyframes.
  std::map<std::size_t, std::shared_ptr<const VoxelCloud>> clouds_;
  std::vector<BlockArena::Handle> levels_;                    // by level; null before its first cloud and once dropped
  std::vector<std::shared_ptr<const VoxelCloud>> releasing_;  // dropped, memory not yet freed
};

/// The warning for a store whose stride grew past `previous_stride` (one or more halvings since), "" when
/// it did not: what was lost, what it means for verification and saving, and what to change.
/// `keyframes` is the database's size.
std::string cloudStoreHalvingWarning(std::size_t previous_stride, const CloudStore& store, std::size_t keyframes);

}  // namespace scan_context_loop
