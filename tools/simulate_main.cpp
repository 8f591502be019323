// scan_context_simulate: ray-cast LiDAR keyframes through a procedural street world along a real KITTI
// trajectory or a procedural drive; writes the KITTI odometry layout and, optionally, a rosbag.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>


#include "scan_context_loop/kitti_io.h"
#include "scan_context_loop/sim/city_drive.h"
#include "scan_context_loop/sim/narrow_drive.h"
#include "scan_context_loop/sim/platform_tilt.h"
#include "scan_context_loop/sim/sequence_writer.h"
#include "scan_context_loop/sim/trajectory.h"
#include "sim_bag.h"

namespace scl = scan_context_loop;
namespace sim = scan_context_loop::sim;

namespace {

const char* kUsage = R"(usage: scan_context_simulate OUT_DIR [options]

Ray-casts LiDAR keyframes through a generated street world and writes OUT_DIR in the KITTI odometry
layout: velodyne/%06d.bin, poses.txt (ground truth), odom_poses.txt (drifted odometry), times.txt,
calib.txt (Tr: identity, so poses.txt holds LiDAR poses), sequence.txt (what was simulated).

trajectory (one of):
  --procedural               a 2.1 km city drive with same-direction, reverse and one-lane-offset
                             revisits (default)
  --city                     a 2.2-3 km drive through oblique, partly curved streets: a loop, then after
                             an hour's stop the same streets again one lane over, in the same lane and
                             the other way
  --narrow                   a 1.0-1.4 km walk (1.5 m/s) through a campus or old town: lanes 5.5 m
                             wide between buildings, a loop, then the same lanes the same way, the
                             other way and back to the start; no vehicles
  --kitti-poses DIR          a real KITTI trajectory: DIR/poses.txt, DIR/calib.txt, DIR/times.txt
  --first N, --last N        frame window of the KITTI trajectory (default: all)
  --keyframe-spacing M       one keyframe every M metres of travel (default 2)

sensor:
  --sensor NAME              hdl64 | vlp16 | os1-64 (default hdl64)
  --noise M                  Gaussian range noise sigma [m] (default: the sensor's, 0.02-0.03)
  --dropout P                probability a return is lost (default 0.02)
  --max-range M              maximum range [m] (default: the sensor's, 100-120)
  --mount-height M           sensor height above the ground [m] (default 1.73)
  --tilt DEG                 hand-held or legged platform: the sensor rolls and pitches (a slow sway and
                             a gait), |tilt| median about 0.7 x DEG, 90th percentile 1.25 x DEG
                             (default 0: level)
  --dim-range M              range at which a dim return (10 % reflectivity, head-on) is detected half
                             the time; brighter surfaces reach further, grazing ground fades sooner
                             (default: the sensor's, 55-80; 0: no fading)
  --voxel M                  write clouds downsampled to M-metre voxels (default 0: raw scans)

world and odometry:
  --seed N                   world, noise and drift seed (default 1)
  --dynamic-cars F           fraction of parked cars that leave, arrive or move a few metres at some
                             time during the drive, so revisits differ (default 0.3)
  --changed-world F          revisits as days later, more the later (0: off, default; 1: strong):
                             parked cars and vegetation change, construction sites, traffic, people
  --repeat-templates         buildings and frontage from a few designs per district: streets alike
  --drift-trans F            odometry translation error per metre travelled (default 0.01: 1 %)
  --drift-yaw-per-m D        odometry heading error per metre travelled [deg/m] (default 0.003)
  --drift-yaw F, --drift-yaw-per-deg F
                             odometry heading error per degree turned [deg/deg] (default 0.005)
  --drift-correlation M      distance over which the odometry's error biases change [m] (default 300)

rosbag:
  --bag FILE                 also write a bag: keyframe clouds (PointCloud2, x y z intensity, sensor
                             frame), drifted odometry and ground truth (nav_msgs/Odometry)
  --cloud-topic T            (default keyframe_cloud)
  --odom-topic T             (default keyframe_odom)
  --truth-topic T            (default ground_truth)
  --sensor-frame F           (default velodyne)
  --odom-frame F             (default odom)

  --threads N                ray-casting threads (default: all cores)

scripts/simulate only:
  --render                   also render OUT_DIR/render_map.png (whole map), render_detail.png (120 m
                             around keyframe 20) and render_scan.png (keyframe 20: top-down, side view,
                             range image) with scripts/render_sequence.py
)";

struct Options {
  std::string out;
  std::string kitti;
  int first = 0, last = -1;
  double spacing = 2.0;
  std::string sensor = "hdl64";
  double noise = -1, dropout = -1, max_range = -1, mount = -1, dim_range = -1, voxel = 0;
  bool city = false, narrow = false;
  double tilt = 0;
  std::uint32_t seed = 1;
  double dynamic_cars = 0.3;
  double changed_world = 0.0;
  bool repeat_templates = false;
  sim::DriftOptions drift;
  sim::BagOptions bag;
  int threads = 0;
};

bool parse(int argc, char** argv, Options* o, std::string* error) {
  std::map<std::string, std::string*> strings = {{"--kitti-poses", &o->kitti},  {"--sensor", &o->sensor},
                                                 {"--bag", &o->bag.path},        {"--cloud-topic", &o->bag.cloud_topic},
                                                 {"--odom-topic", &o->bag.odom_topic}, {"--truth-topic", &o->bag.truth_topic},
                                                 {"--sensor-frame", &o->bag.sensor_frame}, {"--odom-frame", &o->bag.odom_frame}};
  std::map<std::string, double*> numbers = {
      {"--keyframe-spacing", &o->spacing}, {"--noise", &o->noise}, {"--dropout", &o->dropout},
      {"--max-range", &o->max_range}, {"--mount-height", &o->mount}, {"--dim-range", &o->dim_range},
      {"--voxel", &o->voxel},
      {"--tilt", &o->tilt},
      {"--changed-world", &o->changed_world},
      {"--dynamic-cars", &o->dynamic_cars}, {"--drift-trans", &o->drift.translation_per_metre},
      {"--drift-yaw-per-m", &o->drift.yaw_per_metre}, {"--drift-yaw-per-deg", &o->drift.yaw_per_degree},
      {"--drift-yaw", &o->drift.yaw_per_degree}, {"--drift-correlation", &o->drift.correlation_length}};
  std::map<std::string, int*> integers = {{"--first", &o->first}, {"--last", &o->last}, {"--threads", &o->threads}};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--procedural") {
      o->kitti.clear();
      o->city = o->narrow = false;
      continue;
    }
    if (arg == "--city" || arg == "--narrow") {
      (arg == "--city" ? o->city : o->narrow) = true;
      continue;
    }
    if (arg == "--repeat-templates") {
      o->repeat_templates = true;
      continue;
    }
    const bool has_value = i + 1 < argc;
    try {
      if (strings.count(arg) && has_value) {
        *strings[arg] = argv[++i];
      } else if (numbers.count(arg) && has_value) {
        *numbers[arg] = std::stod(argv[++i]);
      } else if (integers.count(arg) && has_value) {
        *integers[arg] = std::stoi(argv[++i]);
      } else if (arg == "--seed" && has_value) {
        o->seed = static_cast<std::uint32_t>(std::stoul(argv[++i]));
      } else if (arg.rfind("--", 0) != 0 && o->out.empty()) {
        o->out = arg;
      } else {
        *error = "unknown or incomplete option: " + arg;
        return false;
      }
    } catch (const std::exception&) {
      *error = "not a number: " + arg + " " + argv[i];
      return false;
    }
  }
  if (o->out.empty()) *error = "OUT_DIR is missing";
  else if (!(o->spacing > 0.0)) *error = "--keyframe-spacing must be positive";
  else if (o->dropout >= 1.0) *error = "--dropout must be below 1";
  else if (o->drift.translation_per_metre < 0 || o->drift.yaw_per_metre < 0 || o->drift.yaw_per_degree < 0)
    *error = "drift rates must be >= 0";
  else if (o->voxel < 0.0) *error = "--voxel must be >= 0";
  else if (o->city + o->narrow + !o->kitti.empty() > 1) *error = "--city, --narrow and --kitti-poses exclude each other";
  else if (o->tilt < 0.0) *error = "--tilt must be >= 0";
  else if (o->changed_world < 0.0) *error = "--changed-world must be >= 0";
  return error->empty();
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  Options o;
  std::string error;
  if (!parse(argc, argv, &o, &error)) {
    std::fprintf(stderr, "scan_context_simulate: %s\n\n%s", error.c_str(), kUsage);
    return 2;
  }
  sim::SensorModel sensor;
  if (!sim::sensorPreset(o.sensor, &sensor)) {
    std::fprintf(stderr, "scan_context_simulate: unknown sensor '%s' (hdl64, vlp16, os1-64)\n", o.sensor.c_str());
    return 2;
  }
  if (o.noise >= 0) sensor.range_noise = static_cast<float>(o.noise);
  if (o.dropout >= 0) sensor.dropout = static_cast<float>(o.dropout);
  if (o.max_range > 0) sensor.max_range = static_cast<float>(o.max_range);
  if (o.mount > 0) sensor.mount_height = static_cast<float>(o.mount);
  if (o.dim_range >= 0) sensor.dim_range = static_cast<float>(o.dim_range);

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
  } else if (o.narrow) {
    const sim::TimedPath drive = sim::narrowDrive(narrow);
    path = drive.path;
    source_times = drive.times;
    sim::narrowWorld(narrow, &world_options);
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
  const std::vector<std::size_t> keyframes = sim::keyframesEvery(path, o.spacing);

  const auto t0 = std::chrono::steady_clock::now();
  world_options.seed = o.seed;
  world_options.dynamic_car_fraction = o.dynamic_cars;
  world_options.duration = source_times.back() - source_times.front();
  world_options.changed_world = o.changed_world;
  world_options.repeat_templates = o.repeat_templates;
  for (double t : source_times) world_options.times.push_back(t - source_times.front());
  const sim::World world = sim::generateWorld(path, world_options);

  sim::SequenceData data;
  sim::TiltOptions tilt;
  tilt.typical_deg = o.tilt;
  tilt.seed = o.seed;
  const std::vector<Eigen::Vector2d> roll_pitch = sim::platformTilt(path, tilt);
  for (std::size_t k : keyframes) {
    data.truth.push_back(sim::sensorPose(world, path[k], sensor.mount_height));
    if (o.tilt > 0) data.truth.back() = sim::tiltPose(data.truth.back(), roll_pitch[k]);
    data.times.push_back(source_times[k] - source_times.front());
  }
  o.drift.seed = o.seed;
  data.odometry = sim::driftedOdometry(data.truth, o.drift);
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const double mean_points = sim::writeSequence(o.out, world, sensor, data, o.voxel, o.seed, threads, &error);
  if (mean_points < 0) {
    std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
    return 1;
  }
  const auto& truth = data.truth;
  double length = 0.0;
  for (std::size_t k = 1; k < truth.size(); ++k) length += (truth[k].translation() - truth[k - 1].translation()).norm();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ofstream info(o.out + "/sequence.txt");
  info << "trajectory: " << (!o.kitti.empty() ? o.kitti : o.city ? "city" : o.narrow ? "narrow" : "procedural") << "\n"
       << "frames: " << o.first << " .. " << (o.last < 0 ? std::string("end") : std::to_string(o.last)) << "\n"
       << "keyframes: " << keyframes.size() << "\nkeyframe_spacing_m: " << o.spacing << "\nlength_m: " << length
       << "\nsensor: " << sensor.name << "\nbeams: " << sensor.elevations_deg.size() << "\ncolumns: " << sensor.columns
       << "\nelevation_top_deg: " << sensor.elevations_deg.front()
       << "\nelevation_bottom_deg: " << sensor.elevations_deg.back() << "\nrange_noise_m: " << sensor.range_noise
       << "\ndropout: " << sensor.dropout << "\nmax_range_m: " << sensor.max_range
       << "\ndim_range_m: " << sensor.dim_range << "\nmount_height_m: " << sensor.mount_height
       << "\nvoxel_m: " << o.voxel << "\nseed: " << o.seed << "\nworld_primitives: " << world.size()
       << "\ndynamic_car_fraction: " << o.dynamic_cars << "\ndrift_translation_per_m: "
       << o.drift.translation_per_metre << "\ndrift_yaw_deg_per_m: " << o.drift.yaw_per_metre
       << "\ndrift_yaw_per_deg: " << o.drift.yaw_per_degree
       << "\ndrift_correlation_m: " << o.drift.correlation_length << "\nseconds: " << seconds << "\n";
  if (o.tilt > 0) info << "tilt_deg: " << o.tilt << "\n";
  info << "changed_world: " << o.changed_world << "\nrepeat_templates: " << o.repeat_templates << "\n";

  if (!o.bag.path.empty()) {
    if (!sim::writeBag(o.out, truth, data.odometry, data.times, o.bag, &error)) {
      std::fprintf(stderr, "scan_context_simulate: %s\n", error.c_str());
      return 1;
    }
  }
  std::printf("%zu keyframes (%.0f m, %.0f points on average, %s) in %.1f s with %d threads -> %s\n",
              keyframes.size(), length, mean_points, sensor.name.c_str(), seconds, threads, o.out.c_str());
  return 0;
}
