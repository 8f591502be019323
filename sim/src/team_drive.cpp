#include "scan_context_sim/team_drive.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "polyline.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {

namespace {

constexpr double kBlockX = 70.0, kBlockY = 50.0;
constexpr int kColumns = 4, kRows = 3;  // streets x = 0 .. 210, y = 0 .. 100

/// A route: grid junctions (column, row) in driving order, and the lane of each leg (1: the right-hand
/// lane, 2: the one to its right).
struct Route {
  std::vector<Eigen::Vector2i> nodes;
  std::vector<int> lanes;  // one per leg
};

const std::vector<Route>& routes() {
  using N = Eigen::Vector2i;
  static const std::vector<Route> r = {
      {{N(0, 0), N(2, 0), N(2, 1), N(0, 1), N(0, 0)}, {1, 1, 1, 1}},
      {{N(0, 0), N(3, 0), N(3, 1), N(1, 1), N(1, 2)}, {2, 1, 1, 1}},
      {{N(0, 0), N(0, 1), N(2, 1), N(2, 0), N(3, 0), N(3, 2)}, {1, 1, 1, 2, 1}},
  };
  return r;
}

/// To the right of travelling along d (unit).
Eigen::Vector2d rightOf(const Eigen::Vector2d& d) { return Eigen::Vector2d(d.y(), -d.x()); }

/// The route's lane centre line as waypoints: each leg's street shifted to the right by its lane,
/// consecutive legs meeting where their shifted lines cross.
std::vector<Eigen::Vector2d> laneWaypoints(const Route& route, bool turned, double lane) {
  std::vector<Eigen::Vector2d> nodes;
  for (const Eigen::Vector2i& n : route.nodes) {
    const Eigen::Vector2i m = turned ? Eigen::Vector2i(kColumns - 1 - n.x(), kRows - 1 - n.y()) : n;
    nodes.emplace_back(kBlockX * m.x(), kBlockY * m.y());
  }
  const std::size_t legs = nodes.size() - 1;
  std::vector<Eigen::Vector2d> dir(legs), shift(legs);
  for (std::size_t k = 0; k < legs; ++k) {
    dir[k] = (nodes[k + 1] - nodes[k]).normalized();
    shift[k] = (route.lanes[k] - 0.5) * lane * rightOf(dir[k]);
  }
  std::vector<Eigen::Vector2d> w = {nodes.front() + shift.front()};
  for (std::size_t k = 0; k + 1 < legs; ++k) {
    // Leg k's line nodes[k + 1] + shift[k] + s dir[k] meets leg k+1's nodes[k + 1] + shift[k + 1] + t dir[k + 1].
    Eigen::Matrix2d a;
    a.col(0) = dir[k];
    a.col(1) = -dir[k + 1];
    const Eigen::Vector2d st = a.colPivHouseholderQr().solve(shift[k + 1] - shift[k]);
    w.push_back(nodes[k + 1] + shift[k] + st.x() * dir[k]);
  }
  w.push_back(nodes.back() + shift.back());
  return w;
}

}  // namespace

std::string checkTeam(const TeamOptions& options) {
  if (options.robots < 1 || options.robots > kMaxTeam) {
    return "a team has 1 to " + std::to_string(kMaxTeam) + " robots, got " + std::to_string(options.robots);
  }
  if (!options.start_offsets.empty() && static_cast<int>(options.start_offsets.size()) != options.robots) {
    return "give one start offset per robot (" + std::to_string(options.robots) + "), got " +
           std::to_string(options.start_offsets.size());
  }
  for (double t : options.start_offsets) {
    if (!(t >= 0.0 && t < 1e6)) return "start offsets must be seconds in [0, 1e6)";
  }
  if (!(options.speed > 0.0 && options.speed <= 40.0)) return "the team's speed must be in (0, 40] m/s";
  if (!(options.lane >= 2.0 && options.lane <= 5.0)) return "the lane width must be in [2, 5] m";
  return "";
}

