// scan_context_simulate: ray-cast LiDAR keyframes through a procedural street world along a real KITTI
// trajectory or a procedural drive; writes the KITTI odometry layout and, optionally, a rosbag.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "scan_context_loop/eval/kitti_io.h"
#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/narrow_drive.h"
#include "scan_context_sim/platform_tilt.h"
#include "scan_context_sim/second_session.h"
#include "scan_context_sim/sensor.h"
#include "scan_context_sim/sequence_writer.h"
#include "scan_context_sim/stack_shape.h"
#include "scan_context_sim/suburb_drive.h"
#include "scan_context_sim/odometry_failures.h"
#include "scan_context_sim/trajectory.h"
#include "cli.h"
#include "sim_bag.h"
#include "simulate_team.h"

namespace scl = scan_context_loop;
namespace sim = scan_context_loop::sim;

namespace {

struct Options {
  std::string out;
  std::string kitti;
  int first = 0, last = -1;
  double spacing = std::nan("");  ///< unset: 2 m, or one frame per scan with --stack
  std::string sensor = "hdl64";
  double noise = -1, dropout = -1, max_range = -1, mount = -1, dim_range = -1, voxel = 0;
  bool city = false, narrow = false, block = false, suburb = false;
  double tilt = 0;
  double mount_pitch = 0;
  std::uint32_t seed = 1;
  double dynamic_cars = 0.3;
  double changed_world = 0.0;
  double traffic = 1.0;
  double season = 0.0, construction = 0.0, furniture = 0.0, pass_traffic = 0.0, pass_seconds = 180.0;
  bool repeat_templates = false;
  int session = 1;
  sim::SecondSessionOptions second;
  sim::DriftOptions drift;
  sim::OdometryFailures failures;
  sim::BagOptions bag;
  bool bag_frames = false;  ///< --sensor-frame or --odom-frame given
  sim::TeamOptions team;
  bool team_mode = false;  ///< --team given
  int threads = 0;
};

/// The usage text lists the options in the groups they are registered in.
void addOptions(scl::cli::Parser* cli, Options* o) {
  cli->positional("OUT_DIR", "the sequence folder (created with its parents when missing)", &o->out)
      .section("trajectory (one of)")
      .flag("--procedural", "a 2.1 km city drive with same-direction, reverse and one-lane-offset revisits (default)",
            [o] {
              o->kitti.clear();
              o->city = o->narrow = o->block = o->suburb = false;
            })
      .flag("--city",
            "a 2.2-3 km drive through oblique, partly curved streets: a loop, then after an hour's stop the same "
            "streets again one lane over, in the same lane and the other way",
            &o->city)
      .flag("--suburb",
            "a 2.3-2.7 km drive through a suburb of detached houses (plots behind front gardens and fences, "
            "garages, cars on driveways, trees on grass verges): a ring of curving streets and three "
            "cul-de-sacs, then after a half-hour stop half the ring again one lane over and all of it the other way",
            &o->suburb)
      .flag("--narrow",
            "a 1.0-1.4 km walk (1.5 m/s) through a campus or old town: lanes 5.5 m wide between buildings, a loop, "
            "then the same lanes the same way, the other way and back to the start; no vehicles",
            &o->narrow)
      .flag("--block",
            "a 400 m drive twice around a 60 x 40 m block, the second lap the other way: a short bag to try a "
            "launch file with",
            &o->block)
      .option("--team", "N",
              "a team: N robots (1-6; robot1..robotN) driving different, overlapping routes of 380-430 m each "
              "through one street grid (3 x 2 blocks of 70 x 50 m): the same street the same way, the other way "
              "in the opposite lane and one lane over, and streets only one robot sees; each with its own "
              "drifting odometry from its own first pose. Writes OUT_DIR/team.txt and OUT_DIR/robotN/",
              [o](const std::string& value, std::string* error) {
                char* end = nullptr;
                const long n = std::strtol(value.c_str(), &end, 10);
                if (end == value.c_str() || *end != '\0') {
                  *error = "must be a number of robots, got '" + value + "'";
                  return false;
                }
                o->team.robots = static_cast<int>(n);
                return o->team_mode = true;
              })
      .option("--team-start", "T1,T2,...",
              "with --team: each robot's start, seconds after the earliest (one per robot; default all 0)",
              [o](const std::string& value, std::string* error) {
                o->team.start_offsets.clear();
                std::size_t from = 0;
                while (from <= value.size()) {
                  const std::size_t comma = std::min(value.find(',', from), value.size());
                  const std::string field = value.substr(from, comma - from);
                  char* end = nullptr;
                  const double t = std::strtod(field.c_str(), &end);
                  if (field.empty() || *end != '\0') {
                    *error = "must be seconds separated by commas, got '" + value + "'";
                    return false;
                  }
                  o->team.start_offsets.push_back(t);
                  from = comma + 1;
                }
                return true;
              })
      .option("--kitti-poses", "DIR", "a real KITTI trajectory: DIR/poses.txt, DIR/calib.txt, DIR/times.txt", &o->kitti)
      .option("--first", "N", "first frame of the KITTI trajectory's window (default: all)", &o->first)
      .option("--last", "N", "last frame of the KITTI trajectory's window (default: all)", &o->last)
      .option("--keyframe-spacing", "M",
              "one keyframe every M metres of travel (default 2; with --stack: one per scan at the stack's rate)",
              &o->spacing)
      .section("sensor")
      .option("--sensor", "NAME",
              sim::sensorPresetNames() +
                  " (default hdl64); the Livox ones scan non-repetitive patterns (0.1 s each): give them a "
                  "keyframe spacing below a scan's travel (0.1 m keeps every KITTI frame the car moves in) and "
                  "merge the scans (accumulate_seconds)",
              &o->sensor)
      .option("--noise", "M", "Gaussian range noise sigma [m] (default: the sensor's, 0.02-0.03)", &o->noise)
      .option("--dropout", "P", "probability a return is lost (default 0.02)", &o->dropout)
      .option("--max-range", "M", "maximum range [m] (default: the sensor's, 70-200)", &o->max_range)
      .option("--mount-height", "M", "sensor height above the ground [m] (default 1.73)", &o->mount)
      .option("--tilt", "DEG",
              "hand-held or legged platform: the sensor rolls and pitches (a slow sway and a gait), |tilt| median "
              "about 0.7 x DEG, 90th percentile 1.25 x DEG (default 0: level)",
              &o->tilt)
      .option("--mount-pitch", "DEG",
              "the sensor mounted pitched by DEG (positive: nose down), all drive long (default 0)", &o->mount_pitch)
      .option("--dim-range", "M",
              "range at which a dim return (10 % reflectivity, head-on) is detected half the time; brighter "
              "surfaces reach further, grazing ground fades sooner (default: the sensor's, 40-120; 0: no fading)",
              &o->dim_range)
      .option("--voxel", "M", "write clouds downsampled to M-metre voxels (default 0: raw scans)", &o->voxel)
      .section("world and odometry")
      .option("--seed", "N", "world, noise and drift seed (default 1)", &o->seed)
      .option("--dynamic-cars", "F",
              "fraction of parked cars that leave, arrive or move a few metres at some time during the drive, so "
              "revisits differ (default 0.3)",
              &o->dynamic_cars)
      .option("--changed-world", "F",
              "revisits as days later, more the later (0: off, default; 1: strong): parked cars and vegetation "
              "change, construction sites, traffic, people",
              &o->changed_world)
      .option("--traffic", "F", "with --changed-world: F times its traffic and pedestrians (default 1; 3: rush hour)",
              &o->traffic)
      .option("--season", "F",
              "leaf-off: about F of the broadleaved trees lose their leaves (trunk, limbs and a sparse crown of "
              "twigs stay) and as many hedges and bushes thin out, each at its own time (default 0: off)",
              &o->season)
      .option("--construction", "F",
              "building sites, about F per 100 m of drive, each from its own time: mesh site fences along the "
              "pavement or round a lot, stacked shipping containers at the kerb or in lots (default 0: off)",
              &o->construction)
      .option("--furniture", "F",
              "about F of the benches, bins, cabinets, bollards, sign posts and bus shelters are moved 2-12 m or "
              "taken away, and new benches and bins appear (default 0: off)",
              &o->furniture)
      .option("--pass-traffic", "F",
              "a different density on each pass (the clock cut at stops and every --pass-seconds): parked cars "
              "present (F = 1: 30-100 %), empty spaces taken, traffic x1/3 to x3 (default 0: off)",
              &o->pass_traffic)
      .option("--pass-seconds", "S", "with --pass-traffic: the longest pass [s] (default 180)", &o->pass_seconds)
      .flag("--repeat-templates", "buildings and frontage from a few designs per district: streets alike",
            &o->repeat_templates)
      .option("--session", "N",
              "1 (default): the drive; 2: the same world on another day, for relocalization in session 1's map: "
              "the drive from its end back to its start in the other lane, parked cars and vegetation changed, "
              "traffic; truth in session 1's frame, its own odometry (from the identity), noise and drift, times "
              "from 0. Give the other options as for session 1",
              &o->session)
      .option("--session-lane", "M",
              "session 2: lateral offset to the right of its direction of travel [m] (default 3: the other lane; "
              "with --narrow give 0, its paths are footpaths)",
              &o->second.lane_offset)
      .option("--session-changes", "F",
              "session 2: how much parked cars and vegetation changed since session 1 (0-1, default 1)",
              &o->second.changed)
      .option("--drift-trans", "F", "odometry translation error per metre travelled (default 0.01: 1 %)",
              &o->drift.translation_per_metre)
      .option("--drift-yaw-per-m", "D", "odometry heading error per metre travelled [deg/m] (default 0.003)",
              &o->drift.yaw_per_metre)
      .option("--drift-yaw", "F", "odometry heading error per degree turned [deg/deg] (default 0.005)",
              &o->drift.yaw_per_degree)
      .alias("--drift-yaw-per-deg")
      .option("--drift-correlation", "M", "distance over which the odometry's error biases change [m] (default 300)",
              &o->drift.correlation_length)
      .option("--heading-ramp", "DEG",
              "odometry that breaks down: a heading error growing with the distance travelled from "
              "--heading-ramp-start on to DEG at the end (default 0: none)",
              &o->failures.heading_ramp_deg)
      .option("--heading-ramp-start", "F", "where the heading ramp starts, a fraction of the path (default 0.5)",
              &o->failures.ramp_start)
      .option("--heading-jumps", "N", "sudden odometry heading errors at N random keyframes (default 0)",
              &o->failures.heading_jumps)
      .option("--heading-jump", "DEG", "size of each heading jump, random sign (default 15)",
              &o->failures.heading_jump_deg)
      .option("--slip-start", "M", "a degenerate stretch from M metres along the path (with --slip-length)",
              &o->failures.slip_start)
      .option("--slip-length", "M", "its length: the odometry's forward motion is scaled there (default 0: none)",
              &o->failures.slip_length)
      .option("--slip-scale", "F", "the forward motion's scale over the slip (default 0.5)", &o->failures.slip_scale)
      .option("--odometry-restart", "M",
              "the odometry restarts from the identity at M metres of path, the stamps going on (default: never)",
              &o->failures.restart_at)
      .section("rosbag")
      .option("--bag", "FILE",
              "also write a bag (its folder is created when missing): keyframe clouds (PointCloud2, x y z "
              "intensity, sensor frame), drifted odometry and ground truth (nav_msgs/Odometry)",
              &o->bag.path)
      .option("--stack", "NAME",
              sim::stackNames() +
                  ": shape the bag like that odometry stack's output: its topics, frames, registered or "
                  "sensor-frame clouds, camera-axes odometry with its /tf_static (lego_loam), and one cloud per "
                  "scan at its rate (10 Hz) unless --keyframe-spacing is given; the ground truth is shaped like "
                  "the odometry",
              [o](const std::string& name, std::string* error) {
                const sim::StackShape* shape = sim::findStackShape(name);
                if (shape == nullptr)
                  *error = "must be one of " + sim::stackNames() + ", got '" + name + "'";
                else
                  o->bag.shape = *shape;
                return shape != nullptr;
              })
      .option("--cloud-topic", "T", "the clouds' topic (default keyframe_cloud)", &o->bag.shape.cloud_topic)
      .option("--odom-topic", "T", "the drifted odometry's topic (default keyframe_odom)", &o->bag.shape.odom_topic)
      .option("--truth-topic", "T", "the ground truth's topic (default ground_truth)", &o->bag.truth_topic)
      .option("--sensor-frame", "F", "the clouds' frame and the odometry's child frame (default velodyne)",
              [o](const std::string& frame, std::string*) {
                o->bag.shape.cloud_frame = o->bag.shape.child_frame = frame;
                return o->bag_frames = true;
              })
      .option("--odom-frame", "F", "the odometry's frame (default odom)",
              [o](const std::string& frame, std::string*) {
                o->bag.shape.odom_frame = frame;
                return o->bag_frames = true;
              })
      .section("other")
      .option("--threads", "N", "ray-casting threads (default: all cores)", &o->threads)
      .epilogue(
          "scripts/simulate only:\n"
          "  --render                   also render OUT_DIR/render_map.png (whole map), render_detail.png (120 m\n"
          "                             around keyframe 20) and render_scan.png (keyframe 20: top-down, side view,\n"
          "                             range image) with scripts/render_sequence.py; with --team, each robot's\n"
          "                             in OUT_DIR/<robot>/");
}

/// Checks the values together; empty when they are fine.
std::string check(const Options& o) {
  if (!std::isnan(o.spacing) && !(o.spacing > 0.0)) return "--keyframe-spacing must be positive";
  if (o.dropout >= 1.0) return "--dropout must be below 1";
  if (o.drift.translation_per_metre < 0 || o.drift.yaw_per_metre < 0 || o.drift.yaw_per_degree < 0)
    return "drift rates must be >= 0";
  if (const std::string why = sim::checkFailures(o.failures); !why.empty()) return why;
  if (o.voxel < 0.0) return "--voxel must be >= 0";
  if (o.city + o.narrow + o.block + o.suburb + !o.kitti.empty() > 1)
    return "--city, --suburb, --narrow, --block and --kitti-poses exclude each other";
  if (o.season < 0.0 || o.season > 1.0 || o.furniture < 0.0 || o.furniture > 1.0 || o.pass_traffic < 0.0 ||
      o.pass_traffic > 1.0)
    return "--season, --furniture and --pass-traffic must be in [0, 1]";
  if (o.construction < 0.0) return "--construction must be >= 0";
  if (!(o.pass_seconds >= 10.0)) return "--pass-seconds must be at least 10";
  if (!o.bag.shape.name.empty() && o.bag.path.empty()) return "--stack shapes the bag: it needs --bag FILE";
  if (o.bag_frames && !o.bag.shape.name.empty()) return "--stack sets the frames: no --sensor-frame or --odom-frame";
  if (o.tilt < 0.0) return "--tilt must be >= 0";
  if (!(std::fabs(o.mount_pitch) <= 45.0)) return "--mount-pitch must be within +-45 degrees";
  if (o.changed_world < 0.0) return "--changed-world must be >= 0";
  if (!(o.traffic >= 0.0 && o.traffic <= 20.0)) return "--traffic must be in [0, 20]";
  if (o.session != 1 && o.session != 2) return "--session must be 1 or 2";
  if (o.second.changed < 0.0 || o.second.changed > 1.0) return "--session-changes must be in [0, 1]";
  if (!o.team.start_offsets.empty() && !o.team_mode) return "--team-start needs --team";
  if (o.team_mode) {
    if (const std::string why = sim::checkTeam(o.team); !why.empty()) return "--team: " + why;
    if (o.city || o.narrow || o.block || o.suburb || !o.kitti.empty())
      return "--team drives its own routes: no other trajectory";
    if (o.season > 0.0 || o.construction > 0.0 || o.furniture > 0.0 || o.pass_traffic > 0.0)
      return "--team has no --season, --construction, --furniture or --pass-traffic (they follow one drive)";
    if (o.session != 1) return "--team has no --session 2";
    if (o.changed_world > 0.0) return "--team has no --changed-world (its traffic follows one drive)";
    if (o.tilt > 0.0 || o.mount_pitch != 0.0) return "--team has no --tilt or --mount-pitch";
    if (o.failures.any())
      return "--team has no odometry failures (--heading-ramp, --heading-jumps, --slip-length, "
             "--odometry-restart)";
    if (!o.bag.shape.name.empty() || o.bag_frames) {
      return "--team bags have the default shape, each robot's topics and frames in its namespace: no --stack, "
             "--sensor-frame or --odom-frame";
    }
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string error;
  scl::cli::Parser cli("scan_context_simulate",
                       "Ray-casts LiDAR keyframes through a generated street world and writes OUT_DIR in the KITTI "
                       "odometry layout: velodyne/%06d.bin, poses.txt (ground truth), odom_poses.txt (drifted "
                       "odometry), times.txt, calib.txt (Tr: identity, so poses.txt holds LiDAR poses), "
                       "sequence.txt (what was simulated).");
  addOptions(&cli, &o);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  error = check(o);
  if (!error.empty()) return cli.fail(error);
  sim::SensorModel sensor;
  if (!sim::sensorPreset(o.sensor, &sensor)) {
    std::fprintf(stderr, "scan_context_simulate: unknown sensor '%s' (%s)\n", o.sensor.c_str(),
                 sim::sensorPresetNames().c_str());
    return 2;
  }
  if (o.noise >= 0) sensor.range_noise = static_cast<float>(o.noise);
  if (o.dropout >= 0) sensor.dropout = static_cast<float>(o.dropout);
  if (o.max_range > 0) sensor.max_range = static_cast<float>(o.max_range);
  if (o.mount > 0) sensor.mount_height = static_cast<float>(o.mount);
  if (o.dim_range >= 0) sensor.dim_range = static_cast<float>(o.dim_range);

  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (!scl::cli::makeDirectories(o.out, &error) ||
      (!o.bag.path.empty() && std::filesystem::path(o.bag.path).has_parent_path() &&
       !scl::cli::makeDirectories(std::filesystem::path(o.bag.path).parent_path().string(), &error))) {
    std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
    return 1;
  }
  if (o.team_mode) {
    sim::TeamRun run;
    run.out = o.out;
    run.team = o.team;
    run.sensor = sensor;
    run.world.seed = o.seed;
    run.world.dynamic_car_fraction = o.dynamic_cars;
    run.world.repeat_templates = o.repeat_templates;
    run.drift = o.drift;
    run.spacing = std::isnan(o.spacing) ? 2.0 : o.spacing;
    run.voxel = o.voxel;
    run.seed = o.seed;
    run.threads = threads;
    run.bag = o.bag;
    if (!sim::simulateTeam(run, &error)) {
      std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
      return 1;
    }
    return 0;
  }

  // The drive: every source frame (for the world) and the keyframes along it.
  std::vector<sim::PathPoint> path;
  std::vector<double> source_times;
  sim::WorldOptions world_options;
  sim::NarrowOptions narrow;
  narrow.seed = o.seed;
  if (!o.kitti.empty()) {
    std::vector<Eigen::Isometry3d> camera;
    Eigen::Isometry3d tr;
    if (!scl::kitti::readPoses(o.kitti + "/poses.txt", &camera, &error) ||
        !scl::kitti::readCalibTr(o.kitti + "/calib.txt", &tr, &error)) {
      std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
      return 1;
    }
    path = sim::pathFromPoses(scl::kitti::lidarPoses(camera, tr), o.first, o.last);
    std::vector<double> times;
    if (scl::kitti::readTimes(o.kitti + "/times.txt", &times, &error)) {
      for (std::size_t k = 0; k < path.size(); ++k) {
        const std::size_t frame = k + std::max(0, o.first);
        source_times.push_back(frame < times.size() ? times[frame] : 0.1 * frame);
      }
    }
  } else if (o.city) {
    sim::CityOptions city;
    city.seed = o.seed;
    const sim::TimedPath drive = sim::cityDrive(city);
    path = drive.path;
    source_times = drive.times;
  } else if (o.suburb) {
    sim::SuburbOptions suburb;
    suburb.seed = o.seed;
    const sim::TimedPath drive = sim::suburbDrive(suburb);
    path = drive.path;
    source_times = drive.times;
    sim::suburbWorld(&world_options);
  } else if (o.narrow) {
    const sim::TimedPath drive = sim::narrowDrive(narrow);
    path = drive.path;
    source_times = drive.times;
    sim::narrowWorld(narrow, &world_options);
  } else if (o.block) {
    path = sim::blockPath(true);
  } else {
    path = sim::proceduralPath();
  }
  if (source_times.size() != path.size()) {
    // 10 m/s along the path.
    source_times.assign(path.size(), 0.0);
    for (std::size_t k = 1; k < path.size(); ++k) {
      source_times[k] = source_times[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y) / 10.0;
    }
  }
  if (path.size() < 2) {
    std::fprintf(stderr, "scan_context_simulate: the trajectory has fewer than two frames\n");
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  world_options.seed = o.seed;
  world_options.dynamic_car_fraction = o.dynamic_cars;
  world_options.duration = source_times.back() - source_times.front();
  world_options.changed_world = o.changed_world;
  world_options.traffic = o.traffic;
  world_options.repeat_templates = o.repeat_templates;
  world_options.season = o.season;
  world_options.construction = o.construction;
  world_options.furniture = o.furniture;
  world_options.pass_traffic = o.pass_traffic;
  world_options.pass_seconds = o.pass_seconds;
  for (double t : source_times) world_options.times.push_back(t - source_times.front());
  // The drive simulated: session 1's, or session 2's through the same world on another day. The world
  // is always built along session 1's path.
  sim::TimedPath drive{path, world_options.times};
  double world_clock = 0.0;
  sim::World world;
  if (o.session == 2) {
    drive = sim::secondSessionDrive(path, world_options.times, o.second);
    const sim::LaterDrive later = sim::laterDrive(drive, world_options.duration, o.second);
    world_clock = later.times.front();
    world = sim::generateWorld(path, world_options, later);
  } else {
    world = sim::generateWorld(path, world_options);
  }
  // Session 2's sensor noise and odometry drift are drawn afresh.
  const std::uint32_t run_seed = o.session == 1 ? o.seed : o.seed ^ 0x5E55102u;

  // A stack's bag has every scan; otherwise a keyframe every --keyframe-spacing metres.
  const bool per_scan = std::isnan(o.spacing) && o.bag.shape.rate_hz > 0.0;
  const double spacing = std::isnan(o.spacing) ? 2.0 : o.spacing;
  const std::vector<std::size_t> keyframes =
      per_scan ? sim::framesEvery(drive.times, 1.0 / o.bag.shape.rate_hz) : sim::keyframesEvery(drive.path, spacing);
  sim::SequenceData data;
  data.world_clock = world_clock;
  sim::TiltOptions tilt;
  tilt.typical_deg = o.tilt;
  tilt.seed = run_seed;
  const std::vector<Eigen::Vector2d> roll_pitch = sim::platformTilt(drive.path, tilt);
  for (std::size_t k : keyframes) {
    data.truth.push_back(sim::sensorPose(world, drive.path[k], sensor.mount_height));
    if (o.tilt > 0) data.truth.back() = sim::tiltPose(data.truth.back(), roll_pitch[k]);
    if (o.mount_pitch != 0.0) data.truth.back() = sim::tiltPose(data.truth.back(), {0.0, o.mount_pitch * M_PI / 180.0});
    data.times.push_back(drive.times[k]);
  }
  o.drift.seed = run_seed;
  data.odometry = sim::driftedOdometry(data.truth, o.drift);
  o.failures.seed = run_seed;
  data.odometry = sim::withFailures(data.odometry, o.failures);
  if (o.session == 2) {
    // A run of its own: its odometry starts at the identity, knowing nothing of session 1's frame.
    const Eigen::Isometry3d origin = data.odometry.front().inverse();
    for (Eigen::Isometry3d& pose : data.odometry) pose = origin * pose;
  }
  const double mean_points = sim::writeSequence(o.out, world, sensor, data, o.voxel, run_seed, threads, &error);
  if (mean_points < 0) {
    std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
    return 1;
  }
  const auto& truth = data.truth;
  double length = 0.0;
  for (std::size_t k = 1; k < truth.size(); ++k) length += (truth[k].translation() - truth[k - 1].translation()).norm();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ofstream info(o.out + "/sequence.txt");
  info << "trajectory: "
       << (!o.kitti.empty() ? o.kitti
           : o.city         ? "city"
           : o.suburb       ? "suburb"
           : o.narrow       ? "narrow"
           : o.block        ? "block"
                            : "procedural")
       << "\n"
       << "frames: " << o.first << " .. " << (o.last < 0 ? std::string("end") : std::to_string(o.last)) << "\n"
       << "keyframes: " << keyframes.size() << "\n";
  if (per_scan)
    info << "scan_rate_hz: " << o.bag.shape.rate_hz;
  else
    info << "keyframe_spacing_m: " << spacing;
  info << "\nlength_m: " << length << "\nsensor: " << sensor.name << "\n";
  if (sensor.pattern == sim::ScanPattern::kSpinning) {
    info << "beams: " << sensor.elevations_deg.size() << "\ncolumns: " << sensor.columns;
  } else {
    info << "rays_per_scan: " << sensor.rays_per_scan << "\nfov_horizontal_deg: " << sensor.fov_horizontal_deg;
  }
  info << "\nelevation_top_deg: " << sim::fovTopDeg(sensor) << "\nelevation_bottom_deg: " << sim::fovBottomDeg(sensor)
       << "\nrange_noise_m: " << sensor.range_noise << "\ndropout: " << sensor.dropout
       << "\nmax_range_m: " << sensor.max_range << "\ndim_range_m: " << sensor.dim_range
       << "\nmount_height_m: " << sensor.mount_height << "\nvoxel_m: " << o.voxel << "\nseed: " << o.seed
       << "\nworld_primitives: " << world.size() << "\ndynamic_car_fraction: " << o.dynamic_cars
       << "\ndrift_translation_per_m: " << o.drift.translation_per_metre
       << "\ndrift_yaw_deg_per_m: " << o.drift.yaw_per_metre << "\ndrift_yaw_per_deg: " << o.drift.yaw_per_degree
       << "\ndrift_correlation_m: " << o.drift.correlation_length << "\nseconds: " << seconds << "\n";
  if (o.tilt > 0) info << "tilt_deg: " << o.tilt << "\n";
  if (o.mount_pitch != 0.0) info << "mount_pitch_deg: " << o.mount_pitch << "\n";
  const sim::OdometryFailures& f = o.failures;
  if (f.heading_ramp_deg != 0.0)
    info << "odometry_heading_ramp_deg: " << f.heading_ramp_deg << " from " << f.ramp_start << "\n";
  if (f.heading_jumps > 0)
    info << "odometry_heading_jumps: " << f.heading_jumps << " x " << f.heading_jump_deg << " deg\n";
  if (f.slip_length > 0.0)
    info << "odometry_slip: " << f.slip_length << " m from " << f.slip_start << " m, scale " << f.slip_scale << "\n";
  if (f.restart_at >= 0.0) info << "odometry_restart_m: " << f.restart_at << "\n";
  info << "changed_world: " << o.changed_world << "\ntraffic: " << o.traffic
       << "\nrepeat_templates: " << o.repeat_templates << "\n";
  // Only when switched on, so the sequences made without them describe themselves as before.
  if (o.season > 0.0) info << "season: " << o.season << "\n";
  if (o.construction > 0.0) info << "construction: " << o.construction << "\n";
  if (o.furniture > 0.0) info << "furniture: " << o.furniture << "\n";
  if (o.pass_traffic > 0.0) info << "pass_traffic: " << o.pass_traffic << " every " << o.pass_seconds << " s\n";
  if (!o.bag.shape.name.empty()) info << "stack: " << o.bag.shape.name << "\n";
  info << "session: " << o.session << "\n";
  if (o.session == 2) {
    info << "session_lane_offset_m: " << o.second.lane_offset << "\nsession_changes: " << o.second.changed
         << "\nsession_world_clock_s: " << world_clock << "\n";
  }

  if (!o.bag.path.empty()) {
    if (!sim::writeBag(o.out, truth, data.odometry, data.times, o.bag, &error)) {
      std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
      return 1;
    }
  }
  std::printf("%zu keyframes (%.0f m, %.0f points on average, %s) in %.1f s with %d threads -> %s\n", keyframes.size(),
              length, mean_points, sensor.name.c_str(), seconds, threads, o.out.c_str());
  return 0;
}
