#include "scan_context_loop/graph/map_files.h"
#include "scan_context_loop/graph/map_set.h"
#include "scan_context_loop/core/team_matcher.h"

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <memory>

#include <Eigen/Cholesky>
#include <pcl/io/pcd_io.h>
#include <sys/stat.h>
#include <unistd.h>

namespace scan_context_loop {

namespace {

constexpr const char* kCloudFile = "map.pcd";

void appendf(std::string* out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string* out, const char* format, ...) {
  char buffer[256];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  if (n > 0) out->append(buffer, static_cast<std::size_t>(std::min<int>(n, sizeof(buffer) - 1)));
}

/// Integer nanoseconds as seconds with nine decimals (exact: no double in between).
void appendStamp(std::string* out, std::int64_t ns) {
  const bool negative = ns < 0;
  const std::uint64_t u = negative ? std::uint64_t(0) - static_cast<std::uint64_t>(ns) : static_cast<std::uint64_t>(ns);
  appendf(out, "%s%" PRIu64 ".%09" PRIu64, negative ? "-" : "", u / 1000000000u, u % 1000000000u);
}

/// 17 significant digits: the double read back is the one written.
void appendNumber(std::string* out, double value) { appendf(out, " %.17g", value); }

/// The rotation as a unit quaternion with w >= 0 (g2o's and evo's habit).
Eigen::Quaterniond quaternionOf(const Eigen::Isometry3d& pose) {
  Eigen::Quaterniond q(pose.linear());
  q.normalize();
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  return q;
}

/// " x y z qx qy qz qw"
void appendPose(std::string* out, const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q = quaternionOf(pose);
  for (int i = 0; i < 3; ++i) appendNumber(out, pose.translation()[i]);
  for (const double v : {q.x(), q.y(), q.z(), q.w()}) appendNumber(out, v);
}

std::string tumText(const std::vector<std::int64_t>& stamps, const std::vector<Eigen::Isometry3d>& poses) {
  std::string out = "# timestamp tx ty tz qx qy qz qw\n";
  for (std::size_t i = 0; i < poses.size(); ++i) {
    appendStamp(&out, stamps[i]);
    appendPose(&out, poses[i]);
    out += '\n';
  }
  return out;
}

std::string kittiText(const std::vector<Eigen::Isometry3d>& poses) {
  std::string out;
  for (const auto& pose : poses) {
    const Eigen::Matrix4d m = pose.matrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) appendf(&out, r + c == 0 ? "%.17g" : " %.17g", m(r, c));
    }
    out += '\n';
  }
  return out;
}

std::string timesText(const std::vector<std::int64_t>& stamps) {
  std::string out;
  for (const std::int64_t stamp : stamps) {
    appendStamp(&out, stamp);
    out += '\n';
  }
  return out;
}

/// frames.txt: per robot `id joined` and T_map<-odom's rows 0-2.
std::string framesText(const std::vector<MapRobot>& robots) {
  std::string out = "# robot joined T_map<-odom (rows 0-2 of the 4x4, row-major); joined 0: in its own group's frame\n";
  for (const MapRobot& robot : robots) {
    out += robot.id + (robot.joined ? " 1" : " 0");
    const Eigen::Matrix4d m = robot.frame.matrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) appendNumber(&out, m(r, c));
    }
    out += '\n';
  }
  return out;
}

template <typename T>
std::vector<T> pick(const std::vector<T>& all, const std::vector<std::size_t>& indices) {
  std::vector<T> out;
  out.reserve(indices.size());
  for (const std::size_t i : indices) out.push_back(all[i]);
  return out;
}

std::string g2oText(const MapFiles& files) {
  std::string out;
  for (std::size_t i = 0; i < files.corrected.size(); ++i) {
    appendf(&out, "VERTEX_SE3:QUAT %zu", i);
    appendPose(&out, files.corrected[i]);
    out += '\n';
  }
  if (!files.corrected.empty()) {  // the graph's gauges
    out += "FIX";
    if (files.held.empty()) out += " 0";
    for (const std::size_t i : files.held) appendf(&out, " %zu", i);
    out += '\n';
  }
  for (const PoseGraphFactor& f : files.factors) {
    appendf(&out, "EDGE_SE3:QUAT %zu %zu", f.a, f.b);
    appendPose(&out, f.measurement);
    const Matrix6d information = g2oInformation(f.measurement, f.covariance);
    for (int r = 0; r < 6; ++r) {
      for (int c = r; c < 6; ++c) appendNumber(&out, information(r, c));
    }
    out += '\n';
  }
  return out;
}

