// Configuration of the ROS-free Scan Context core.
#pragma once

#include <string>
#include <vector>

namespace scan_context_loop {

/// What the rotation-invariant ring key holds for each ring.
enum class RingKeyType {
  /// Fraction of the ring's sectors that hold points. Insensitive to height changes (parked trucks,
  /// a different lidar_height) and to negative heights; chosen as default by measurement (README).
  kOccupancy,
  /// Mean of the ring's max heights, empty sectors counting as 0 (the published Scan Context key).
  kMeanHeight,
};

/// Parses "occupancy" / "mean_height"; returns false for anything else.
bool parseRingKeyType(const std::string& text, RingKeyType* out);
const char* ringKeyTypeName(RingKeyType type);

/// Every tunable of the core. Members carry the documented defaults; call validate() before use.
struct Config {
  // ---- descriptor -------------------------------------------------------------------------
  /// Radial bins of the polar grid (the paper's 20).
  int num_rings = 20;
  /// Azimuthal bins of the polar grid (the paper's 60, i.e. 6 degrees each).
  int num_sectors = 60;
  /// Points farther than this horizontal range [m] are ignored (the paper's 80 m).
  double max_radius = 80.0;
  /// Points closer than this horizontal range [m] are ignored (the ego vehicle's own returns).
  double min_range = 0.0;
  /// Added to every z before taking the bin maximum [m]. 2.0 as in the published code for clouds in
  /// the sensor frame of a car-mounted LiDAR; 0 for gravity-aligned clouds already in a base frame.
  /// Bins that hold points are tracked separately, so negative heights never read as empty.
  double lidar_height = 2.0;
  /// Ring key content, see RingKeyType.
  RingKeyType ring_key = RingKeyType::kOccupancy;

  // ---- search -----------------------------------------------------------------------------
  /// Nearest ring keys fetched from the kd-tree and scored with the full descriptor distance.
  int num_candidates = 10;
  /// Width of the local column search around the sector-key shift, as a fraction of num_sectors:
  /// +-(search_ratio / 2 * num_sectors) columns. 1.0 searches every shift exhaustively.
  double search_ratio = 0.1;
  /// A match is reported when the best candidate's distance is below this threshold. 0.2 is the
  /// F1-maximising value measured on simulated HDL-64E streets (README, "Choosing the threshold"); the
  /// published code's 0.13 misses real reverse revisits such as KITTI 08 720/1500 (about 0.2).
  double distance_threshold = 0.2;

  // ---- exclusion of recent keyframes (each rule: 0 disables it) ---------------------------
  /// The most recent keyframes that are never candidates (the paper's 50).
  int exclude_recent_frames = 50;
  /// Keyframes less than this many seconds older than the query are never candidates.
  double exclude_recent_seconds = 0.0;
  /// Keyframes less than this odometry path length [m] behind the query are never candidates
  /// (needs poses; keyframes added without a pose do not advance the path length).
  double exclude_recent_distance = 0.0;

  /// Human-readable problems, empty when the configuration is usable.
  std::vector<std::string> validate() const;

  /// Number of columns searched on each side of the coarse shift.
  int searchHalfWidth() const;
};

/// The configuration keys: exactly the Config member names, as used in config/*.yaml.
const std::vector<std::string>& configKeys();

/// Sets one member from its text form ("20", "0.25", "occupancy"). Returns false, leaving the config
/// unchanged, for an unknown key or a value that does not parse as the member's type.
bool setConfigValue(Config* config, const std::string& key, const std::string& value, std::string* error);

}  // namespace scan_context_loop
