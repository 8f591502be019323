// Configuration of the ROS-free Scan Context core.
#pragma once

#include <string>
#include <vector>

namespace scan_context_loop {

/// What the rotation-invariant ring key holds for each ring.
enum class RingKeyType {
  /// Mean of the ring's max heights, empty sectors counting as 0 (the published Scan Context key; the
  /// default, doc/defaults.md says why).
  kMeanHeight,
  /// Fraction of the ring's sectors that hold points; does not depend on lidar_height.
  kOccupancy,
};

/// Parses "occupancy" / "mean_height"; returns false for anything else.
bool parseRingKeyType(const std::string& text, RingKeyType* out);
const char* ringKeyTypeName(RingKeyType type);

/// The fine registration geometric verification runs: the built-in voxel GICP over the prepared keyframe
/// data (the default), or PCL's GICP, ICP or NDT over the voxel means.
enum class RegistrationMethod { kVgicp, kGicp, kIcp, kNdt };

/// Parses "vgicp" / "gicp" / "icp" / "ndt"; returns false for anything else.
bool parseRegistrationMethod(const std::string& text, RegistrationMethod* out);
const char* registrationMethodName(RegistrationMethod method);

/// Where the gravity alignment of each keyframe comes from (gravity_alignment.h).
enum class GravityAlignmentMode {
  /// The pose's roll and pitch when the keyframe has a pose whose tilt is within trusted_pose_max_tilt_deg
  /// (a larger one means a world frame that is not z-up), else a ground-plane fit, else none.
  kAuto,
  kPose,    ///< the pose's roll and pitch only (keyframes without a pose are not gravity-aligned)
  kGround,  ///< a ground-plane fit only
  kOff,
};

/// Parses "auto" / "pose" / "ground" / "off"; returns false for anything else.
bool parseGravityAlignmentMode(const std::string& text, GravityAlignmentMode* out);
const char* gravityAlignmentModeName(GravityAlignmentMode mode);

/// Geometric verification: the verify_* keys (member `x` is key `verify_x`; `enabled` is `verify`)
/// and the registration's fixed internals. How the defaults were chosen: doc/defaults.md.
struct VerificationConfig {
  /// Verify candidates by registration; a loop is then reported only when one is accepted.
  bool enabled = true;
  /// Candidates whose descriptor distance is below this looser threshold are verified.
  double threshold = 0.5;
  /// At most this many candidates are verified per keyframe (best distance first): the cost bound.
  int max_candidates = 2;
  /// Memory budget for the registration data kept for verification [bytes] (see CloudStore).
  double max_bytes = 1024.0 * 1024.0 * 1024.0;
  /// Voxel edge of the registration data [m].
  double voxel_leaf = 1.0;
  /// Points beyond this horizontal range are not used [m].
  double max_range = 40.0;
  /// Accept only when the symmetric structure overlap (the smaller of the two directions' fractions
  /// of vertical-structure voxels, within the region both sensors cover, that agree) is at least this.
  double min_inlier_ratio = 0.55;
  /// A registration that passes every other test with an overlap in [supported_inlier_ratio,
  /// min_inlier_ratio) needs support: it is reported only once a confirmed loop that passed in full
  /// agrees with it strictly through the odometry (ConsistencyFilter): sparse sensors see less of the
  /// same structure from a few metres aside. Equal to min_inlier_ratio: off. Without the consistency check such loops
  /// are not reported.
  double supported_inlier_ratio = 0.4;
  /// The same two floors for the column overlap (VerificationResult::column_overlap), which asks of each
  /// structure voxel only whether the other keyframe saw its surface anywhere in a column around it: a
  /// sparse sensor (16 rings 2 degrees apart) samples a facade at other heights from another viewpoint,
  /// so its voxels rarely meet although the walls do. A registration passes the overlap test in full
  /// when either overlap reaches its floor, and with support likewise. 1: the column overlap is not used.
  double min_column_overlap = 0.8;
  double supported_column_overlap = 0.7;
  /// Accept only when the agreeing voxels' mean squared point-to-plane distance is below this [m^2]
  /// (a sanity bound).
  double max_fitness = 0.015;
  /// Largest share of either keyframe's structure that may stand where the other saw through (within
  /// 25 m; free_space.h): a secondary test.
  double max_violation = 0.4;
  /// A registration over max_violation but at most this, passing every other test, needs support,
  /// like one under min_inlier_ratio. Equal to max_violation: off.
  double supported_max_violation = 0.55;
  /// Both keyframes are gravity-aligned before they are registered, so the registered rotation between
  /// them should be a yaw. When it tilts by more than this [deg], the registration's roll and pitch are
  /// not trusted (a sparse scan's few rings leave them loose): yaw and translation are registered again
  /// with roll and pitch held at the gravity alignment's, and the loop's roll and pitch variance is
  /// then this angle squared. 0: always so; 90: never. (Key verify_max_tilt.)
  double registration_max_tilt_deg = 1.0;
  /// The fine registration: the built-in voxel GICP (vgicp), or PCL's GICP, ICP or NDT over the voxel
  /// means (slower; kept for comparison).
  RegistrationMethod method = RegistrationMethod::kVgicp;
  /// A registered loop whose rotation disagrees with the odometry's relative rotation between the two
  /// keyframes by more than odometry_rotation + odometry_rotation_drift * (odometry path between them)
  /// [deg, deg/m] is rejected (needs poses; 0 disables): mirror-image streets register well the wrong
  /// way round.
  double odometry_rotation = 10.0;
  double odometry_rotation_drift = 0.02;
  /// Register against the candidate and this many keyframes on each side of it, moved into the
  /// candidate's frame through the odometry (0: the candidate alone).
  int submap = 0;
  /// Accept loops whose position along one horizontal direction the scene does not fix (a corridor,
  /// an open road); their covariance then says so. Off: such loops are rejected.
  bool allow_degenerate = false;

