#include "scan_context_loop/core/cloud_store.h"

#include <limits>
#include <sstream>

namespace scan_context_loop {

int CloudStore::levelOf(std::size_t index) {
  return index == 0 ? std::numeric_limits<std::size_t>::digits : __builtin_ctzll(index);
}

void CloudStore::add(std::size_t index, const VoxelCloud& cloud) {
  // Free a few of the clouds the last halving dropped (freeing half of 50,000 at once stalled the
  // keyframe that triggered it for 0.3 s, and at 100,000 for 0.7 s, in scripts/measure/soak).
  for (std::size_t n = 0; n < kReleasedPerAdd && !releasing_.empty(); ++n) releasing_.pop_back();
  if (index % stride_ != 0) return;  // between the kept keyframes at the current density
  const std::size_t size = cloud.bytes();
  while (bytes_ + size > max_bytes_ && stride_ < (std::size_t(1) << 30)) {
    // Halve the density everywhere: keep only multiples of the doubled stride, which drops the level
    // log2(stride_) whole. Its clouds leave the store now and are freed over the next adds; its arena
    // lives until the last of them is gone.
    const auto dropped_level = static_cast<std::size_t>(levelOf(stride_));
    stride_ *= 2;
    for (auto it = clouds_.begin(); it != clouds_.end();) {
      if (it->first % stride_ != 0) {
        bytes_ -= it->second->bytes();
        releasing_.push_back(std::move(it->second));
        it = clouds_.erase(it);
        ++dropped_;
        --stored_;
      } else {
        ++it;
      }
    }
    if (dropped_level < levels_.size()) levels_[dropped_level].reset();
    if (index % stride_ != 0) return;
  }
  const auto level = static_cast<std::size_t>(levelOf(index));
  if (levels_.size() <= level) levels_.resize(level + 1);
  if (!levels_[level]) levels_[level] = BlockArena::create(kLevelBlockBytes, BlockArena::Pages::kOrdinary);
  // The copy's arrays are exactly as long as the voxels, so the budget counts what they take.
  auto copy = std::make_shared<const VoxelCloud>(cloud, levels_[level].get());
  std::shared_ptr<const VoxelCloud>& slot = clouds_[index];
  if (slot) {
    bytes_ -= slot->bytes();  // stored again: the new data replace the old
  } else {
    ++stored_;
  }
  slot = std::move(copy);
  bytes_ += size;
}

std::string cloudStoreHalvingWarning(std::size_t previous_stride, const CloudStore& store, std::size_t keyframes) {
  if (store.stride() <= previous_stride) return "";
  const std::size_t without = keyframes > store.stored() ? keyframes - store.stored() : 0;
  std::ostringstream out;
  out << "the registration data reached verify_max_bytes (" << store.maxBytes() / (1024 * 1024)
      << " MiB): one keyframe in " << store.stride() << " keeps its data from now on; " << without << " of "
      << keyframes
      << " keyframes have none, so loops to them cannot be verified and a database saved with clouds holds "
         "none for them; raise verify_max_bytes to keep more";
  return out.str();
}

std::size_t CloudStore::memoryBytes() const {
  std::size_t total = 0;
  for (const auto& level : levels_) total += level ? level->mappedBytes() : 0;
  return total;
}

const VoxelCloud* CloudStore::get(std::size_t index) const {
  const auto it = clouds_.find(index);
  return it != clouds_.end() ? it->second.get() : nullptr;
}

std::shared_ptr<const VoxelCloud> CloudStore::share(std::size_t index) const {
  const auto it = clouds_.find(index);
  return it != clouds_.end() ? it->second : nullptr;
}

std::vector<std::pair<std::size_t, std::shared_ptr<const VoxelCloud>>> CloudStore::share(std::size_t begin,
                                                                                         std::size_t end) const {
  std::vector<std::pair<std::size_t, std::shared_ptr<const VoxelCloud>>> shared;
  for (auto it = clouds_.lower_bound(begin); it != clouds_.end() && it->first < end; ++it) shared.push_back(*it);
  return shared;
}

}  // namespace scan_context_loop
