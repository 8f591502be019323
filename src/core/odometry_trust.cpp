#include "scan_context_loop/core/odometry_trust.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/database.h"

namespace scan_context_loop {

void OdometryTrust::add(const Keyframe& query, const Keyframe& match, const Eigen::Isometry3d& relative,
                        const Config& config) {
  if (!query.info.pose || !match.info.pose || query.session != match.session) return;
  Anchor a;
  a.query_pose = *query.info.pose;
  a.match_pose = *match.info.pose;
  a.relative = relative;
  a.query_path = query.path_length;
  a.match_path = match.path_length;
  a.query_session = query.session;
  a.match_session = match.session;
  const auto anchor = static_cast<std::uint32_t>(anchors_.size());
  anchors_.push_back(a);
  Orders& orders = orders_[{a.query_session, a.match_session}];
  // After its equals: the orders keep equal paths in the order the loops were confirmed.
  const auto insert = [anchor](std::vector<Entry>* order, double path) {
    const auto at =
        std::upper_bound(order->begin(), order->end(), path, [](double p, const Entry& e) { return p < e.path; });
    order->insert(at, Entry{path, anchor});
  };
  insert(&orders.by_query, a.query_path);
  insert(&orders.by_match, a.match_path);
  // How wrong the direct odometry between the two keyframes was.
  const double path = std::fabs(query.path_length - match.path_length);
  if (!(path >= kMinMeasuredPath)) return;
  const Eigen::Isometry3d direct = a.query_pose.inverse() * a.match_pose;
  const double beyond = (direct.translation() - relative.translation()).norm() - config.gate_odometry_distance;
  if (std::isfinite(beyond)) translation_rate_ = std::max(translation_rate_, beyond / path);
}

OdometryPrediction OdometryTrust::predict(const Eigen::Isometry3d& pose, double path, std::uint32_t session,
                                          const Keyframe& candidate) const {
  OdometryPrediction best;
  best.relative = pose.inverse() * *candidate.info.pose;
  best.path = std::fabs(path - candidate.path_length);
  const Anchor* via = nullptr;
  std::uint32_t via_index = 0;
  const auto found = orders_.find({session, candidate.session});
  if (found != orders_.end()) {
    // An anchor leaves |path - its query's path| + |its match's path - the candidate's| of odometry.
    // Both orders are walked outwards from the two targets, the nearer next entry first: an anchor not
    // yet met in either walk leaves at least the two next distances together.
    struct Walk {
      const std::vector<Entry>& order;
      double target;
      std::size_t left, right;  // entries [left, right) walked
      Walk(const std::vector<Entry>& o, double t) : order(o), target(t) {
        left = right = static_cast<std::size_t>(
            std::lower_bound(o.begin(), o.end(), t, [](const Entry& e, double p) { return e.path < p; }) - o.begin());
      }
      bool done() const { return left == 0 && right == order.size(); }
      double leftGap() const {
        return left > 0 ? std::fabs(target - order[left - 1].path) : std::numeric_limits<double>::infinity();
      }
      double rightGap() const {
        return right < order.size() ? std::fabs(order[right].path - target) : std::numeric_limits<double>::infinity();
      }
      double next() const { return std::min(leftGap(), rightGap()); }
      std::uint32_t step() { return leftGap() <= rightGap() ? order[--left].anchor : order[right++].anchor; }
    };
    Walk by_query(found->second.by_query, path), by_match(found->second.by_match, candidate.path_length);
    while (!by_query.done() && !by_match.done()) {
      const double next_query = by_query.next(), next_match = by_match.next();
      if (!(next_query + next_match <= best.path)) break;
      const std::uint32_t index = next_query <= next_match ? by_query.step() : by_match.step();
      const Anchor& a = anchors_[index];
      const double length = std::fabs(path - a.query_path) + std::fabs(a.match_path - candidate.path_length);
      // Of equals the first confirmed, as a scan in that order picks; the direct odometry before both.
      if (length < best.path || (via != nullptr && length == best.path && index < via_index)) {
        best.path = length;
        via = &a;
        via_index = index;
      }
    }
  }
  if (via != nullptr) {
    best.relative = pose.inverse() * via->query_pose * via->relative * via->match_pose.inverse() * *candidate.info.pose;
    best.anchored = true;
  }
  return best;
}

double allowedDriftRate(const Config& config, const OdometryTrust& trust) {
  return std::max(config.gate_odometry_drift, OdometryTrust::kMeasuredDriftMargin * trust.translationRate());
}

double gateRadius(const Config& config, const OdometryTrust& trust, double path) {
  return config.gate_odometry_distance + allowedDriftRate(config, trust) * path;
}

}  // namespace scan_context_loop
