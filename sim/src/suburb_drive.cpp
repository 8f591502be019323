#include "scan_context_sim/suburb_drive.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "polyline.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {

namespace {

/// A closed curve as points 0.5 m apart, from a polygon: resampled, then smoothed by a moving average
/// that wraps round.
std::vector<Eigen::Vector2d> closedCurve(std::vector<Eigen::Vector2d> polygon, int window) {
  polygon.push_back(polygon.front());
  std::size_t no_mark = 0;
  std::vector<Eigen::Vector2d> points = resample(polygon, 0.5, &no_mark);
  points.pop_back();  // the first point again
  const int n = static_cast<int>(points.size());
  std::vector<Eigen::Vector2d> smooth(points.size());
  for (int k = 0; k < n; ++k) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int d = -window; d <= window; ++d) sum += points[((k + d) % n + n) % n];
    smooth[k] = sum / (2 * window + 1);
  }
  return smooth;
}

/// Appends the points `from`, ..., with each moved `lane` to the left of the direction they run in.
void inLane(const std::vector<Eigen::Vector2d>& centre, double lane, std::vector<Eigen::Vector2d>* out) {
  for (std::size_t k = 0; k < centre.size(); ++k) {
    const Eigen::Vector2d d =
        centre[std::min(k + 1, centre.size() - 1)] - centre[k > 0 ? k - 1 : 0];
    const Eigen::Vector2d left = Eigen::Vector2d(-d.y(), d.x()).normalized();
    out->push_back(centre[k] + lane * left);
  }
}

}  // namespace

TimedPath suburbDrive(const SuburbOptions& options) {
  std::mt19937 rng(options.seed);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const double heading = uniform(0.0, 2.0 * M_PI);
  const Eigen::Vector2d ex(std::cos(heading), std::sin(heading)), ey(-ex.y(), ex.x());
  const double a = uniform(120.0, 150.0), b = uniform(85.0, 105.0);
  std::vector<Eigen::Vector2d> polygon;
  constexpr int kVertices = 12;
  for (int k = 0; k < kVertices; ++k) {
    const double angle = 2.0 * M_PI * (k + uniform(-0.15, 0.15)) / kVertices, scale = uniform(0.92, 1.08);
    polygon.push_back(scale * (a * std::cos(angle) * ex + b * std::sin(angle) * ey));
  }
  // Anticlockwise: the inside is to the left of the direction of travel.
  const std::vector<Eigen::Vector2d> ring = closedCurve(polygon, 30);
  const int n = static_cast<int>(ring.size());
  const auto ringPoint = [&](int k) { return ring[((k % n) + n) % n]; };
  const auto ringArc = [&](int from, int to, int step) {
    std::vector<Eigen::Vector2d> arc;
    for (int k = from; k != to; k += step) arc.push_back(ringPoint(k));
    arc.push_back(ringPoint(to));
    return arc;
  };

  // The cul-de-sacs: where they leave the ring, and their centre lines out to the turning circle and
  // round it, anticlockwise (turning left round the island, as traffic driving on the right does).
  int junction[3];
  std::vector<Eigen::Vector2d> spur_in[3], circle[3];
  for (int j = 0; j < 3; ++j) {
    junction[j] = static_cast<int>(n * (j + 0.5 + uniform(-0.08, 0.08)) / 3.0);
    const Eigen::Vector2d p = ringPoint(junction[j]);
    const Eigen::Vector2d tangent = (ringPoint(junction[j] + 1) - ringPoint(junction[j] - 1)).normalized();
    const Eigen::Vector2d inward(-tangent.y(), tangent.x());
    const double side = j < 2 ? 1.0 : -1.0;  // two into the ring, one out of it
    double h = std::atan2(side * inward.y(), side * inward.x()) + uniform(-0.25, 0.25);
    const double length = uniform(50.0, 75.0), kink_at = uniform(0.4, 0.6) * length, kink = uniform(-0.35, 0.35);
    Eigen::Vector2d q = p;
    for (double s = 0.0; s < length; s += 0.5) {
      if (s >= kink_at && s < kink_at + 0.5) h += kink;
      spur_in[j].push_back(q);
      q += 0.5 * Eigen::Vector2d(std::cos(h), std::sin(h));
    }
    constexpr double kRadius = 8.0;
    const Eigen::Vector2d centre = q + kRadius * Eigen::Vector2d(std::cos(h), std::sin(h));
    const double start = std::atan2(q.y() - centre.y(), q.x() - centre.x());
    for (double t = 0.0; t < 2.0 * M_PI; t += 0.5 / kRadius) {
      circle[j].push_back(centre + kRadius * Eigen::Vector2d(std::cos(start + t), std::sin(start + t)));
    }
  }
  const double right = -options.lane, left = options.lane;
  std::vector<Eigen::Vector2d> raw;
  const auto culDeSac = [&](int j) {
    inLane(spur_in[j], right, &raw);
    inLane(circle[j], right, &raw);
    inLane(std::vector<Eigen::Vector2d>(spur_in[j].rbegin(), spur_in[j].rend()), right, &raw);
  };
  // Lap 1: round the ring in the right-hand lane, into every cul-de-sac.
  int at = 0;
  for (int j = 0; j < 3; ++j) {
    inLane(ringArc(at, junction[j], 1), right, &raw);
    culDeSac(j);
    at = junction[j];
  }
  inLane(ringArc(at, n, 1), right, &raw);
  std::size_t pause = raw.size();
  // Lap 2: half the ring the same way one lane to the left, the second cul-de-sac again, then the whole
  // ring the other way in its right-hand lane, which is lap 1's left-hand one.
  inLane(ringArc(0, junction[1], 1), left, &raw);
  culDeSac(1);
  inLane(ringArc(junction[1], junction[1] - n, -1), right, &raw);

  return timedDrive(raw, pause, options.speed, options.pause);
}

void suburbWorld(WorldOptions* world) {
  world->style = WorldOptions::Style::kSuburb;
  world->road_half_width = 4.5;
}

}  // namespace sim
}  // namespace scan_context_loop