  // ---- fixed internals (no configuration key) ----
  /// Either keyframe with fewer vertical-structure voxels (facades, poles, trunks) is unverifiable.
  int min_structure = 150;
  /// Half-width of the coarse translation search around each hypothesis [m]: the descriptor prior has
  /// no translation beyond its viewpoint, and true revisits lie up to a few metres to the side.
  double search_radius = 6.0;
  /// Cell of the bird's-eye coarse search [m].
  double search_cell = 1.0;
  /// Hypotheses whose coarse score is at least this fraction of the best one's are registered too,
  /// best first, until one is accepted (at most max_hypotheses). One: over ten HDL-64E and VLP-16
  /// sequences (3,500 verified loops) a second registration was accepted once, and the loop was found
  /// again; it cost every wrong candidate twice its time, which made most of the verification p99.
  double hypothesis_ratio = 0.85;
  int max_hypotheses = 1;
  /// Correspondence distance of the coarse and the fine GICP stage [m].
  double coarse_correspondence = 2.0;
  double fine_correspondence = 0.8;
  int max_iterations = 15;
  /// Source voxels GICP uses per iteration (the cost bound; vertical structure first).
  int max_source_voxels = 1200;
  /// A moved structure voxel agrees with the other keyframe when a voxel of it lies within
  /// `inlier_distance` [m] and the point-to-plane distance is below `inlier_plane_distance` [m].
  double inlier_distance = 1.0;
  double inlier_plane_distance = 0.25;
  /// Reject when the registration cannot fix the position in some horizontal direction: the smallest
  /// eigenvalue of the point-to-plane information over the translation is below this fraction of the
  /// largest (a straight corridor or an open road seen along its axis), unless allow_degenerate.
  double min_constraint_ratio = 0.02;
  /// Floors on the reported variances of x, y, z [m^2] and of roll, pitch, yaw [rad^2].
  double min_translation_variance = 0.01;
  double min_rotation_variance = 7.6e-5;  // (0.5 deg)^2
  /// NDT voxel resolution [m] (method ndt only).
  double ndt_resolution = 2.0;