/// PCL's own PCD header for `cloud`, for binary data.
std::string pcdHeader(const pcl::PointCloud<pcl::PointXYZ>& cloud) {
  return pcl::PCDWriter::generateHeader(cloud) + "DATA binary\n";
}

/// Writes the cloud's x y z as float32 (the host's byte order, as PCL writes binary PCD).
bool writeCloud(AtomicFileWriter* file, const pcl::PointCloud<pcl::PointXYZ>& cloud, std::string* error) {
  const std::string header = pcdHeader(cloud);
  if (!file->write(header.data(), header.size(), error)) return false;
  std::vector<float> block;
  constexpr std::size_t kPointsPerBlock = 1 << 16;
  for (std::size_t begin = 0; begin < cloud.size(); begin += kPointsPerBlock) {
    const std::size_t end = std::min(cloud.size(), begin + kPointsPerBlock);
    block.clear();
    for (std::size_t i = begin; i < end; ++i) {
      block.push_back(cloud[i].x);
      block.push_back(cloud[i].y);
      block.push_back(cloud[i].z);
    }
    if (!file->write(block.data(), block.size() * sizeof(float), error)) return false;
  }
  return true;
}

bool refuse(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

/// Why `files` cannot be written as they are, or "".
std::string inconsistency(const MapFiles& files) {
  const std::size_t n = files.stamps_ns.size();
  if (files.corrected.size() != n || files.odometry.size() != n) {
    return "the stamps (" + std::to_string(n) + "), corrected poses (" + std::to_string(files.corrected.size()) +
           ") and odometry poses (" + std::to_string(files.odometry.size()) + ") differ in number";
  }
  const auto increasing = [&](const std::vector<std::size_t>& keyframes, const std::string& whose) -> std::string {
    for (std::size_t k = 0; k < keyframes.size(); ++k) {
      if (keyframes[k] >= n)
        return whose + "keyframe " + std::to_string(keyframes[k]) + " is beyond the " + std::to_string(n) +
               " there are";
      if (k > 0 && files.stamps_ns[keyframes[k]] <= files.stamps_ns[keyframes[k - 1]]) {
        return whose + "keyframe stamps do not increase at keyframe " + std::to_string(keyframes[k]);
      }
    }
    return "";
  };
  if (files.robots.empty()) {
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    const std::string why = increasing(all, "");
    if (!why.empty()) return why;
  }
  for (const MapRobot& robot : files.robots) {
    if (!validRobotId(robot.id)) return "the robot id \"" + robot.id + "\" is not " + kRobotIdRule;
    const std::string why = increasing(robot.keyframes, "robot " + robot.id + ": ");
    if (!why.empty()) return why;
  }
  for (const std::size_t i : files.held) {
    if (i >= n) return "a held keyframe " + std::to_string(i) + " is beyond the " + std::to_string(n) + " there are";
  }
  for (const PoseGraphFactor& f : files.factors) {
    if (f.a >= n || f.b >= n) {
      return "a factor " + std::to_string(f.a) + " -> " + std::to_string(f.b) + " names a keyframe beyond the " +
             std::to_string(n) + " there are";
    }
  }
  return "";
}

/// The directory, created (one level) when missing.
bool prepareDirectory(const std::string& directory, std::string* error) {
  if (directory.empty()) return refuse(error, "no directory given");
  struct stat st;
  if (::stat(directory.c_str(), &st) == 0) {
    return S_ISDIR(st.st_mode) || refuse(error, "cannot write the map into " + directory + ": not a directory");
  }
  if (::mkdir(directory.c_str(), 0755) != 0 && errno != EEXIST) {
    return refuse(error, "cannot create the directory " + directory + ": " + std::strerror(errno));
  }
  return true;
}

std::string sizeText(std::uint64_t bytes) {
  char buffer[32];
  if (bytes < 10000) {
    std::snprintf(buffer, sizeof(buffer), "%" PRIu64 " B", bytes);
  } else if (bytes < 10000000) {
    std::snprintf(buffer, sizeof(buffer), "%.1f kB", bytes / 1e3);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.1f MB", bytes / 1e6);
  }
  return buffer;
}

}  // namespace

