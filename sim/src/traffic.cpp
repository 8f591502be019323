// Traffic and pedestrians of the changed world: things that pass the sensor, each present for a few
// seconds, placed by where the sensor is at that time so they are seen and never stand in its way.
#include <algorithm>
#include <cmath>
#include <utility>

#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

namespace {

/// Where the sensor is along the drive at a time, and where along the path a distance is.
class DriveClock {
 public:
  DriveClock(const std::vector<PathPoint>& path, const std::vector<double>& times, double duration)
      : path_(path), arc_(path.size(), 0.0) {
    for (std::size_t k = 1; k < path.size(); ++k) {
      arc_[k] = arc_[k - 1] + std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y);
    }
    if (times.size() == path.size()) {
      times_ = times;
    } else {  // a uniform speed over the duration
      times_.resize(path.size());
      const double length = std::max(arc_.back(), 1e-9);
      for (std::size_t k = 0; k < path.size(); ++k) times_[k] = duration * arc_[k] / length;
    }
  }

  const std::vector<double>& times() const { return times_; }
  double start() const { return times_.front(); }
  double end() const { return times_.back(); }

  /// Distance along the path driven by time t.
  double arcAt(double t) const {
    const std::size_t k = segment(times_, t);
    const double span = times_[k + 1] - times_[k];
    const double f = span > 0.0 ? std::clamp((t - times_[k]) / span, 0.0, 1.0) : 0.0;
    return arc_[k] + f * (arc_[k + 1] - arc_[k]);
  }

  /// The point `s` along the path, heading as the path there; false beyond its ends.
  bool pointAt(double s, PathPoint* q) const {
    if (s < 0.0 || s > arc_.back()) return false;
    const std::size_t k = segment(arc_, s);
    const double span = arc_[k + 1] - arc_[k];
    const double f = span > 0.0 ? (s - arc_[k]) / span : 0.0;
    *q = {path_[k].x + f * (path_[k + 1].x - path_[k].x), path_[k].y + f * (path_[k + 1].y - path_[k].y),
          path_[k].heading};
    return true;
  }

  /// True when f keeps more than `distance` from every sensor position between t0 and t1 (and a
  /// little either side, for the path points' spacing).
  bool clearOf(const Footprint& f, double t0, double t1, double distance) const {
    const auto first = std::lower_bound(times_.begin(), times_.end(), t0 - 0.3);
    const auto last = std::upper_bound(times_.begin(), times_.end(), t1 + 0.3);
    for (auto it = first == times_.begin() ? first : first - 1; it != last && it != times_.end(); ++it) {
      const PathPoint& p = path_[static_cast<std::size_t>(it - times_.begin())];
      if (f.distanceTo(Eigen::Vector2d(p.x, p.y)) <= distance) return false;
    }
    return true;
  }

 private:
  /// k with values[k] <= v < values[k + 1], clamped to the segments there are.
  static std::size_t segment(const std::vector<double>& values, double v) {
    const auto it = std::upper_bound(values.begin(), values.end(), v);
    const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - values.begin() - 1, 0));
    return std::min(k, values.size() - 2);
  }

  const std::vector<PathPoint>& path_;
  std::vector<double> arc_, times_;
};

