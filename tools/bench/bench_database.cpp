// Times saving and loading the database file (core/database_file.h) and prints its size per keyframe:
// KEYFRAMES keyframes without registration data, and CLOUD_KEYFRAMES with it.
// The descriptors are synthetic: real KITTI scans' grids, turned, with height noise and bins that
// come and go (bench_data.h). The registration data are the six real scans' voxel clouds, in turn.
// Usage: scan_context_bench_database [DATA_DIR [KEYFRAMES [CLOUD_KEYFRAMES]]]  (--help lists the arguments)
// With --write FILE it only writes the KEYFRAMES synthetic keyframes to FILE (the 1M soak's map).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <atomic>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include <Eigen/Geometry>

#include "bench_data.h"
#include "cli.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/pcl_adapters.h"

namespace scl = scan_context_loop;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Another process's small file writes beside a save (a rosbag, a log): every 10 ms a few bytes are
/// written to a file in `directory` and renamed into place, while the save runs. The longest one [s].
class NeighbourWrites {
 public:
  explicit NeighbourWrites(const std::string& directory)
      : file_((fs::path(directory) / "scan_context_bench_neighbour").string()), thread_([this] { run(); }) {}
  double stop() {
    done_ = true;
    thread_.join();
    std::error_code ignored;
    fs::remove(file_, ignored);
    return longest_;
  }

