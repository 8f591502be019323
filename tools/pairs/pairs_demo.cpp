// Scores the real KITTI scan pairs in ../shared/data against their ground truth: descriptor distance,
// match decision and yaw prior beside the true yaw. Usage: scan_context_pairs [DATA_DIR]
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/descriptor.h"
#include "scan_context_loop/core/detector.h"
#include "scan_context_loop/eval/kitti_io.h"
#include "cli.h"

namespace scl = scan_context_loop;

namespace {

struct Pair {
  const char* sequence;
  int query;
  int match;
  const char* note;
};

bool truthYaw(const std::string& dir, int query, int match, double* yaw, double* distance) {
  std::vector<Eigen::Isometry3d> cam;
  Eigen::Isometry3d tr;
  std::string error;
  if (!scl::kitti::readPoses(dir + "/poses.txt", &cam, &error) ||
      !scl::kitti::readCalibTr(dir + "/calib.txt", &tr, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return false;
  }
  const auto lidar = scl::kitti::lidarPoses(cam, tr);
  const Eigen::Isometry3d rel = lidar.at(query).inverse() * lidar.at(match);
  *yaw = std::atan2(rel(1, 0), rel(0, 0));
  *distance = rel.translation().norm();
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = "../shared/data";
  scl::cli::Parser cli("scan_context_pairs",
                       "Scores the real KITTI scan pairs against their ground truth with the default configuration: "
                       "descriptor distance (the best over the lateral viewpoints), match decision, and the yaw "
                       "prior beside the true yaw.");
  cli.positional("DATA_DIR", "the real data, holding kitti/00 and kitti/08 (default ../shared/data)", &data, false);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  scl::Config config;
  const std::vector<Pair> pairs = {
      {"00", 94, 95, "consecutive frames, same place"},
      {"00", 198, 199, "consecutive frames, same place"},
      {"00", 94, 198, "58 m apart, different places"},
      {"08", 720, 1500, "real reverse-direction revisit"},
  };
  std::printf(
      "threshold %.3f, %d rings x %d sectors, max radius %.0f m, ring key %s, lateral viewpoints every "
      "%.1f m (%d a side); view = the viewpoint of the best distance\n\n",
      config.distance_threshold, config.num_rings, config.num_sectors, config.max_radius,
      scl::ringKeyTypeName(config.ring_key), config.lateral_offset_step, config.lateral_offset_count);
  std::printf("%-4s %6s %6s  %8s  %6s  %-5s  %9s  %9s  %7s  %s\n", "seq", "query", "match", "distance", "view", "match",
              "yaw [deg]", "true yaw", "apart", "");
  int wrong = 0;
  for (const auto& pair : pairs) {
    const std::string dir = data + "/kitti/" + pair.sequence;
    pcl::PointCloud<pcl::PointXYZI> a, b;
    std::string error;
    if (!scl::kitti::readScan(scl::kitti::scanPath(dir, pair.query), &a, &error) ||
        !scl::kitti::readScan(scl::kitti::scanPath(dir, pair.match), &b, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 1;
    }
    // From the sensor and from each lateral viewpoint (Config::lateral_offset_step), as the detector does.
    const scl::Descriptor match_descriptor = scl::makeDescriptor(b, config);
    scl::Alignment al = scl::align(scl::makeDescriptor(a, config), match_descriptor, config);
    float view = 0.0f;
    for (const Eigen::Vector2f& v : scl::lateralViewpoints(config)) {
      const scl::Alignment other = scl::align(scl::makeDescriptor(a, config, v), match_descriptor, config);
      if (other.distance < al.distance) {
        al = other;
        view = v.y();
      }
    }
    double true_yaw = 0.0, apart = 0.0;
    if (!truthYaw(dir, pair.query, pair.match, &true_yaw, &apart)) return 1;
    const bool match = al.distance < config.distance_threshold;
    const bool should = apart < 5.0;
    wrong += match != should;
    std::printf("%-4s %6d %6d  %8.4f  %+5.1fm  %-5s  %9.2f  %9.2f  %5.1f m  %s\n", pair.sequence, pair.query,
                pair.match, al.distance, view, match ? "yes" : "no", al.yaw * 180.0 / M_PI, true_yaw * 180.0 / M_PI,
                apart, pair.note);
  }
  std::printf("\n%d of %zu decisions disagree with the ground truth (revisit = under 5 m apart)\n", wrong,
              pairs.size());
  return 0;
}