/// A car (now and then a lorry) for a few seconds, every half second a little further: following or
/// leading the sensor in its lane 10-40 m away, or oncoming in the other lane. Where it would come
/// within 2.5 m of the sensor (2 m for oncoming traffic passing it), or into something standing at
/// the kerb, it is left out.
void addVehicle(StreetKit& kit, const DriveClock& clock, double from, double to) {
  const double t0 = kit.uniform(from, to);
  const double window = kit.uniform(4.0, 10.0), step = 0.5;
  const bool oncoming = kit.chance(0.5);
  const VehicleShape shape = kit.vehicleShape(kit.chance(0.15));
  const double side = kit.chance(0.5) ? 1.0 : -1.0;
  const double lateral = oncoming ? side * std::max(3.0, 2.15 + shape.width / 2) : kit.uniform(-0.3, 0.3);
  const double gap = oncoming ? kit.uniform(25.0, 80.0) : kit.eitherWay(10.0, 40.0);
  const double speed = kit.uniform(8.0, 14.0);  // oncoming; the others keep the sensor's pace
  const double s0 = clock.arcAt(t0);
  for (double t = t0; t < t0 + window; t += step) {
    PathPoint q;
    if (!clock.pointAt(oncoming ? s0 + gap - speed * (t - t0) : clock.arcAt(t) + gap, &q)) break;
    if (oncoming) q.heading += M_PI;
    Vehicle v = kit.vehicleAt(shape, q, -shape.length / 2, lateral, q.heading);
    const Footprint f = StreetKit::footprintOf(v.body);
    // Overlaps of a few decimetres with a parked car at the lane's edge pass.
    if (!kit.occupied.free(f, -0.3) || !clock.clearOf(f, t, t + step, oncoming ? 2.0 : 2.5)) continue;
    v.body.present_from = v.cabin.present_from = t;
    v.body.present_to = v.cabin.present_to = t + step;
    kit.add(v);
  }
}

/// Someone walking along the pavement near the sensor for a few seconds, until they would reach the
/// road or something in their way.
void addPedestrian(StreetKit& kit, const DriveClock& clock, double from, double to) {
  const double t0 = kit.uniform(from, to);
  const double window = kit.uniform(5.0, 15.0), step = 1.0;
  const double ahead = kit.uniform(-20.0, 50.0), sign = kit.chance(0.5) ? 1.0 : -1.0;
  const double speed = kit.eitherWay(0.8, 1.6);
  const double radius = kit.uniform(0.25, 0.35), height = kit.uniform(1.6, 1.9);
  const double across = kit.uniform(0.0, 1.0);
  PathPoint q;
  if (!clock.pointAt(clock.arcAt(t0) + ahead, &q)) return;
  const Style& style = styleOf(kit.districtAt(StreetKit::at(q, 0.0, sign * 15.0)));
  const double lateral = sign * (kit.kerb() + 0.4 + across * std::max(0.0, style.pavement - 0.8));
  for (double t = t0; t < t0 + window; t += step) {
    const Eigen::Vector2d c = StreetKit::at(q, speed * (t - t0), lateral);
    const Footprint f = StreetKit::footprintOf(c, 0.0, radius, radius);
    if (!kit.roads.clear(f, kit.kerb() + 0.1) || !kit.occupied.free(f, 0.1) || !clock.clearOf(f, t, t + step, 2.5)) {
      break;
    }
    Primitive person = kit.cylinder(c, radius, 0.0, height, Material::kPerson);
    person.present_from = t;
    person.present_to = t + step;
    kit.out.push_back(person);
  }
}

}  // namespace

void addTraffic(const std::vector<PathPoint>& path, const std::vector<double>& times, double strength, StreetKit* kit) {
  addTraffic(path, times, strength, kit, -1e300, 1e300);
}

void addTraffic(const std::vector<PathPoint>& path, const std::vector<double>& times, double strength, StreetKit* kit,
                double from, double to) {
  if (path.size() < 2) return;
  const DriveClock clock(path, times, kit->options.duration);
  from = std::max(from, clock.start());
  to = std::min(to, clock.end());
  if (!(to > from)) return;
  const double duration = to - from;
  const long vehicles = kit->options.vehicles ? std::lround(strength * duration / 4.0) : 0;
  const long pedestrians = std::lround(strength * duration / 2.0);
  for (long i = 0; i < vehicles; ++i) addVehicle(*kit, clock, from, to);
  for (long i = 0; i < pedestrians; ++i) addPedestrian(*kit, clock, from, to);
}