Matrix6d g2oInformation(const Eigen::Isometry3d& measurement, const Matrix6d& covariance) {
  Matrix6d information = covariance.ldlt().solve(Matrix6d::Identity());
  information = 0.5 * (information + information.transpose());
  Matrix6d k = Matrix6d::Zero();
  k.topLeftCorner<3, 3>() = measurement.linear();
  k.bottomRightCorner<3, 3>() = 2.0 * Eigen::Matrix3d::Identity();
  const Matrix6d converted = k.transpose() * information * k;
  return 0.5 * (converted + converted.transpose());
}

MapFiles mapFilesOf(const PoseGraph& graph, const std::vector<std::int64_t>& stamps_ns,
                    const std::vector<std::string>& robots) {
  MapFiles files;
  files.stamps_ns = stamps_ns;
  files.corrected = graph.poses();
  files.odometry.reserve(graph.size());
  for (std::size_t i = 0; i < graph.size(); ++i) files.odometry.push_back(graph.odometryPose(i));
  files.factors = graph.factors();
  files.held = graph.held();
  for (std::size_t c = 0; c < robots.size(); ++c) {
    MapRobot robot;
    robot.id = robots[c];
    robot.keyframes = graph.chainKeyframes(c);
    robot.frame = graph.frame(c);
    robot.joined = graph.joined(c);
    files.robots.push_back(std::move(robot));
  }
  return files;
}

std::vector<std::string> mapFileNames(bool with_cloud, const std::vector<std::string>& robots) {
  std::vector<std::string> names;
  if (with_cloud) names.push_back(kCloudFile);
  const std::vector<std::string> trajectories = {"corrected_tum", "odometry_tum", "corrected_kitti", "times"};
  if (robots.empty()) {
    for (const std::string& name : trajectories) names.push_back(name + ".txt");
  }
  for (const std::string& robot : robots) {
    for (const std::string& name : trajectories) names.push_back(name + "_" + robot + ".txt");
  }
  if (!robots.empty()) names.push_back("frames.txt");
  names.push_back("pose_graph.g2o");
  return names;
}

std::string MapFilesReport::summary() const {
  std::string out = directory + ":";
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::size_t slash = files[i].rfind('/');
    const std::string name = slash == std::string::npos ? files[i] : files[i].substr(slash + 1);
    out += (i == 0 ? " " : ", ") + name + " " + sizeText(bytes[i]);
    if (name == kCloudFile) {
      char buffer[96];
      std::snprintf(buffer, sizeof(buffer), " (%zu points, voxel-filtered at %.2f m)", points, voxel);
      out += buffer;
    }
  }
  out += "; " + std::to_string(keyframes) + " keyframes, " + std::to_string(loops) + " loops";
  if (!removed_stale_cloud.empty()) out += "; removed the older " + std::string(kCloudFile) + " (no map in this save)";
  return out;
}

