// Prints the core's benchmark table: descriptor time on real KITTI scans (raw and 0.4 m voxel
// downsampled), ground-plane gravity alignment time on them, pair distance time, online insert + query time at several
// database sizes, and memory. Usage: scan_context_bench [DATA_DIR [MAX_DATABASE_SIZE]]  (--help lists the arguments)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <time.h>

#include <Eigen/Geometry>
#include <pcl/filters/voxel_grid.h>
#include <unistd.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/alignment.h"
#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/gravity_alignment.h"
#include "scan_context_loop/core/verification.h"
#include "cli.h"
#include "bench_data.h"

namespace scl = scan_context_loop;
using Clock = std::chrono::steady_clock;

/// The calling thread's CPU time so far [us].
double threadCpuMicroseconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e6 + t.tv_nsec * 1e-3;
}

namespace {

struct Stats {
  double median, p99, max;
};

Stats summarise(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))]; };
  return {at(0.5), at(0.99), v.back()};
}

double microseconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

/// Times fn() `repeat` times and returns the per-call microseconds.
template <typename Fn>
std::vector<double> timeIt(int repeat, Fn fn) {
  std::vector<double> t;
  for (int i = 0; i < repeat; ++i) {
    const auto a = Clock::now();
    fn();
    t.push_back(microseconds(a, Clock::now()));
  }
  return t;
}

