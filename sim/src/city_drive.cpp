#include "scan_context_sim/city_drive.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Core>

#include "polyline.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace sim {

namespace {

constexpr double kDeg = M_PI / 180.0;

/// A street: a circular arc (or a straight line when curvature is 0) through `anchor` with `heading`
/// there, parameterised by arc length s from the anchor (negative before it).
struct Street {
  Eigen::Vector2d anchor;
  double heading = 0.0, curvature = 0.0;

  double headingAt(double s) const { return heading + curvature * s; }
  Eigen::Vector2d at(double s) const {
    if (std::fabs(curvature) < 1e-9) return anchor + s * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    const double h = headingAt(s);
    return anchor + Eigen::Vector2d(std::sin(h) - std::sin(heading), std::cos(heading) - std::cos(h)) / curvature;
  }
};

/// Arc length along `curve` where it crosses the straight street `line`, searched over [from, to].
double crossing(const Street& curve, const Street& line, double from, double to) {
  const Eigen::Vector2d normal(-std::sin(line.heading), std::cos(line.heading));
  const auto side = [&](double s) { return normal.dot(curve.at(s) - line.anchor); };
  for (double s = from; s < to; s += 1.0) {
    double lo = s, hi = s + 1.0;
    if ((side(lo) > 0) == (side(hi) > 0)) continue;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((side(mid) > 0) == (side(lo) > 0) ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  return from;  // not reached: the streets are laid out to cross
}

}  // namespace

TimedPath cityDrive(const CityOptions& options) {
  std::mt19937 rng(options.seed);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  // Three long streets (family A) and four shorter ones (family B) crossing them obliquely.
  const double a_heading = uniform(0.0, 2.0 * M_PI);
  double gamma = uniform(55.0, 70.0) * kDeg;
  if (uniform(0.0, 1.0) < 0.5) gamma = M_PI - gamma;
  const Eigen::Vector2d along(std::cos(a_heading), std::sin(a_heading)), across(-along.y(), along.x());
  std::vector<Street> a_streets, b_streets;
  double offset = 0.0;
  for (int j = 0; j < 3; ++j) {
    // Spaced 105-135 m apart measured across, each a few degrees off the family's heading.
    a_streets.push_back({offset * across, a_heading + uniform(-3.0, 3.0) * kDeg, 0.0});
    offset += uniform(105.0, 135.0);
  }
  offset = 0.0;
  for (int i = 0; i < 4; ++i) {
    // Anchored where they cross the middle A street, so a curved one turns away from its heading by
    // at most about 15 degrees at the outer ones.
    const double curvature =
        uniform(0.0, 1.0) < 0.5 ? (uniform(0.0, 1.0) < 0.5 ? 1 : -1) / uniform(600.0, 1000.0) : 0.0;
    b_streets.push_back({a_streets[1].at(offset), a_heading + gamma + uniform(-4.0, 4.0) * kDeg, curvature});
    offset += uniform(115.0, 145.0);
  }
  // Junction (i, j) where B street i crosses A street j, as arc lengths along both.
  Eigen::Vector2d node_s[4][3];  // (along A street j, along B street i)
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double sb = crossing(b_streets[i], a_streets[j], -300.0, 300.0);
      const Eigen::Vector2d p = b_streets[i].at(sb);
      const Street& a = a_streets[j];
      node_s[i][j] = Eigen::Vector2d((p - a.anchor).dot(Eigen::Vector2d(std::cos(a.heading), std::sin(a.heading))), sb);
    }
  }

  // The route: junctions in driving order, each leg with the lane it is driven in (lateral offset,
  // positive to the left of the direction of travel).
  struct Leg {
    int i, j;
    double lane;
  };
  const double right = -options.lane;
  const std::vector<Leg> first_half = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {3, 2, 0},
                                       {2, 2, 0}, {1, 2, 0}, {0, 2, 0}, {0, 1, 0}, {0, 0, 0}};
  const std::vector<Leg> second_half = {// The loop's first street again, one lane to the right.
                                        {1, 0, right},
                                        {2, 0, right},
                                        {3, 0, right},
                                        // Its next two streets in the same lane as before.
                                        {3, 1, 0},
                                        {3, 2, 0},
                                        {2, 2, 0},
                                        // A middle street not driven before.
                                        {2, 1, 0},
                                        {1, 1, 0},
                                        {0, 1, 0},
                                        // The loop's last two streets against its direction, in the opposite lane.
                                        {0, 2, right},
                                        {1, 2, right},
                                        {2, 2, right}};
  std::vector<Leg> route = first_half;
  route.insert(route.end(), second_half.begin(), second_half.end());

  // Each leg sampled along its street, in its lane, stopping `trim` metres short of both junctions;
  // the corners are bridged when resampling and rounded by the smoothing below.
  const double trim = 12.0;
  std::vector<Eigen::Vector2d> raw;
  std::size_t pause = 0;
  for (std::size_t k = 1; k < route.size(); ++k) {
    const Leg& from = route[k - 1];
    const Leg& to = route[k];
    const bool on_a = from.j == to.j;
    const Street& street = on_a ? a_streets[to.j] : b_streets[to.i];
    const double s0 = on_a ? node_s[from.i][from.j].x() : node_s[from.i][from.j].y();
    const double s1 = on_a ? node_s[to.i][to.j].x() : node_s[to.i][to.j].y();
    const double direction = s1 > s0 ? 1.0 : -1.0;
    if (k == first_half.size()) pause = raw.size();
    for (double s = s0 + direction * trim; direction * (s1 - s) > trim; s += direction * 0.5) {
      const double h = street.headingAt(s) + (direction < 0 ? M_PI : 0.0);
      raw.push_back(street.at(s) + to.lane * Eigen::Vector2d(-std::sin(h), std::cos(h)));
    }
  }
  return timedDrive(raw, pause, options.speed, options.pause);
}

}  // namespace sim
}  // namespace scan_context_loop