namespace {

/// writeMapFiles' work; *done gets what was written (and removed) as it goes.
bool writeAll(const std::string& directory, const MapFiles& files, MapFilesReport* done, std::string* error) {
  const std::string prefix = directory.back() == '/' ? directory : directory + "/";
  // The leftovers of every file a save may write, map.pcd's too when this save writes none.
  std::vector<std::string> robot_ids;
  for (const MapRobot& robot : files.robots) robot_ids.push_back(robot.id);
  for (const std::string& name : mapFileNames(true, robot_ids)) {
    for (AbandonedFile& file : removeAbandonedTemporaries(prefix + name)) done->abandoned.push_back(std::move(file));
  }
  for (AbandonedFile& file : removeAbandonedSwaps(directory)) done->abandoned.push_back(std::move(file));
  // Each trajectory file's text: the whole graph's for one robot, each robot's own with robots.
  std::map<std::string, std::string> texts;
  const auto trajectories = [&](const std::string& suffix, const std::vector<std::size_t>* keyframes) {
    const auto stamps = keyframes ? pick(files.stamps_ns, *keyframes) : files.stamps_ns;
    const auto corrected = keyframes ? pick(files.corrected, *keyframes) : files.corrected;
    texts["corrected_tum" + suffix] = tumText(stamps, corrected);
    texts["odometry_tum" + suffix] = tumText(stamps, keyframes ? pick(files.odometry, *keyframes) : files.odometry);
    texts["corrected_kitti" + suffix] = kittiText(corrected);
    texts["times" + suffix] = timesText(stamps);
  };
  if (files.robots.empty()) trajectories(".txt", nullptr);
  for (const MapRobot& robot : files.robots) trajectories("_" + robot.id + ".txt", &robot.keyframes);
  if (!files.robots.empty()) texts["frames.txt"] = framesText(files.robots);
  texts["pose_graph.g2o"] = g2oText(files);
  // The new set goes into a directory beside this one and takes its place in one step (map_set.h); where
  // that cannot be had (a directory holding subdirectories, no room beside it, no hard links), each file
  // is still replaced whole, after all of them are written.
  const std::vector<std::string> every_name = mapFileNames(true, robot_ids);
  DirectorySwap swap;
  std::string no_swap;
  const bool as_set = swap.open(directory, std::set<std::string>(every_name.begin(), every_name.end()), &no_swap);
  const std::string write_prefix = as_set ? swap.staging() + "/" : prefix;
  const std::string stale = prefix + kCloudFile;
  const bool had_cloud = ::access(stale.c_str(), F_OK) == 0;
  std::vector<std::unique_ptr<AtomicFileWriter>> writers;
  for (const std::string& name : mapFileNames(files.has_cloud, robot_ids)) {
    const std::string path = prefix + name;
    writers.emplace_back(new AtomicFileWriter);
    AtomicFileWriter* file = writers.back().get();
    if (!file->open(write_prefix + name, error)) return false;  // the writers made so far remove theirs
    if (name == kCloudFile) {
      if (!writeCloud(file, files.cloud, error)) return false;
      done->bytes.push_back(pcdHeader(files.cloud).size() + files.cloud.size() * 3 * sizeof(float));
    } else {
      const std::string& text = texts[name];
      if (!file->write(text.data(), text.size(), error)) return false;
      done->bytes.push_back(text.size());
    }
    done->files.push_back(path);
  }
  // Everything is in temporary files: now the renames (each flushed first), then the swap.
  for (auto& file : writers) {
    if (!file->commit(error)) return false;
  }
  if (as_set && !swap.commit(error)) return false;
  // An older map.pcd would sit beside a trajectory it does not match (a swap left it behind already).
  if (!files.has_cloud && had_cloud) {
    const bool gone = (as_set && swap.exchanged()) || ::unlink(stale.c_str()) == 0;
    if (gone) done->removed_stale_cloud = stale;
  }
  return true;
}

}  // namespace

bool writeMapFiles(const std::string& directory, const MapFiles& files, MapFilesReport* report, std::string* error) {
  MapFilesReport done;
  done.directory = directory;
  if (report) *report = done;
  const std::string why = inconsistency(files);
  if (!why.empty()) return refuse(error, "map not saved: " + why);
  if (!prepareDirectory(directory, error)) return false;
  done.keyframes = files.stamps_ns.size();
  for (const auto& f : files.factors) done.loops += f.loop ? 1 : 0;
  done.points = files.has_cloud ? files.cloud.size() : 0;
  done.voxel = files.voxel;
  if (!writeAll(directory, files, &done, error)) {
    if (report) report->abandoned = std::move(done.abandoned);
    return false;
  }
  if (report) *report = std::move(done);
  return true;
}

}  // namespace scan_context_loop