std::size_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = "../shared/data";
  std::size_t max_size = 100000;
  scl::cli::Parser cli(
      "scan_context_bench",
      "Prints the core's benchmark table as Markdown: descriptor time on six real KITTI scans (raw "
      "and 0.4 m voxels), gravity alignment, pair distance, online query + insert at 1k, 10k, 100k and "
      "1M keyframes (up to MAX_DATABASE_SIZE), verification, and bytes per keyframe.");
  cli.positional("DATA_DIR", "the real data, holding kitti/00 and kitti/08 (default ../shared/data)", &data, false)
      .positional(
          "MAX_DATABASE_SIZE", "largest database size for the online rows (default 100000)",
          [&max_size](const std::string& v, std::string* error) {
            std::uint64_t n = 0;
            if (scl::cli::toUnsigned(v, &n) && n > 0) {
              max_size = static_cast<std::size_t>(n);
              return true;
            }
            *error = "needs a positive integer, got '" + v + "'";
            return false;
          },
          false);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  scl::Config config;

  std::vector<pcl::PointCloud<pcl::PointXYZI>> raw, down;
  if (!scl::bench::readScans(data, &raw)) return 1;
  for (const auto& cloud : raw) {
    pcl::PointCloud<pcl::PointXYZI> filtered;
    pcl::VoxelGrid<pcl::PointXYZI> voxel;
    voxel.setLeafSize(0.4f, 0.4f, 0.4f);
    voxel.setInputCloud(cloud.makeShared());
    voxel.filter(filtered);
    down.push_back(std::move(filtered));
  }

  std::printf("| measurement | points / size | median | p99 | max |\n|---|---|---|---|---|\n");
  const auto row = [](const char* what, const std::string& size, const Stats& s, const char* unit) {
    std::printf("| %s | %s | %.3f %s | %.3f %s | %.3f %s |\n", what, size.c_str(), s.median, unit, s.p99, unit, s.max,
                unit);
  };
  for (int pass = 0; pass < 2; ++pass) {
    const auto& clouds = pass == 0 ? raw : down;
    std::vector<double> t;
    std::size_t points = 0;
    for (const auto& c : clouds) {
      points += c.size();
      const auto v = timeIt(100, [&] {
        volatile int n = scl::makeDescriptor(c, config).occupied_columns;
        (void)n;
      });
      t.insert(t.end(), v.begin(), v.end());
    }
    for (double& x : t) x /= 1000.0;
    row(pass == 0 ? "descriptor, raw scan" : "descriptor, 0.4 m voxels", std::to_string(points / clouds.size()),
        summarise(t), "ms");
  }

  // Gravity-aligning from the ground plane: as is, and with 20 degrees of roll and pitch (the ground then
  // rises across the range band, which changes which points the fit considers).
  const float twenty_degrees = static_cast<float>(20.0 * M_PI / 180.0);
  const Eigen::Matrix3f tilt = (Eigen::AngleAxisf(twenty_degrees, Eigen::Vector3f::UnitY()) *
                                Eigen::AngleAxisf(twenty_degrees, Eigen::Vector3f::UnitX()))
                                   .toRotationMatrix();
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<double> t;
    std::size_t points = 0;
    for (const auto& c : raw) {
      const pcl::PointCloud<pcl::PointXYZ> tilted = scl::rotatedCloud(scl::viewOf(c), tilt.transpose());
      const scl::PointView view = pass == 0 ? scl::viewOf(c) : scl::viewOf(tilted);
      points += view.count;
      const auto v = timeIt(100, [&] {
        Eigen::Matrix3d level;
        volatile bool ok = scl::gravityAlignmentFromGround(view, scl::GroundFitOptions(), &level, nullptr);
        (void)ok;
      });
      t.insert(t.end(), v.begin(), v.end());
    }
    for (double& x : t) x /= 1000.0;
    row(pass == 0 ? "ground-plane gravity alignment, raw scan"
                  : "ground-plane gravity alignment, raw scan tilted 20 deg roll + pitch",
        std::to_string(points / raw.size()), summarise(t), "ms");
  }

  // Verification: the registration data every keyframe prepares once, and one candidate's
  // verification against a query (its index built, the coarse search over three yaw hypotheses, GICP,
  // the acceptance test), on the real pairs: the reverse revisit, consecutive scans, 58 m apart.
  const scl::VerificationConfig verification = config.verification;
  std::vector<scl::VoxelCloud> prepared;
  {
    std::vector<double> t;
    std::size_t points = 0;
    for (const auto& c : raw) {
      points += c.size();
      const auto v = timeIt(50, [&] {
        volatile std::size_t n = scl::prepareCloud(scl::viewOf(c), verification).size();
        (void)n;
      });
      t.insert(t.end(), v.begin(), v.end());
      prepared.push_back(scl::prepareCloud(scl::viewOf(c), verification));
    }
    for (double& x : t) x /= 1000.0;
    row("verification data (1 m voxels, 40 m), raw scan", std::to_string(points / raw.size()), summarise(t), "ms");
    std::vector<double> u;
    const std::vector<std::pair<int, int>> pairs = {{4, 5}, {5, 4}, {0, 1}, {2, 3}, {0, 2}, {2, 0}};
    for (const auto& p : pairs) {
      const double yaw =
          scl::align(scl::makeDescriptor(raw[p.first], config), scl::makeDescriptor(raw[p.second], config), config).yaw;
      const std::vector<Eigen::Isometry3d> guesses = {scl::priorPose(yaw), scl::priorPose(yaw + 1.2),
                                                      scl::priorPose(yaw - 2.0)};
      const auto v = timeIt(30, [&] {
        scl::Verifier verifier(verification);
        verifier.setQuery(prepared[p.first]);
        volatile bool ok = verifier.verify(prepared[p.second], guesses).accepted;
        (void)ok;
      });
      u.insert(u.end(), v.begin(), v.end());
    }
    for (double& x : u) x /= 1000.0;
    row("verification of one candidate, 3 yaw hypotheses (6 real pairs)", "~8k voxels", summarise(u), "ms");
  }

  std::vector<scl::Descriptor> descriptors;
  std::vector<scl::HeightGrid> grids;
  for (const auto& c : raw) {
    grids.push_back(scl::makeHeightGrid(c, config));
    descriptors.push_back(scl::makeDescriptor(grids.back(), config));
  }
  std::vector<double> pair;
  for (int i = 0; i < 20000; ++i) {
    const auto& a = descriptors[i % descriptors.size()];
    const auto& b = descriptors[(i / descriptors.size()) % descriptors.size()];
    const auto t0 = Clock::now();
    volatile double d = scl::align(a, b, config).distance;
    (void)d;
    pair.push_back(microseconds(t0, Clock::now()));
  }
  row("pair distance (sector-key shift + 7 columns + refinement)", "20 x 60", summarise(pair), "us");

  // Online: query then insert, one keyframe at a time, as the node does.
  scl::Database db(config);
  scl::bench::GridStream stream(grids, 7);
  // Each step's time [us], its start on the monotonic clock [s] and the thread's CPU time over it [us]:
  // a step whose CPU time is well below its time waited (for another thread, the machine).
  std::vector<double> step, started, cpu;
  std::size_t blind = 0;
  const std::size_t rss_before = residentBytes();
  const std::vector<std::size_t> marks = {1000, 10000, 100000, 1000000};
  for (std::size_t n = 0; n < max_size; ++n) {
    scl::KeyframeInfo info;
    info.stamp = 0.1 * n;
    scl::Descriptor d = scl::makeDescriptor(stream.next(), config);
    const double cpu0 = threadCpuMicroseconds();
    const auto t0 = Clock::now();
    const scl::QueryResult r = db.query(d, info);
    db.add(info, std::move(d));
    step.push_back(microseconds(t0, Clock::now()));
    cpu.push_back(threadCpuMicroseconds() - cpu0);
    started.push_back(std::chrono::duration<double>(t0.time_since_epoch()).count());
    // Every keyframe outside the exclusion window must be searchable.
    blind += r.eligible - std::min(r.eligible, db.indexedCount());
    if (std::find(marks.begin(), marks.end(), n + 1) != marks.end()) {
      // The last 1,000 steps up to this size.
      std::vector<double> window(step.end() - std::min<std::size_t>(1000, step.size()), step.end());
      for (double& x : window) x /= 1000.0;
      row("online query + insert", std::to_string(n + 1) + " keyframes", summarise(window), "ms");
    }
  }
  const std::size_t rss_after = residentBytes();
  // Every step counts, the first ones included; the kd-tree is rebuilt on the database's own thread,
  // so a step pays a rebuild only when it has to wait for one (Database::Tree in database.cpp).
  const auto worst = std::max_element(step.begin(), step.end());
  std::printf("\nworst single step over the whole run: %.3f ms (keyframe %zu)\n", *worst / 1000.0,
              static_cast<std::size_t>(worst - step.begin()) + 1);
  std::vector<std::size_t> order(step.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const std::size_t shown = std::min<std::size_t>(5, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<long>(shown), order.end(),
                    [&step](std::size_t a, std::size_t b) { return step[a] > step[b]; });
  std::printf("the %zu slowest steps:", shown);
  for (std::size_t i = 0; i < shown; ++i) {
    std::printf("%s %.3f ms (keyframe %zu, at %.6f s, CPU %.3f ms)", i ? "," : "", step[order[i]] / 1000.0,
                order[i] + 1, started[order[i]], cpu[order[i]] / 1000.0);
  }
  std::printf("\nkeyframes eligible but not searchable at query time: %zu\n", blind);
  const scl::Database::IndexBuilds builds = db.indexBuilds();
  std::printf("kd-tree builds: %zu on the database's thread (%zu waited for), %zu on the caller's\n", builds.background,
              builds.waited, builds.at_once);
  std::printf("bytes per keyframe: %zu accounted (descriptor, keys, record, tree); %.0f measured RSS growth\n",
              db.bytesPerKeyframe(), static_cast<double>(rss_after - rss_before) / db.size());
  return 0;
}
