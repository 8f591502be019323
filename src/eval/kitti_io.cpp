#include "scan_context_loop/eval/kitti_io.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace scan_context_loop {
namespace kitti {

namespace {

bool fail(std::string* error, const std::string& text) {
  if (error) *error = text;
  return false;
}

/// True when nothing but white space is left in `in`.
bool onlySpaceLeft(std::istream& in) {
  in >> std::ws;
  return in.eof();
}

}  // namespace

bool parsePoseRow(const std::string& line, Eigen::Isometry3d* out) {
  std::istringstream in(line);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (!(in >> m(r, c))) return false;
    }
  }
  if (!m.allFinite() || !onlySpaceLeft(in)) return false;
  out->matrix() = m;
  return true;
}

bool readScan(const std::string& path, std::vector<float>* buffer, PointView* view, std::string* error) {
  *view = PointView();
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return fail(error, "cannot open " + path);
  const std::streamsize bytes = in.tellg();
  if (bytes < 0 || bytes % 16 != 0) {
    return fail(error, path + ": size " + std::to_string(bytes) + " is not a multiple of 16 bytes");
  }
  in.seekg(0);
  buffer->resize(static_cast<std::size_t>(bytes) / sizeof(float));
  if (!in.read(reinterpret_cast<char*>(buffer->data()), bytes)) return fail(error, "cannot read " + path);
  view->data = reinterpret_cast<const std::uint8_t*>(buffer->data());
  view->count = buffer->size() / 4;
  view->stride = 4 * sizeof(float);
  return true;
}

bool readScan(const std::string& path, pcl::PointCloud<pcl::PointXYZI>* cloud, std::string* error) {
  std::vector<float> raw;
  PointView view;
  if (!readScan(path, &raw, &view, error)) return false;
  const std::size_t n = raw.size() / 4;
  cloud->clear();
  cloud->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    pcl::PointXYZI& p = (*cloud)[i];
    p.x = raw[4 * i];
    p.y = raw[4 * i + 1];
    p.z = raw[4 * i + 2];
    p.intensity = raw[4 * i + 3];
  }
  cloud->width = static_cast<std::uint32_t>(n);
  cloud->height = 1;
  cloud->is_dense = false;
  return true;
}

bool writeScan(const std::string& path, const pcl::PointCloud<pcl::PointXYZI>& cloud, std::string* error) {
  std::vector<float> raw;
  raw.reserve(cloud.size() * 4);
  for (const auto& p : cloud) {
    raw.insert(raw.end(), {p.x, p.y, p.z, p.intensity});
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return fail(error, "cannot create " + path);
  out.write(reinterpret_cast<const char*>(raw.data()), static_cast<std::streamsize>(raw.size() * sizeof(float)));
  return out.good() || fail(error, "cannot write " + path);
}

bool readPoses(const std::string& path, std::vector<Eigen::Isometry3d>* poses, std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  poses->clear();
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    Eigen::Isometry3d pose;
    if (!parsePoseRow(line, &pose)) {
      return fail(error, path + ":" + std::to_string(number) + ": expected exactly 12 finite numbers");
    }
    poses->push_back(pose);
  }
  return true;
}

bool writePoses(const std::string& path, const std::vector<Eigen::Isometry3d>& poses, std::string* error) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) return fail(error, "cannot create " + path);
  out << std::setprecision(9) << std::scientific;
  for (const auto& pose : poses) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) out << pose.matrix()(r, c) << (r == 2 && c == 3 ? '\n' : ' ');
    }
  }
  return out.good() || fail(error, "cannot write " + path);
}

bool readCalibTr(const std::string& path, Eigen::Isometry3d* tr, std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("Tr:", 0) != 0) continue;
    if (!parsePoseRow(line.substr(3), tr)) return fail(error, path + ": malformed Tr: line");
    return true;
  }
  return fail(error, path + ": no Tr: line");
}

bool readTimes(const std::string& path, std::vector<double>* times, std::string* error) {
  std::ifstream in(path);
  if (!in) return fail(error, "cannot open " + path);
  times->clear();
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream field(line);
    double t;
    if (!(field >> t) || !std::isfinite(t) || !onlySpaceLeft(field)) {
      return fail(error, path + ":" + std::to_string(number) + ": expected one finite number");
    }
    times->push_back(t);
  }
  return true;
}

std::vector<Eigen::Isometry3d> lidarPoses(const std::vector<Eigen::Isometry3d>& camera_poses,
                                          const Eigen::Isometry3d& tr) {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(camera_poses.size());
  const Eigen::Isometry3d tr_inv = tr.inverse();
  for (const auto& pose : camera_poses) out.push_back(tr_inv * pose * tr);
  return out;
}

std::string scanPath(const std::string& sequence_dir, int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.bin", frame);
  return sequence_dir + "/velodyne/" + name;
}

}  // namespace kitti
}  // namespace scan_context_loop