std::vector<RobotDrive> teamDrives(const TeamOptions& options) {
  std::vector<RobotDrive> team;
  const double earliest = options.start_offsets.empty()
                              ? 0.0
                              : *std::min_element(options.start_offsets.begin(), options.start_offsets.end());
  for (int r = 0; r < options.robots; ++r) {
    const Route& route = routes()[r % routes().size()];
    RobotDrive robot;
    robot.id = "robot" + std::to_string(r + 1);
    robot.drive.path = roundedPolyline(laneWaypoints(route, r >= 3, options.lane), 8.0, 0.5);
    robot.drive.times = distanceAlong(robot.drive.path);
    for (double& t : robot.drive.times) t /= options.speed;
    robot.start = options.start_offsets.empty() ? 0.0 : options.start_offsets[r] - earliest;
    team.push_back(std::move(robot));
  }
  return team;
}

std::vector<std::vector<PathPoint>> teamStreets(const std::vector<RobotDrive>& drives, double same_lane) {
  std::vector<std::vector<PathPoint>> streets;
  for (std::size_t r = 0; r < drives.size(); ++r) {
    std::vector<PathPoint> piece;
    const auto flush = [&] {
      if (piece.size() >= 2) streets.push_back(piece);
      piece.clear();
    };
    for (const PathPoint& p : drives[r].drive.path) {
      bool driven = false;
      for (std::size_t e = 0; e < r && !driven; ++e) {
        for (const PathPoint& q : drives[e].drive.path) {
          if (std::hypot(p.x - q.x, p.y - q.y) < same_lane) {
            driven = true;
            break;
          }
        }
      }
      if (driven)
        flush();
      else
        piece.push_back(p);
    }
    flush();
  }
  return streets;
}

Overlap overlapOf(const std::vector<PathPoint>& a, const std::vector<PathPoint>& b, double reach) {
  Overlap overlap;
  for (std::size_t k = 1; k < a.size(); ++k) {
    const PathPoint& p = a[k];
    double best = std::numeric_limits<double>::infinity();
    const PathPoint* nearest = nullptr;
    for (const PathPoint& q : b) {
      const double d = std::hypot(p.x - q.x, p.y - q.y);
      if (d < best) best = d, nearest = &q;
    }
    if (nearest == nullptr || best > reach) continue;
    const double step = std::hypot(p.x - a[k - 1].x, p.y - a[k - 1].y);
    const double turn = std::fabs(std::remainder(p.heading - nearest->heading, 2.0 * M_PI)) * 180.0 / M_PI;
    overlap.any += step;
    if (turn < 30.0 && best < 1.0) overlap.same_lane += step;
    if (turn < 30.0 && best >= 2.5 && best <= 4.5) overlap.other_lane += step;
    if (turn > 150.0 && best <= 4.5) overlap.reverse += step;
  }
  return overlap;
}

SequenceData robotSequence(const World& world, const RobotDrive& robot, double mount_height, double spacing,
                           const DriftOptions& drift) {
  SequenceData data;
  std::vector<Eigen::Isometry3d> world_truth;
  for (std::size_t k : keyframesEvery(robot.drive.path, spacing)) {
    world_truth.push_back(sensorPose(world, robot.drive.path[k], mount_height));
    data.times.push_back(robot.drive.times[k] - robot.drive.times.front());
  }
  if (world_truth.empty()) return data;
  data.origin = world_truth.front();
  for (const Eigen::Isometry3d& pose : world_truth) data.truth.push_back(data.origin.inverse() * pose);
  data.truth.front() = Eigen::Isometry3d::Identity();  // exactly, not to rounding
  data.odometry = driftedOdometry(data.truth, drift);
  data.world_clock = robot.start;
  return data;
}

std::uint32_t robotSeed(std::uint32_t seed, int robot) {
  return seed * 0x9E3779B1u ^ static_cast<std::uint32_t>(robot + 1) * 0x85EBCA6Bu;
}

}  // namespace sim
}  // namespace scan_context_loop
