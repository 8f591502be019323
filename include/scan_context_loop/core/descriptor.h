// The Scan Context descriptor: a rings x sectors polar grid of maximum point heights, its keys, and
// the compact form the database stores.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory_resource>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "scan_context_loop/core/config.h"

namespace scan_context_loop {

/// A read-only view of points stored with a fixed stride (pcl_adapters.h makes one of a PCL cloud), x, y and z as
/// float32 at given byte offsets. Works on PCL clouds, raw sensor_msgs/PointCloud2 data and KITTI .bin buffers without
/// copying.
struct PointView {
  const std::uint8_t* data = nullptr;
  std::size_t count = 0;
  std::size_t stride = 0;  ///< bytes from one point to the next
  std::size_t offset_x = 0;
  std::size_t offset_y = 4;
  std::size_t offset_z = 8;
};

/// Points whose height z + lidar_height exceeds this in magnitude [m] are skipped like NaN/Inf: no
/// sensor sees them, and heights near float's limit would overflow the keys' sums to infinity.
constexpr float kMaxPointHeight = 1e4f;

/// The raw polar grid. heights(r, s) is the maximum of z + lidar_height over the points in ring r,
/// sector s, or 0 when the bin holds no point; occupied(r, s) says whether it holds any, so a bin whose
/// maximum height is zero or negative is never mistaken for an empty one.
///
/// Geometry: ring r covers horizontal ranges [r, r + 1) * max_radius / num_rings (points below
/// min_range or beyond max_radius are dropped). Sector s covers azimuths [s, s + 1) * 2 pi / num_sectors,
/// the azimuth atan2(y, x) being measured counter-clockwise from +x in [0, 2 pi). Rotating the cloud by
/// +k sectors about z therefore moves column s to column s + k (mod num_sectors).
struct HeightGrid {
  Eigen::MatrixXf heights;
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic> occupied;
  std::size_t points_used = 0;     ///< points that fell into a bin
  std::size_t points_skipped = 0;  ///< NaN/Inf, beyond kMaxPointHeight or out of [min_range, max_radius]
};

/// `viewpoint` moves the grid's centre to (x, y) in the cloud's frame, axes unchanged: the scene as a
/// sensor standing there would bin it (a virtual viewpoint; occlusions are not recomputed). The
/// detector uses it to search for revisits a lane or two to the side (Config::lateral_offset_step).
HeightGrid makeHeightGrid(const PointView& points, const Config& config,
                          const Eigen::Vector2f& viewpoint = Eigen::Vector2f::Zero());

/// One grid per viewpoint, as makeHeightGrid would make each, of the points turned by `rotation` first
/// (a gravity alignment; the identity turns nothing): the points are read once for all of them, and no
/// rotated copy of the cloud is made.
std::vector<HeightGrid> makeHeightGrids(const PointView& points, const Config& config,
                                        const std::vector<Eigen::Vector2f>& viewpoints,
                                        const Eigen::Matrix3f& rotation = Eigen::Matrix3f::Identity());

/// A unit column's entries are stored as int8: the entry times kUnitColumnScale, rounded. Its length is
/// then kUnitColumnScale within the rounding, and a dot product of two columns, summed in integers and
/// divided by kUnitColumnScale^2, is their cosine within about 0.01 (a whole descriptor's distance, a
/// mean over the shared columns, much closer).
constexpr int kUnitColumnScale = 127;

/// What the distance and the database need, about 1.6 KB at 20 x 60. Its arrays are on the
/// heap unless the descriptor was made with another memory resource (a loaded database's keyframes
/// share a BlockArena); a copy is always on the heap, and so is whatever is moved *assigned* into a
/// descriptor of another resource (std::pmr copies then), so make descriptors in place or move-construct
/// them to keep them where they are.
struct Descriptor {
  Descriptor() = default;
  explicit Descriptor(std::pmr::memory_resource* memory)
      : unit_columns(memory), column_occupied(memory), ring_key(memory), sector_key(memory) {}

  int num_rings = 0;
  int num_sectors = 0;
  /// num_sectors columns of num_rings entries each (column-major), every column scaled to unit length
  /// and quantised (quantiseUnitColumn); an empty column, or one whose heights are all exactly 0, is all
  /// zeros.
  std::pmr::vector<std::int8_t> unit_columns;
  /// 1 where the column holds at least one point.
  std::pmr::vector<std::uint8_t> column_occupied;
  /// Rotation-invariant key per ring (Config::ring_key), the kd-tree coordinates.
  std::pmr::vector<float> ring_key;
  /// Mean max height per sector (empty bins as 0): drives the coarse yaw alignment.
  std::pmr::vector<float> sector_key;
  int occupied_columns = 0;

  bool empty() const { return occupied_columns == 0; }
  /// Bytes its arrays hold, on the heap or in its memory resource.
  std::size_t bytes() const;
};

Descriptor makeDescriptor(const HeightGrid& grid, const Config& config);

Descriptor makeDescriptor(const PointView& points, const Config& config,
                          const Eigen::Vector2f& viewpoint = Eigen::Vector2f::Zero());

/// Writes the column `heights` (`rings` values) scaled to unit length and quantised to `out`: each
/// entry times kUnitColumnScale, rounded to the nearest integer; all zeros when the heights are.
void quantiseUnitColumn(const float* heights, int rings, std::int8_t* out);

/// Slack for float rounding (a key against its bound, a column's length).
constexpr double kUnitColumnTolerance = 1e-3;
/// How far a quantised unit column's length, in units of kUnitColumnScale, may be off 1: each entry is
/// off by at most half a step, so the length by at most sqrt(rings) / 2 steps; plus
/// kUnitColumnTolerance (0.019 in all at 20 rings).
double quantisedColumnTolerance(int rings);

/// What in `d` (whose arrays have its grid's sizes) makeDescriptor cannot produce with `ring_key`, or ""
/// when nothing: a value that is not finite; an occupied column whose length is neither 1 (within
/// quantisedColumnTolerance) nor 0 (heights all exactly 0); an empty column with a value or a sector key that
/// is not 0; occupied_columns other than the occupied flags' count; a sector key or mean-height ring key
/// beyond kMaxPointHeight, an occupancy ring key outside [0, 1] (each with kUnitColumnTolerance of slack
/// for rounding). A file's descriptors are checked with it, so that none can match every query.
std::string descriptorImplausibility(const Descriptor& d, RingKeyType ring_key);

}  // namespace scan_context_loop
