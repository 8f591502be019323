// What a team's keyframes cost a robot (doc/multi_robot.md, memory): ROBOTS robots of KEYFRAMES keyframes
// each, their descriptors synthetic (real KITTI scans' grids, bench_data.h). The first robot's keyframes sit
// in a LoopDetector as the node holds its own; the others' reach a TeamMatcher as records
// (keyframeRecord), as the node's team worker takes them. Each side is measured in a process of its own,
// forked once everything is made (so neither reuses the other's freed memory): the growth of its resident
// memory per keyframe, and the ratio foreign / own.
// Usage: scan_context_bench_team [DATA_DIR [KEYFRAMES [ROBOTS]]]  (--help lists the arguments)
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_data.h"
#include "cli.h"
#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/team_matcher.h"

namespace scl = scan_context_loop;

namespace {

/// Resident memory of this process [bytes].
double residentBytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  statm >> pages >> resident;
  return resident * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

/// Runs `measure` in a forked process and reads the two numbers it writes back (bytes a keyframe,
/// accounted bytes a keyframe); false when the child fails.
template <typename Measure>
bool inChild(Measure measure, double* per_keyframe, double* accounted) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return false;
  const pid_t child = ::fork();
  if (child < 0) return false;
  if (child == 0) {
    ::close(pipe_fds[0]);
    double out[2] = {0.0, 0.0};
    const bool ok = measure(&out[0], &out[1]);
    if (ok && ::write(pipe_fds[1], out, sizeof(out)) != sizeof(out)) ::_exit(2);
    ::_exit(ok ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  double in[2] = {0.0, 0.0};
  const bool read = ::read(pipe_fds[0], in, sizeof(in)) == sizeof(in);
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  *per_keyframe = in[0];
  *accounted = in[1];
  return read && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = "../shared/data";
  std::size_t keyframes = 20000, robots = 3;
  scl::cli::Parser cli("scan_context_bench_team",
                       "Prints, as Markdown, the resident memory a robot's own keyframe takes in its database and a "
                       "keyframe of another robot of its team takes as a record in its team matcher, each "
                       "measured in a forked process, and their ratio.");
  const auto count = [](std::size_t* n) {
    return [n](const std::string& v, std::string* error) {
      if (scl::cli::toUnsigned(v, n) && *n > 0) return true;
      *error = "must be a positive whole number";
      return false;
    };
  };
  cli.positional("DATA_DIR", "the real data, holding kitti/00 and kitti/08 (default ../shared/data)", &data, false)
      .positional("KEYFRAMES", "keyframes per robot (default 20000)", count(&keyframes), false)
      .positional("ROBOTS", "robots in the team, this one included (default 3)", count(&robots), false);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  if (robots < 2) return cli.fail("a team has two robots at least");

  const scl::Config config;
  std::vector<pcl::PointCloud<pcl::PointXYZI>> raw;
  if (!scl::bench::readScans(data, &raw)) return 1;
  std::vector<scl::HeightGrid> grids;
  for (const auto& c : raw) grids.push_back(scl::makeHeightGrid(scl::viewOf(c), config));

  // The others' records made before either measurement and kept alive, so that the children find no
  // freed memory to reuse.
  std::vector<std::vector<std::uint8_t>> records;
  std::vector<scl::TeamKeyframeId> ids;
  std::vector<std::unique_ptr<scl::LoopDetector>> others;
  for (std::size_t r = 1; r < robots; ++r) {
    others.push_back(std::make_unique<scl::LoopDetector>(config));
    std::string error;
    if (!others.back()->appendSessions(
            scl::bench::makeKeyframes(keyframes, grids, {}, config, static_cast<std::uint32_t>(r + 1)), &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 1;
    }
    for (std::size_t k = 0; k < keyframes; ++k) {
      records.push_back(scl::keyframeRecord(*others.back(), k));
      ids.push_back({"robot" + std::to_string(r + 1), 1, static_cast<std::uint32_t>(k)});
    }
  }

  double own_bytes = 0.0, own_accounted = 0.0, foreign_bytes = 0.0, foreign_accounted = 0.0;
  const bool own_ok = inChild(
      [&](double* per_keyframe, double* accounted) {
        // Made here, as the node makes its own keyframes, a thousand at a time (what each batch leaves
        // behind on the heap is reused by the next).
        scl::LoopDetector detector(config);
        const double before = residentBytes();
        std::string error;
        for (std::size_t made = 0; made < keyframes; made += 1000) {
          const std::size_t batch = std::min<std::size_t>(1000, keyframes - made);
          const auto seed = static_cast<std::uint32_t>(1000 + made);
          if (!detector.appendSessions(scl::bench::makeKeyframes(batch, grids, {}, config, seed), &error)) return false;
        }
        *per_keyframe = (residentBytes() - before) / static_cast<double>(keyframes);
        *accounted = static_cast<double>(detector.database().bytesPerKeyframe());
        return true;
      },
      &own_bytes, &own_accounted);
  const bool foreign_ok = inChild(
      [&](double* per_keyframe, double* accounted) {
        scl::TeamMatcher matcher(config);
        const double before = residentBytes();
        for (std::size_t i = 0; i < records.size(); ++i) {
          if (matcher.add(ids[i], 0, records[i].data(), records[i].size()) != scl::TeamMatcher::Added::kAdded) {
            return false;
          }
        }
        *per_keyframe = (residentBytes() - before) / static_cast<double>(records.size());
        *accounted = static_cast<double>(matcher.recordBytes()) / static_cast<double>(records.size());
        return true;
      },
      &foreign_bytes, &foreign_accounted);
  if (!own_ok || !foreign_ok) {
    std::fprintf(stderr, "a measurement failed\n");
    return 1;
  }
  rusage usage{};
  ::getrusage(RUSAGE_CHILDREN, &usage);
  std::printf(
      "| robots | keyframes a robot | record size | own keyframe: resident (accounted) | foreign keyframe: "
      "resident (accounted) | foreign / own | peak resident, largest child |\n|---|---|---|---|---|---|---|\n");
  std::printf("| %zu | %zu | %zu B | %.0f B (%.0f B) | %.0f B (%.0f B) | %.2f | %.0f MB |\n", robots, keyframes,
              records.front().size(), own_bytes, own_accounted, foreign_bytes, foreign_accounted,
              foreign_bytes / own_bytes, usage.ru_maxrss / 1024.0);
  return 0;
}