namespace {

/// A pass of the drive: a stretch of its clock with its own density.
struct Pass {
  double from, to;    ///< [from, to) on the drive's clock; the first and last reach to -+infinity
  double parked;      ///< share of the parked cars present
  double filled;      ///< share of the empty spaces taken
  double traffic;     ///< traffic and pedestrians, a multiple of the usual
};

/// The drive's clock cut at every stop longer than a minute (the next pass starts when it drives on)
/// and every `seconds` of driving, each pass with its density drawn: the wider `strength` spreads it.
std::vector<Pass> passesOf(const std::vector<double>& times, double seconds, double strength, StreetKit& kit) {
  std::vector<double> starts(1, -1e300);
  double start = times.front();
  for (std::size_t k = 1; k < times.size(); ++k) {
    if (times[k] - times[k - 1] > 60.0 || times[k] - start >= seconds) {
      starts.push_back(times[k]);
      start = times[k];
    }
  }
  std::vector<Pass> passes;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    Pass p;
    p.from = starts[i];
    p.to = i + 1 < starts.size() ? starts[i + 1] : 1e300;
    p.parked = 1.0 - strength * kit.uniform(0.0, 0.7);
    p.filled = strength * kit.uniform(0.0, 0.5);
    p.traffic = std::exp(strength * kit.uniform(-std::log(3.0), std::log(3.0)));
    passes.push_back(p);
  }
  return passes;
}

/// The windows of the passes whose `share` exceeds u, adjoining ones merged: where a thing with draw u
/// is there (a car that stays when few are parked stays when more are too).
template <typename Share>
std::vector<std::pair<double, double>> presentIn(const std::vector<Pass>& passes, double u, Share share) {
  std::vector<std::pair<double, double>> runs;
  for (const Pass& p : passes) {
    if (!(u < share(p))) continue;
    if (!runs.empty() && runs.back().second == p.from)
      runs.back().second = p.to;
    else
      runs.emplace_back(p.from, p.to);
  }
  return runs;
}

/// Solid `index` is there only within `runs` (and its own window): itself in the first, copies in the
/// others; never, when none is left.
void keepOnlyDuring(StreetKit& kit, std::size_t index, const std::vector<std::pair<double, double>>& runs) {
  const Primitive solid = kit.out[index];
  bool first = true;
  for (const auto& run : runs) {
    const double from = std::max(run.first, solid.present_from), to = std::min(run.second, solid.present_to);
    if (!(from < to)) continue;
    Primitive copy = solid;
    copy.present_from = from;
    copy.present_to = to;
    if (first)
      kit.out[index] = copy;
    else
      kit.out.push_back(copy);
    first = false;
  }
  if (first) kit.out[index].present_to = kit.out[index].present_from;
}

}  // namespace

void passDensity(const std::vector<PathPoint>& path, const std::vector<double>& times, const StreetRecord& record,
                 double strength, StreetKit* kit) {
  if (path.size() < 2) return;
  const DriveClock clock(path, times, kit->options.duration);
  const std::vector<Pass> passes = passesOf(clock.times(), kit->options.pass_seconds, strength, *kit);
  for (const StreetRecord::Car& car : record.parked) {
    const auto runs = presentIn(passes, kit->uniform(0.0, 1.0), [](const Pass& p) { return p.parked; });
    keepOnlyDuring(*kit, car.body, runs);
    if (car.cabin != car.body) keepOnlyDuring(*kit, car.cabin, runs);
  }
  for (const StreetRecord::Space& space : record.empty_spaces) {
    const double u = kit->uniform(0.0, 1.0);
    Vehicle v = kit->parkedVehicle(space.p, space.sign, 0.0, space.industrial);
    const auto runs = presentIn(passes, u, [](const Pass& p) { return p.filled; });
    const Footprint f = StreetKit::footprintOf(v.body);
    if (runs.empty() || !kit->roads.clear(f, kit->parkingClearance()) || !kit->occupied.free(f, 0.3)) continue;
    kit->occupied.mark(f);
    const StreetRecord::Car car = kit->add(v);
    keepOnlyDuring(*kit, car.body, runs);
    if (car.cabin != car.body) keepOnlyDuring(*kit, car.cabin, runs);
  }
  // The traffic of the changed world (or of this option alone), at each pass's own multiple.
  const double base = kit->options.traffic * (kit->options.changed_world > 0.0 ? kit->options.changed_world : strength);
  for (const Pass& p : passes) addTraffic(path, times, base * p.traffic, kit, p.from, p.to);
}

}  // namespace sim
}  // namespace scan_context_loop