  /// Problems of the fixed internals, and of the keyed settings too (as Config::validate checks them).
  std::vector<std::string> validate() const;
};

/// Every tunable of the core. Members carry the documented defaults; call validate() before use.
struct Config {
  // ---- keyframe input (keyframes.h: the node and the evaluator alike) ----------------------
  /// Clouds arrive registered in the pose's frame (A-LOAM, LIO-SAM, FAST-LIO): each is moved back into
  /// the sensor frame with the keyframe's pose before it is described.
  bool cloud_in_world_frame = false;
  /// Keyframe selection: a cloud becomes a keyframe when the sensor moved at least this far [m] or
  /// turned at least this much in yaw [deg] since the last keyframe (both 0: every cloud).
  double keyframe_min_distance = 0.0;
  double keyframe_min_angle = 0.0;
  /// Scan accumulation for sensors whose single scan sees too little (Livox Avia, Mid-360: a narrow or
  /// patchy, non-repetitive field of view): a keyframe is made of every scan of the last
  /// accumulate_seconds [s] and, when set, of the last accumulate_distance [m] of odometry path, each
  /// moved into the keyframe's sensor frame through the odometry (needs poses; both 0: off). Every
  /// scan counts, whether keyframe selection picks it or not.
  double accumulate_seconds = 0.0;
  double accumulate_distance = 0.0;
  /// Time going backwards: keyframes stamped at least this long [s] before the previous keyframe (a bag
  /// played again, a restarted odometry) start a new session (Database::startSession) on evidence only:
  /// three such keyframes in a row, in order among themselves, or one whose odometry pose lies 10 m or
  /// more from the last cloud's; the ones before are refused as out of order, so one bad stamp never
  /// splits a session. A smaller step back is refused as out of order. 0: every step back is refused.
  double new_session_jump = 1.0;
  /// Time jumping ahead: a keyframe stamped more than this long [s] after the last cloud is refused
  /// unless three keyframes in a row, in order, show the same jump (clouds back after an outage), so a
  /// single far-future stamp is not taken and the next ones do not fall behind it. 0: no bound. The
  /// default, about 116 days, lets a robot resume after a night or a week in the same session.
  double max_stamp_step = 1e7;
  /// Only keyframes of the earlier sessions are candidates, never the current session's own: relocalization
  /// in a prior map (the node's mode: relocalize sets it).
  bool prior_sessions_only = false;
  /// Voxel filter before describing [m] (0: off), after the accumulation.
  double voxel_leaf = 0.0;
  /// Covariance of a loop with only the descriptor's yaw prior: variance of x, y, z [m^2] and of roll
  /// and pitch [rad^2]; yaw's is (half a sector)^2 (loopCovariance, keyframes.h).
  double covariance_translation = 100.0;
  double covariance_rotation = 0.01;

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
  RingKeyType ring_key = RingKeyType::kMeanHeight;

  /// Gravity alignment: each keyframe is rotated into a gravity-aligned frame (same heading) before it is
  /// described and registered, so a sensor tilted 10-20 degrees (hand-held, backpack, legged) still
  /// matches a level pass. Tilts below 0.5 degrees are left alone. Loop poses are reported in the
  /// sensor frames all the same; the yaw prior is that of the gravity-aligned frames.
  GravityAlignmentMode gravity_alignment = GravityAlignmentMode::kAuto;
  /// kAuto: a pose tilted more than this [deg] is not trusted for gravity alignment (ground fit instead).
  /// (Key gravity_alignment_max_tilt.)
  double trusted_pose_max_tilt_deg = 30.0;

