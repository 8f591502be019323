// Where the street generator may put things: clear of every driven road, and clear of what it has
// already placed. Internal to the simulator library.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

/// An oriented rectangle on the ground plane.
struct Footprint {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  Eigen::Vector2d half = Eigen::Vector2d::Zero();

  /// Distance from p to the rectangle (0 inside it).
  double distanceTo(const Eigen::Vector2d& p) const;
  /// Axis-aligned bounds grown by `margin`.
  void bounds(double margin, Eigen::Vector2d* lo, Eigen::Vector2d* hi) const;
  /// Whether the two rectangles overlap once this one is grown by `margin` (negative: shrunk), so that
  /// rectangles which merely touch do not count (separating-axis test).
  bool overlaps(const Footprint& other, double margin) const;
};

/// Items in a hash grid over the ground plane, looked up by the cells a rectangle covers.
class CellHash {
 public:
  explicit CellHash(double cell) : cell_(cell) {}
  void insert(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, std::uint32_t item);
  /// Calls fn(item) for the items of every cell that [lo, hi] touches (an item may come more than once);
  /// stops early when fn returns false. Returns false when it stopped early.
  template <typename Fn>
  bool forEach(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, Fn fn) const {
    for (int i = index(lo.x()); i <= index(hi.x()); ++i) {
      for (int j = index(lo.y()); j <= index(hi.y()); ++j) {
        const auto it = cells_.find(key(i, j));
        if (it == cells_.end()) continue;
        for (std::uint32_t item : it->second) {
          if (!fn(item)) return false;
        }
      }
    }
    return true;
  }

 private:
  int index(double v) const;
  static std::int64_t key(int i, int j) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32 |
                                     static_cast<std::uint32_t>(j));
  }
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

/// The driven path as road centre points.
class RoadMap {
 public:
  explicit RoadMap(const std::vector<PathPoint>& dense);
  /// True when no path point lies within `clearance` of the rectangle.
  bool clear(const Footprint& f, double clearance) const;

 private:
  std::vector<Eigen::Vector2d> points_;
  CellHash grid_;
};

/// The footprints placed so far.
class Occupancy {
 public:
  Occupancy() : grid_(8.0) {}
  /// True when f, grown by `margin`, overlaps nothing placed.
  bool free(const Footprint& f, double margin) const;
  void mark(const Footprint& f);

 private:
  std::vector<Footprint> placed_;
  CellHash grid_;
};

/// The path resampled every `spacing` metres along straight segments between its points.
std::vector<PathPoint> densify(const std::vector<PathPoint>& path, double spacing);

}  // namespace sim
}  // namespace scan_context_loop
