#include "scan_context_loop/core/settings.h"

#include <cmath>

#include "setting_rows.h"

namespace scan_context_loop {

namespace {

using namespace rows;

#define C(expr) SCL_MEMBER(Config, expr)
#define N(expr) SCL_MEMBER(NodeOptions, expr)

// The groups: sections of config/default.yaml in this order, and the dynamic_reconfigure groups of the
// live rows (cfg/LoopClosure.cfg). The node's table shares "output" with the core's.
const SettingGroup kKeyframes{"keyframes", "keyframe input (the node and scripts/evaluate alike: keyframes.h)"};
const SettingGroup kDescriptor{"descriptor", "Scan Context descriptor"};
const SettingGroup kSearch{"search", "search, exclusion of recent keyframes (0 disables a rule), odometry gate"};
const SettingGroup kVerification{"verification", "geometric verification"};
const SettingGroup kConsistency{"consistency",
                                "pairwise consistency of verified loops, loop tracking (both need verify)"};
const SettingGroup kOutput{"output", "loops out, and the node's processing (queue_size and below: the node only)"};
const SettingGroup kInputs{"inputs", "inputs (the node only)"};
const SettingGroup kSessions{"sessions", "sessions and relocalization (the node only)"};
const SettingGroup kTeam{"team", "several robots (the node only; doc/multi_robot.md)"};

std::vector<Setting<Config>> makeConfigSettings() {
  using Cfg = Config;
  return joined<Cfg>({
      group<Cfg>(
          kKeyframes,
          {
              boolSetting<Cfg>("cloud_in_world_frame", C(cloud_in_world_frame),
                               "clouds arrive registered in the pose frame",
                               "As A-LOAM and LeGO-LOAM publish them: each is transformed back to the sensor."),
              live(doubleSetting<Cfg>(
                  "keyframe_min_distance", C(keyframe_min_distance), atLeast(0, " (0 disables)"),
                  "keyframe selection: metres since the last keyframe",
                  "For stacks that publish every scan; with keyframe_min_angle 0 too, every cloud is "
                  "a keyframe.")),
              live(doubleSetting<Cfg>("keyframe_min_angle", C(keyframe_min_angle), atLeast(0, " (0 disables)"),
                                      "keyframe selection: degrees of yaw since the last keyframe")),
              doubleSetting<Cfg>("accumulate_seconds", C(accumulate_seconds), atLeast(0, " (0 disables)"),
                                 "a keyframe merges the scans of this many seconds",
                                 "Scan accumulation for Livox-like sensors (a narrow or patchy field of view): the "
                                 "scans are merged through the odometry, so it needs poses."),
              doubleSetting<Cfg>("accumulate_distance", C(accumulate_distance), atLeast(0, " (0 disables)"),
                                 "a keyframe also merges the scans of this many metres of odometry path"),
              doubleSetting<Cfg>(
                  "new_session_jump", C(new_session_jump), atLeast(0, " (0: never)"),
                  "a stamp this far back [s] starts a new session (3 in a row, or with an odometry jump)",
                  "Time going backwards (a bag played again, a restarted odometry): keyframes stamped at "
                  "least this many seconds before the previous one start a new session -- earlier "
                  "sessions stay, all of them candidates -- once 3 in a row show it, or at once when the "
                  "odometry pose jumps 10 m too; until then, and for a smaller step back, they are "
                  "refused as out of order (0: every step back is refused)."),
              doubleSetting<Cfg>("max_stamp_step", C(max_stamp_step), atLeast(0, " (0: no bound)"),
                                 "a stamp this far ahead [s] is refused unless 3 in a row agree",
                                 "Time jumping ahead: a keyframe stamped more than this many seconds after the last "
                                 "cloud is refused unless 3 in a row show the same jump (clouds back after an outage); "
                                 "one far-future stamp neither enters nor splits the session."),
              boolSetting<Cfg>("prior_sessions_only", C(prior_sessions_only),
                               "only earlier sessions' keyframes are candidates (relocalization)",
                               "Never the current session's own: relocalization in a prior map (a loaded database; "
                               "mode relocalize sets it)."),
              doubleSetting<Cfg>("voxel_leaf", C(voxel_leaf), atLeast(0, " (0 disables)"),
                                 "voxel filter before describing [m]", "The descriptor keeps bin maxima either way."),
          }),
      group<Cfg>(
          kDescriptor,
          {
              intSetting<Cfg>("num_rings", C(num_rings), closed(1, 1000), "radial bins of the polar grid",
                              "The paper's 20. Changing it invalidates a database."),
              intSetting<Cfg>("num_sectors", C(num_sectors), closed(3, 3600), "azimuthal bins of the polar grid",
                              "60 are 6 degrees each. Changing it invalidates a database."),
              doubleSetting<Cfg>("max_radius", C(max_radius), positive(),
                                 "points beyond this horizontal range are ignored [m]"),
              doubleSetting<Cfg>("min_range", C(min_range), atLeast(0),
                                 "points closer than this horizontal range are ignored [m]",
                                 "E.g. the vehicle's own returns."),
              doubleSetting<Cfg>(
                  "lidar_height", C(lidar_height), {}, "added to every z before taking the bin maximum [m]",
                  "2.0 for clouds in a car-mounted sensor frame, 0 for gravity-aligned clouds already in "
                  "a base frame. Bins with points never read as empty, whatever the sign."),
              enumSetting<Cfg, RingKeyType>("ring_key", C(ring_key), parseRingKeyType, ringKeyTypeName,
                                            {RingKeyType::kMeanHeight, RingKeyType::kOccupancy},
                                            "what the ring key holds",
                                            "The key searched in the kd-tree: mean_height (the published key, measured "
                                            "better) or occupancy."),
              formerly(
                  {"levelling"},
                  enumSetting<Cfg, GravityAlignmentMode>(
                      "gravity_alignment", C(gravity_alignment), parseGravityAlignmentMode, gravityAlignmentModeName,
                      {GravityAlignmentMode::kAuto, GravityAlignmentMode::kPose, GravityAlignmentMode::kGround,
                       GravityAlignmentMode::kOff},
                      "where each keyframe's gravity alignment comes from",
                      "Before describing and registering. auto: the pose's roll and pitch when the keyframe has a "
                      "pose tilted at most gravity_alignment_max_tilt, else a ground-plane fit. For hand-held, "
                      "backpack and legged sensors that tilt 10-20 degrees. Loop poses stay in the sensor frames.")),
              formerly({"levelling_max_tilt"},
                       doubleSetting<Cfg>("gravity_alignment_max_tilt", C(trusted_pose_max_tilt_deg), closed(0, 90),
                                          "auto gravity alignment: a pose tilted more than this is not trusted [deg]",
                                          "A world frame that is not z-up.")),
          }),
      group<Cfg>(
          kSearch,
          {
              live(doubleSetting<Cfg>("distance_threshold", C(distance_threshold), openLow(0, 2),
                                      "a descriptor match is below this distance",
                                      "A loop is published when the best distance is below this (0: identical, 1: "
                                      "nothing in common). 0.21 keeps 100% precision on the simulated KITTI-trajectory "
                                      "sequences (doc/verification.md, \"Choosing the threshold\").")),
              live(intSetting<Cfg>("num_candidates", C(num_candidates), closed(1, 10000),
                                   "ring-key neighbours scored in full", "Scored with the full descriptor distance.")),
              intSetting<Cfg>(
                  "exact_search_limit", C(exact_search_limit), atLeast(0, " (0: always approximate)"),
                  "databases up to this many keyframes are searched exactly, larger ones approximately",
                  "Approximately: randomized kd-trees at a bounded cost, so a database of 100,000 keyframes "
                  "is searched about as fast as one of 20,000."),
              live(doubleSetting<Cfg>("search_ratio", C(search_ratio), closed(0, 1),
                                      "column search width around the coarse shift",
                                      "Around the sector-key shift, as a fraction of num_sectors (1: every shift).")),
              doubleSetting<Cfg>("lateral_offset_step", C(lateral_offset_step), atLeast(0, " (0 disables)"),
                                 "spacing of the virtual lateral viewpoints [m]",
                                 "For revisits a lane or more to the side: the keyframe is also described as seen from "
                                 "lateral_offset_count points on each side, this far apart along the sensor's y axis, "
                                 "and each description searches the database; the viewpoint also seeds verification "
                                 "with that translation. 2.5 m by measurement (doc/verification.md, \"Lateral "
                                 "viewpoints\"); 0 gives the plain Scan Context search."),
              intSetting<Cfg>("lateral_offset_count", C(lateral_offset_count), closed(1, 10),
                              "virtual viewpoints per side"),
              intSetting<Cfg>("exclude_recent_frames", C(exclude_recent_frames), atLeast(0, " (0 disables)"),
                              "the most recent keyframes are never candidates"),
              doubleSetting<Cfg>("exclude_recent_seconds", C(exclude_recent_seconds), atLeast(0, " (0 disables)"),
                                 "keyframes younger than this are never candidates [s]",
                                 "Younger than the query by this many seconds."),
              doubleSetting<Cfg>("exclude_recent_distance", C(exclude_recent_distance), atLeast(0, " (0 disables)"),
                                 "keyframes less than this path behind are never candidates [m]",
                                 "Odometry path length behind the query."),
              live(doubleSetting<Cfg>(
                  "gate_odometry_distance", C(gate_odometry_distance), atLeast(0, " (off when both are 0)"),
                  "odometry gate: fixed allowance [m]",
                  "Candidates farther from the query by odometry than gate_odometry_distance plus "
                  "gate_odometry_drift per metre of odometry path between the two keyframes are "
                  "dropped (both 0: off). 20 m + 10 % is twice the simulated odometry's drift after 2 "
                  "km. The odometry is also relied on from the nearest confirmed loop, over the "
                  "shorter path that leaves, and the rate grows to 1.5x the worst drift confirmed "
                  "loops measured, so an odometry that breaks down still gets its loops "
                  "(doc/odometry_checks.md).")),
              live(doubleSetting<Cfg>("gate_odometry_drift", C(gate_odometry_drift), atLeast(0, " (off when both are 0)"),
                                      "odometry gate: allowance per metre of path",
                                      "See gate_odometry_distance [m per m of odometry path].")),
          }),
      group<Cfg>(
          kVerification,
          {
              boolSetting<Cfg>("verify", C(verification.enabled), "verify candidates by registration",
                               "Voxel GICP from the descriptor's yaw hypotheses; loops are then published only when "
                               "verified, with the registered relative pose, its covariance and the fitness. false "
                               "publishes the descriptor matches with a yaw-only prior."),
              live(
                  doubleSetting<Cfg>("verify_threshold", C(verification.threshold), openLow(0, 2),
                                     "candidates below this distance are verified",
                                     "A looser descriptor threshold (precision held at 1.000 up to 0.6 on the baseline "
                                     "sequences; a higher value costs registrations, not precision).")),
              live(intSetting<Cfg>("verify_max_candidates", C(verification.max_candidates), closed(1, 100),
                                   "candidates verified per keyframe at most", "The cost bound; a few ms each.")),
              doubleSetting<Cfg>("verify_max_bytes", C(verification.max_bytes), atLeast(1e6),
                                 "memory for the registration data [bytes]",
                                 "The keyframes' registration data: 1 m voxels, 16 bytes each, ~130 KB an HDL-64E "
                                 "keyframe. Past it, only every second (fourth, ...) keyframe keeps its data."),
              doubleSetting<Cfg>("verify_voxel_leaf", C(verification.voxel_leaf), positive(),
                                 "registration voxel edge [m]"),
              doubleSetting<Cfg>("verify_max_range", C(verification.max_range), positive(),
                                 "registration crop range [m]", "Horizontal."),
              live(doubleSetting<Cfg>("verify_min_inlier_ratio", C(verification.min_inlier_ratio), closed(0, 1),
                                      "symmetric structure overlap a loop needs on its own",
                                      "Acceptance, chosen on the eleven baseline sequences (doc/verification.md): the "
                                      "symmetric overlap of vertical structure (facades, poles, trunks) in the region "
                                      "both keyframes cover, at least this (wrong places: at most 0.41 on ten "
                                      "sequences, 0.546 among repeated buildings; true: 0.55-0.83 at the 5th "
                                      "percentile).")),
              live(doubleSetting<Cfg>(
                  "verify_supported_inlier_ratio", C(verification.supported_inlier_ratio), closed(0, 1),
                  "overlap a loop that needs support must reach",
                  "A registration passing every other test with an overlap between this and "
                  "verify_min_inlier_ratio is reported only when a loop that passed in full agrees "
                  "with it through the odometry (the consistency check, consistency_min_support > 0); "
                  "sparse sensors (VLP-16) see less of the same structure.")),
              live(
                  doubleSetting<Cfg>("verify_min_column_overlap", C(verification.min_column_overlap), closed(0, 1),
                                     "column overlap a loop needs on its own (1: not used)",
                                     "The same floor for the column overlap: a structure voxel agrees when the other "
                                     "keyframe saw its surface anywhere in a column around it, whatever the height. "
                                     "Sparse sensors (VLP-16) sample a facade at other heights from another viewpoint, "
                                     "so their voxels rarely meet although the walls do. Either overlap reaching its "
                                     "floor passes the test (doc/verification.md, \"Sparse sensors\").")),
              live(doubleSetting<Cfg>("verify_supported_column_overlap", C(verification.supported_column_overlap),
                                      closed(0, 1),
                                      "column overlap a loop that needs support must reach (1: not used)")),
              live(doubleSetting<Cfg>("verify_max_fitness", C(verification.max_fitness), positive(),
                                      "largest mean squared point-to-plane distance [m^2]", "Of the agreeing voxels.")),
              live(doubleSetting<Cfg>("verify_max_violation", C(verification.max_violation), closed(0, 1),
                                      "largest free-space violation of a loop on its own",
                                      "The share of either side's structure standing where the other saw through.")),
              live(doubleSetting<Cfg>("verify_supported_max_violation", C(verification.supported_max_violation),
                                      closed(0, 1), "largest free-space violation of a loop that needs support",
                                      "A registration whose violation lies between verify_max_violation and this needs "
                                      "support, as for verify_supported_inlier_ratio.")),
              live(doubleSetting<Cfg>(
                  "verify_max_tilt", C(verification.registration_max_tilt_deg), closed(0, 90),
                  "registered tilt above which roll and pitch come from the gravity alignment [deg]",
                  "Both keyframes are gravity-aligned, so the registered rotation between them should "
                  "be a yaw. When it tilts by more than this, yaw and translation are registered "
                  "again and the variance of roll and pitch in the loop's covariance is this angle "
                  "squared.")),
              enumSetting<Cfg, RegistrationMethod>("verify_method", C(verification.method), parseRegistrationMethod,
                                                   registrationMethodName,
                                                   {RegistrationMethod::kVgicp, RegistrationMethod::kGicp,
                                                    RegistrationMethod::kIcp, RegistrationMethod::kNdt},
                                                   "the fine registration",
                                                   "vgicp: the built-in voxel GICP over the prepared keyframe data; "
                                                   "gicp, icp, ndt: PCL's over the voxel "
                                                   "means (slower; doc/verification.md, \"Registration method\")."),
              live(doubleSetting<Cfg>(
                  "verify_odometry_rotation", C(verification.odometry_rotation), atLeast(0, " (0 disables)"),
                  "largest disagreement with the odometry's rotation [deg]",
                  "Plus verify_odometry_rotation_drift per metre of odometry path between the two "
                  "keyframes (mirror-image streets register well the wrong way round). A registered "
                  "loop beyond it, or, relied on from a confirmed loop, whose position is off by more "
                  "than consistency_translation plus the gate's rate per metre, is not accepted "
                  "alone: it waits for one support more than consistency_min_support from other such "
                  "loops (odometry that broke down: doc/odometry_checks.md).")),
              live(doubleSetting<Cfg>("verify_odometry_rotation_drift", C(verification.odometry_rotation_drift),
                                      atLeast(0),
                                      "the odometry rotation check's growth per metre of odometry path [deg/m]")),
              intSetting<Cfg>("verify_submap", C(verification.submap), closed(0, 20),
                              "candidate neighbours registered too",
                              "Register against the candidate and this many keyframes each side of it, joined through "
                              "the odometry (0: the candidate alone). Helps sparse sensors (VLP-16); costs memory "
                              "reads, not registrations."),
              boolSetting<Cfg>("verify_allow_degenerate", C(verification.allow_degenerate),
                               "accept loops the scene does not fix along one direction",
                               "A corridor, an open road: the loop comes with the large covariance that says so; false "
                               "rejects them."),
          }),
      group<Cfg>(
          kConsistency,
          {
              intSetting<Cfg>("consistency_min_support", C(consistency_min_support), closed(0, 100, " (0 disables)"),
                              "agreeing loops a verified loop needs",
                              "A verified loop is published once this many other verified loops agree with it through "
                              "the odometry (measured in doc/verification.md, \"Consistency of loops\"; no effect "
                              "without verify). It may then come a few keyframes after its query keyframe; a loop "
                              "nothing agrees with within consistency_window keyframes is dropped (and published on "
                              "loop_candidates_rejected)."),
              intSetting<Cfg>("consistency_window", C(consistency_window), closed(1, 100000),
                              "keyframes a loop waits for support"),
              live(doubleSetting<Cfg>("consistency_translation", C(consistency_translation), positive(),
                                      "cycle translation tolerance [m]",
                                      "Agreement: the cycle odometry-loop-odometry-loop closes within this translation "
                                      "and consistency_rotation, plus consistency_drift times the odometry path length "
                                      "the cycle runs along.")),
              live(doubleSetting<Cfg>("consistency_rotation", C(consistency_rotation), positive(),
                                      "cycle rotation tolerance [deg]")),
              live(doubleSetting<Cfg>("consistency_drift", C(consistency_drift), atLeast(0),
                                      "tolerance per metre of path")),
              live(
                  doubleSetting<Cfg>("track_distance", C(track_distance), atLeast(0),
                                     "odometry path a confirmed loop predicts the next keyframes' matches over [m] "
                                     "(0: off)",
                                     "Each following keyframe within this path also tries the keyframe where that loop "
                                     "and the odometry put it, registered from that guess (doc/verification.md, \"Loop "
                                     "tracking\"). Its loop is published when it agrees with the confirmed one.")),
          }),
      group<Cfg>(kOutput,
                 {
                     live(doubleSetting<Cfg>("covariance_translation", C(covariance_translation), positive(),
                                             "x, y, z variance of a yaw-prior-only loop [m^2]",
                                             "A loop published without verification (the yaw variance is half a sector "
                                             "squared).")),
                     live(doubleSetting<Cfg>("covariance_rotation", C(covariance_rotation), positive(),
                                             "roll, pitch variance of a yaw-prior-only loop [rad^2]")),
                 }),
  });
}

std::vector<Setting<NodeOptions>> makeNodeSettings() {
  using O = NodeOptions;
  return joined<O>({
      group<O>(
          kInputs,
          {
              enumSetting<O, PoseSource>("pose_source", N(pose_source), parsePoseSource, poseSourceName,
                                         {PoseSource::kOdom, PoseSource::kTf},
                                         "odom: keyframe_odom messages; tf: tf lookups",
                                         "Where keyframe poses come from; tf looks them up at the cloud stamp."),
              stringSetting<O>("fixed_frame", N(fixed_frame), {}, "tf mode: the frame poses are looked up in",
                               "Also the frame of the markers."),
              doubleSetting<O>("tf_timeout", N(tf_timeout), atLeast(0),
                               "tf mode: how long to wait for a transform [s]"),
              stringSetting<O>("sensor_frame", N(sensor_frame), {}, "the sensor's frame (empty: the cloud's)",
                               "Set it for registered clouds in tf mode, and for sensor-frame points labelled "
                               "with another frame (SC-A-LOAM's local clouds: the odometry's child frame)."),
              boolSetting<O>(
                  "sensor_extrinsic_from_tf", N(sensor_extrinsic_from_tf),
                  "odometry of another frame: extrinsic child <- sensor from tf",
                  "Odometry whose child_frame_id is not the clouds' frame (LeGO-LOAM's camera axes, an IMU body "
                  "frame): each pose moves to the sensor with that extrinsic (set sensor_frame for registered "
                  "clouds), looked up without waiting; keyframes wait for it up to 5 s, then a warning names "
                  "both frames and the poses are used as they are. Frame ids are read without tf1's leading "
                  "'/'."),
              boolSetting<O>("approximate_sync", N(approximate_sync),
                             "approximate (true) or exact time synchronisation", "Of the clouds and the odometry."),
              intSetting<O>("sync_queue_size", N(sync_queue_size), closed(1, 10000), "message_filters queue per input"),
          }),
      group<O>(
          kOutput,
          {
              intSetting<O>("queue_size", N(queue_size), closed(1, 100000), "keyframes waiting for the worker",
                            "More are dropped, counted and reported."),
              intSetting<O>("heap_statistics_interval", N(heap_statistics_interval), closed(0, 100000000),
                            "keyframes between reads of malloc's statistics (0: never)",
                            "Read once the queue is empty: heap allocated and free, in the diagnostics (glibc's "
                            "mallinfo2 walks the whole heap, tens of ms on a large fragmented one); with 0 the "
                            "diagnostics leave them out."),
              boolSetting<O>("lio_sam_output", N(lio_sam_output), "also publish LIO-SAM's loop message",
                             "[query stamp, match stamp] (std_msgs/Float64MultiArray) on lio_loop, for LIO-SAM's "
                             "loop-closure hook (remap lio_loop to lio_loop/loop_closure_detection)."),
              live(doubleSetting<O>("lio_sam_min_interval", N(lio_sam_min_interval), atLeast(0),
                                    "lio_loop: at most one message per this many seconds",
                                    "LIO-SAM handles one loop per loop-closure cycle (loopClosureFrequency, 1 Hz by "
                                    "default): lio_loop gets only verified loops (all when verify is false), one per "
                                    "keyframe.")),
              doubleSetting<O>("unsynchronised_warning", N(unsynchronised_warning), positive(),
                               "warn when clouds come without poses this long [s]"),
              doubleSetting<O>(
                  "no_input_warning", N(no_input_warning), positive(),
                  "warn, naming the topic, when no cloud or odometry came for this long [s]",
                  "Since the start or the last one, with the topic's publisher count, the odometry's with "
                  "pose_source odom (a misspelt or unremapped topic, a stack that stopped); repeated every "
                  "this many seconds while it lasts."),
          }),
      group<O>(
          kSessions,
          {
              enumSetting<O, NodeMode>(
                  "mode", N(mode), parseNodeMode, nodeModeName, {NodeMode::kDetect, NodeMode::kRelocalize},
                  "detect loops, or relocalize in a loaded map",
                  "detect: loops within and across sessions. relocalize: the map in database_load is "
                  "read-only; for every keyframe, its verified place in that map goes out on "
                  "relocalization (geometry_msgs/PoseWithCovarianceStamped, T_map<-sensor in map_frame); "
                  "the keyframe's own session is never a candidate (prior_sessions_only)."),
              stringSetting<O>("map_frame", N(map_frame), {}, "relocalize: the frame of the loaded map's poses"),
              stringSetting<O>("database_load", N(database_load), {}, "database file loaded at start (empty: none)",
                               "As prior sessions; the services ~save_database and ~load_database write and read the "
                               "same format."),
              stringSetting<O>("database_save", N(database_save), {}, "database file written at shutdown (empty: none)",
                               "Never in relocalize mode."),
              boolSetting<O>(
                  "database_save_overwrite", N(database_save_overwrite),
                  "replace a database_save file this run did not load (false: save beside it)",
                  "A file already at database_save that this run did not load (database_load empty, misspelt "
                  "or another file): with false this run's database is saved beside it, to "
                  "<stem>.<unix time>.<extension>, named in a warning, so that a map is never lost to a "
                  "forgotten database_load."),
              boolSetting<O>("database_save_clouds", N(database_save_clouds),
                             "saved databases include the registration clouds",
                             "Several times larger; without them loops into the saved keyframes cannot be verified."),
              doubleSetting<O>("database_autosave_seconds", N(database_autosave_seconds), closed(0, 1e6),
                               "with database_save: also written there this often while it changes [s] (0: at shutdown "
                               "only)",
                               "Wall time, on a thread of its own (detection goes on; the file it replaces is kept as "
                               "<file>.bak), so a crash loses at most this much."),
              doubleSetting<O>(
                  "database_shutdown_seconds", N(database_shutdown_seconds), closed(0.1, 1e6),
                  "the shutdown save (and the autosave in progress) takes at most this long; the rest is "
                  "cancelled and named in the log [s]",
                  "roslaunch sends SIGTERM 15 s after SIGINT, and a save cut off there leaves only a "
                  "temporary file. A write that does not fit is cancelled, the file at database_save stays "
                  "as the last save left it, and the log says how many keyframes of the run are lost."),
              stringSetting<O>("database_directory", N(database_directory), {},
                               "~save_database writes only here (empty: the directory of database_save, else of "
                               "database_load, else $ROS_HOME/scan_context_loop)",
                               "A relative path is a name in it; \"..\", paths outside it and symbolic links are "
                               "refused."),
          }),
      group<O>(
          kTeam,
          {
              stringSetting<O>(
                  "robot_id",
                  N(robot_id),
                  {}, "this robot's id in a team: [A-Za-z0-9_], 1-64, the first a letter (empty: no team)",
                  "With one, the node shares each keyframe it stores on <team_namespace>/keyframe_records, "
                  "takes the other robots' records, and publishes the loops of its keyframes into theirs "
                  "with query_robot / match_robot set (needs mode detect)."),
              stringSetting<O>("team_namespace", N(team_namespace), {}, "the namespace a team's nodes share",
                               "Topics keyframe_records and members there."),
              doubleSetting<O>("team_max_bytes_per_second", N(team_max_bytes_per_second), positive(),
                               "what the node sends to its team, on average at most [B/s]",
                               "Records and the records and registration data it serves: records over it are not "
                               "published live (the others fetch them later), requests over it are answered busy."),
              doubleSetting<O>("team_request_timeout", N(team_request_timeout), positive(),
                               "a request to another robot's node fails after this long [s]",
                               "Its records, a keyframe's registration data; a node that let one time out is asked "
                               "nothing for 30 s."),
              doubleSetting<O>("team_max_bytes", N(team_max_bytes), closed(1e6, 1e12),
                               "memory the other robots' keyframe records may take; more are refused [bytes]",
                               "About 2.6 KB a record: 256 MiB hold about 100,000; refused ones are counted in the "
                               "diagnostics. Their registration data, fetched when a candidate needs them, live in the "
                               "cloud store under verify_max_bytes."),
          }),
  });
}

#undef N
#undef C

}  // namespace

bool SettingRange::contains(double v) const {
  if (!std::isfinite(v)) return false;
  return (open_low ? v > low : v >= low) && (open_high ? v < high : v <= high);
}

std::string SettingRange::interval() const {
  if (!boundedBelow() && !boundedAbove()) return "any";
  if (!boundedAbove()) return std::string(open_low ? "> " : ">= ") + numberText(low);
  if (!boundedBelow()) return std::string(open_high ? "< " : "<= ") + numberText(high);
  return std::string(open_low ? "(" : "[") + numberText(low) + ", " + numberText(high) + (open_high ? ")" : "]");
}

std::string SettingRange::rule() const {
  std::string r;
  if (!boundedBelow() && !boundedAbove()) {
    r = "must be finite";
  } else if (!boundedBelow() || !boundedAbove()) {
    r = "must be finite and " + interval();
  } else {
    r = "must be in " + interval();
  }
  return r + note;
}

std::string deprecatedKeyWarning(const std::string& old_key, const std::string& key) {
  return old_key + " is deprecated, use " + key;
}

const std::vector<Setting<Config>>& configSettings() {
  static const std::vector<Setting<Config>> table = makeConfigSettings();
  return table;
}

const std::vector<Setting<NodeOptions>>& nodeSettings() {
  static const std::vector<Setting<NodeOptions>> table = makeNodeSettings();
  return table;
}

std::string settingTypeName(SettingType type, const std::vector<std::string>& choices) {
  switch (type) {
    case SettingType::kInt:
      return "an integer";
    case SettingType::kDouble:
      return "a number";
    case SettingType::kBool:
      return "true or false";
    case SettingType::kString:
      return "a string";
    case SettingType::kChoice: {
      std::string text = "one of";
      for (std::size_t i = 0; i < choices.size(); ++i) text += (i ? ", " : " ") + choices[i];
      return text;
    }
  }
  return "a value";
}

}  // namespace scan_context_loop