  // ---- search -----------------------------------------------------------------------------
  /// Nearest ring keys fetched from the kd-tree and scored with the full descriptor distance.
  int num_candidates = 10;
  /// Databases of up to this many searchable keyframes find the nearest ring keys exactly (one kd-tree,
  /// every branch that could hold a nearer key visited); above it, approximately (two randomized
  /// kd-trees, 128 keys compared). An exact search costs about in proportion to the database, the
  /// approximate one about the same at any size. 0: always approximate.
  int exact_search_limit = 20000;
  /// Width of the local column search around the sector-key shift, as a fraction of num_sectors:
  /// +-(search_ratio / 2 * num_sectors) columns. 1.0 searches every shift exhaustively.
  double search_ratio = 0.1;
  /// A match is reported when the best candidate's distance is below this threshold (without
  /// verification; with it, verify_threshold decides which candidates are registered).
  double distance_threshold = 0.21;
  /// Virtual viewpoints for revisits a lane or more to the side [m] (0 disables): besides the real one,
  /// the query is described from lateral_offset_count points on each side along the sensor's y axis,
  /// lateral_offset_step apart, and each of those descriptors searches the database too; a candidate
  /// keeps the viewpoint it scored best from, which also seeds verification with that translation.
  double lateral_offset_step = 2.5;
  /// Virtual viewpoints on each side when lateral_offset_step > 0.
  int lateral_offset_count = 1;

  // ---- exclusion of recent keyframes (each rule: 0 disables it) ---------------------------
  /// The most recent keyframes that are never candidates (the paper's 50).
  int exclude_recent_frames = 50;
  /// Keyframes less than this many seconds older than the query are never candidates.
  double exclude_recent_seconds = 0.0;
  /// Keyframes less than this odometry path length [m] behind the query are never candidates
  /// (needs poses; keyframes added without a pose do not advance the path length).
  double exclude_recent_distance = 0.0;

  /// Odometry gate: a candidate is dropped when its odometry position is farther from the query's than
  /// gate_odometry_distance [m] + gate_odometry_drift [m per m] * (odometry path length between them)
  /// (needs poses; both 0 disables it). It removes look-alike streets a few hundred metres away; an
  /// odometry that drifts more needs a larger allowance, and long loops get it by construction.
  double gate_odometry_distance = 20.0;
  double gate_odometry_drift = 0.1;

  // ---- geometric verification (verification.h): the verify_* keys --------------------------
  VerificationConfig verification;

  // ---- pairwise consistency of verified loops (consistency.h) ---------------------------------
  /// With verify: a verified loop is published only once at least this many other verified loops agree
  /// with it (0 disables the check); loops wait for that support for consistency_window keyframes.
  /// Without verify it has no effect.
  int consistency_min_support = 1;
  /// Keyframes a verified loop waits for support before it is dropped; loops whose queries are further
  /// apart than this are not compared.
  int consistency_window = 10;
  /// Two loops agree when the cycle odometry - loop - odometry - loop closes within this translation
  /// [m] and yaw [deg], plus consistency_drift times the odometry path length the cycle runs along.
  double consistency_translation = 1.0;
  double consistency_rotation = 2.0;
  double consistency_drift = 0.05;

  // ---- loop tracking (loop_tracking.h) ----------------------------------------------------------
  /// With verify: after a confirmed loop, each following keyframe within this much odometry path [m]
  /// of that loop's query also tries the keyframe (of the loop's match session) nearest to where the
  /// loop and the odometry put it, registered from that pose guess, before the descriptor's candidates.
  /// Such a loop is reported when it agrees with the confirmed one (loopsAgree) and then carries the
  /// track on; 0 disables tracking.
  double track_distance = 100.0;

  /// Human-readable problems, empty when the configuration is usable.
  std::vector<std::string> validate() const;

  /// Number of columns searched on each side of the coarse shift.
  int searchHalfWidth() const;
};

/// The configuration keys: exactly the Config member names, as used in config/*.yaml.
const std::vector<std::string>& configKeys();

/// Sets one member from its text form ("20", "0.25", "occupancy"). Returns false, leaving the config
/// unchanged, for an unknown key or a value that does not parse as the member's type. A deprecated name
/// of a key (Setting::deprecated_keys) sets the key; `warning` (when given) then says so, else is cleared.
bool setConfigValue(Config* config, const std::string& key, const std::string& value, std::string* error,
                    std::string* warning = nullptr);

}  // namespace scan_context_loop