 private:
  void run() {
    while (!done_) {
      const auto t0 = Clock::now();
      std::ofstream(file_ + ".tmp") << "progress\n";
      fs::rename(file_ + ".tmp", file_);
      longest_ = std::max(longest_, secondsSince(t0));
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  std::string file_;
  std::atomic<bool> done_{false};
  double longest_ = 0.0;
  std::thread thread_;
};

/// Builds a detector of `count` keyframes, saves it, loads it into a fresh detector (best of three) and
/// prints one Markdown row. Returns false on an error.
bool measure(const char* what, std::size_t count, const std::vector<scl::HeightGrid>& grids,
             const std::vector<scl::VoxelCloud>& clouds, const scl::Config& config, const std::string& path) {
  std::string error;
  double snapshot_seconds = 0.0, save_seconds = 0.0, neighbour_seconds = 0.0;
  {
    scl::LoopDetector detector(config);
    if (!detector.appendSessions(scl::bench::makeKeyframes(count, grids, clouds, config), &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return false;
    }
    scl::SaveOptions options;
    options.include_clouds = !clouds.empty();
    // What the node's worker pays (the snapshot), then what the writer's thread does.
    const auto t0 = Clock::now();
    const scl::DatabaseSnapshot snapshot(detector, options.include_clouds);
    snapshot_seconds = secondsSince(t0);
    NeighbourWrites neighbour(fs::path(path).parent_path().string());
    const auto t1 = Clock::now();
    const bool written = scl::writeDatabase(snapshot, path, false, &error);
    save_seconds = secondsSince(t1);
    neighbour_seconds = neighbour.stop();
    if (!written) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return false;
    }
  }
  // loadDatabase is readDatabaseFile then appendSessions; timed apart. The first run allocates the
  // keyframes' memory afresh (as a node starting up does); later runs may reuse the heap.
  double first_seconds = 0.0, read_seconds = 1e9, join_seconds = 1e9;
  for (int run = 0; run < 3; ++run) {
    scl::LoopDetector detector(config);
    scl::PriorSessions sessions;
    const auto t0 = Clock::now();
    if (!scl::readDatabaseFile(path, config, &sessions, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return false;
    }
    const auto t1 = Clock::now();
    if (!detector.appendSessions(std::move(sessions), &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return false;
    }
    const double read = std::chrono::duration<double>(t1 - t0).count(), join = secondsSince(t1);
    if (run == 0) first_seconds = read + join;
    if (read + join < read_seconds + join_seconds) {
      read_seconds = read;
      join_seconds = join;
    }
    if (detector.database().size() != count || detector.database().indexedCount() != count) {
      std::fprintf(stderr, "loaded %zu keyframes (%zu indexed) of %zu\n", detector.database().size(),
                   detector.database().indexedCount(), count);
      return false;
    }
  }
  const double bytes = static_cast<double>(fs::file_size(path));
  std::printf("| %s | %zu | %.1f MB | %.0f | %.1f ms | %.3f s | %.0f ms | %.3f s | %.3f s + %.3f s |\n", what, count,
              bytes / 1e6, bytes / count, snapshot_seconds * 1e3, save_seconds, neighbour_seconds * 1e3, first_seconds,
              read_seconds, join_seconds);
  return true;
}

/// Minor page faults of this process so far (the first touch of each page of new memory).
long minorFaults() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// One load into a fresh detector: readDatabaseFile (read, check, decode) and appendSessions (join and
/// kd-tree), each with its seconds and minor page faults.
struct LoadTimes {
  double read = 0.0, join = 0.0;
  long read_faults = 0, join_faults = 0;
  /// After the join: until the kd-tree built in the background was done (queries scan meanwhile) [s].
  double index_behind = 0.0;
  long peak_rss_kb = 0;
  double total() const { return read + join; }
};

/// Loads `path` once into a fresh detector and prints its LoadTimes as four numbers (--load, run in a
/// new process: nothing allocated before, as when a node starts).
int loadOnce(const std::string& path, const scl::Config& config) {
  scl::LoopDetector detector(config);
  scl::PriorSessions sessions;
  std::string error;
  const long f0 = minorFaults();
  const auto t0 = Clock::now();
  bool ok = scl::readDatabaseFile(path, config, &sessions, &error);
  const auto t1 = Clock::now();
  const long f1 = minorFaults();
  ok = ok && detector.appendSessions(std::move(sessions), &error);
  const auto t2 = Clock::now();
  const long f2 = minorFaults();
  if (!ok) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  while (!detector.database().indexBuilds().finished) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  std::printf("%.6f %.6f %ld %ld %.6f %ld\n", std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count(), f1 - f0, f2 - f1, secondsSince(t2), usage.ru_maxrss);
  return 0;
}

/// Runs this program with --load `path` in a new process `runs` times; prints the best and worst total
/// and their splits. False when a run fails.
bool loadInNewProcesses(const char* what, const std::string& path, int runs) {
  const std::string command = "'" + fs::read_symlink("/proc/self/exe").string() + "' --load '" + path + "'";
  std::vector<LoadTimes> times;
  for (int run = 0; run < runs; ++run) {
    LoadTimes t;
    FILE* pipe = ::popen(command.c_str(), "r");
    const bool read = pipe && std::fscanf(pipe, "%lf %lf %ld %ld %lf %ld", &t.read, &t.join, &t.read_faults,
                                          &t.join_faults, &t.index_behind, &t.peak_rss_kb) == 6;
    if (pipe == nullptr || ::pclose(pipe) != 0 || !read) {
      std::fprintf(stderr, "loading %s in a new process failed\n", path.c_str());
      return false;
    }
    times.push_back(t);
  }
  const auto by_total = [](const LoadTimes& a, const LoadTimes& b) { return a.total() < b.total(); };
  const LoadTimes best = *std::min_element(times.begin(), times.end(), by_total);
  const LoadTimes worst = *std::max_element(times.begin(), times.end(), by_total);
  const auto split = [](const LoadTimes& t) {
    char text[256];
    std::snprintf(text, sizeof(text), "%.3f s (%ld page faults) + %.3f s (%ld page faults) | %.3f s | %.0f MB", t.read,
                  t.read_faults, t.join, t.join_faults, t.index_behind, t.peak_rss_kb / 1024.0);
    return std::string(text);
  };
  std::printf("| %s | %.3f s | %.3f s | %s | %s |\n", what, best.total(), worst.total(), split(best).c_str(),
              split(worst).c_str());
  return true;
}

/// Writes `count` synthetic keyframes without registration data to `path` (replacing it). 0 on success.
int writeOnly(const std::string& path, std::size_t count, const std::vector<scl::HeightGrid>& grids,
              const scl::Config& config) {
  scl::LoopDetector detector(config);
  std::string error;
  const auto t0 = Clock::now();
  bool ok = detector.appendSessions(scl::bench::makeKeyframes(count, grids, {}, config), &error);
  ok = ok && scl::writeDatabase(scl::DatabaseSnapshot(detector, false), path, false, &error);
  if (!ok) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  std::printf("wrote %zu keyframes to %s (%.1f MB) in %.1f s\n", count, path.c_str(),
              static_cast<double>(fs::file_size(path)) / 1e6, secondsSince(t0));
  return 0;
}

bool positiveCount(const std::string& v, std::size_t* out, std::string* error) {
  std::uint64_t n = 0;
  if (scl::cli::toUnsigned(v, &n) && n > 0) {
    *out = static_cast<std::size_t>(n);
    return true;
  }
  *error = "needs a positive integer, got '" + v + "'";
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = "../shared/data";
  std::string directory = fs::temp_directory_path().string(), load, write;
  std::size_t keyframes = 100000, cloud_keyframes = 2000;
  scl::cli::Parser cli("scan_context_bench_database",
                       "Prints save and load time and file size per keyframe of the database file as Markdown: "
                       "KEYFRAMES synthetic keyframes (descriptors, stamps, poses) without registration data, and "
                       "CLOUD_KEYFRAMES with the real scans' registration data. Loading includes the checks and "
                       "the kd-tree build; the file is read from the page cache (written just before).");
  cli.positional("DATA_DIR", "the real data, holding kitti/00 and kitti/08 (default ../shared/data)", &data, false)
      .positional(
          "KEYFRAMES", "keyframes without registration data (default 100000)",
          [&keyframes](const std::string& v, std::string* error) { return positiveCount(v, &keyframes, error); }, false)
      .positional(
          "CLOUD_KEYFRAMES", "keyframes with registration data (default 2000)",
          [&cloud_keyframes](const std::string& v, std::string* error) {
            return positiveCount(v, &cloud_keyframes, error);
          },
          false)
      .option("--dir", "DIR", "where the files are written (and removed afterwards; default the temporary directory)",
              &directory)
      .option("--load", "FILE",
              "only load FILE once and print the seconds reading and joining took, their page faults, the seconds "
              "until the kd-tree built in the background was done, and the peak RSS [KB]",
              &load)
      .option("--write", "FILE",
              "only write the KEYFRAMES synthetic keyframes (no registration data) to FILE, as a map to load", &write);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;

  const scl::Config config;
  if (!load.empty()) return loadOnce(load, config);
  std::vector<pcl::PointCloud<pcl::PointXYZI>> raw;
  if (!scl::bench::readScans(data, &raw)) return 1;
  std::vector<scl::HeightGrid> grids;
  std::vector<scl::VoxelCloud> clouds;
  for (const auto& c : raw) {
    grids.push_back(scl::makeHeightGrid(scl::viewOf(c), config));
    clouds.push_back(scl::prepareCloud(scl::viewOf(c), config.verification));
  }
  if (!write.empty()) return writeOnly(write, keyframes, grids, config);
  const std::string plain = (fs::path(directory) / "scan_context_bench_database.scl").string();
  const std::string with_clouds = (fs::path(directory) / "scan_context_bench_database_clouds.scl").string();
  std::printf(
      "| file | keyframes | size | bytes / keyframe | snapshot (the worker's part) | write (with fsync) | a "
      "neighbour's write and rename meanwhile, longest | load, first run | load, best of 3: read and check + "
      "join and index |\n|---|---|---|---|---|---|---|---|---|\n");
  bool ok = measure("descriptors, stamps, poses", keyframes, grids, {}, config, plain) &&
            measure("with registration data (LZ4)", cloud_keyframes, grids, clouds, config, with_clouds);
  // A new process touches every page of the keyframes' memory for the first time.
  constexpr int kFreshRuns = 3;
  if (ok) {
    std::printf(
        "\nload in a new process (nothing allocated before), %d runs; above exact_search_limit the kd-tree is "
        "built in the background after the join, queries scanning every key meanwhile:\n\n| file | best | worst "
        "| best run: read and check + join | kd-tree done after | peak RSS | worst run: read and check + join "
        "| kd-tree done after | peak RSS |\n|---|---|---|---|---|---|---|---|---|\n",
        kFreshRuns);
  }
  ok = ok && loadInNewProcesses("descriptors, stamps, poses", plain, kFreshRuns) &&
       loadInNewProcesses("with registration data (LZ4)", with_clouds, kFreshRuns);
  std::size_t voxels = 0;
  for (const auto& c : clouds) voxels += c.size();
  std::printf("\nregistration data of the real scans: %zu voxels, %zu bytes in memory per keyframe on average\n",
              voxels / clouds.size(), voxels * (sizeof(Eigen::Vector3f) + 4) / clouds.size());
  std::error_code ignored;
  fs::remove(plain, ignored);
  fs::remove(with_clouds, ignored);
  return ok ? 0 : 1;
}
