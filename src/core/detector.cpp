#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "scan_context_loop/core/acceptance_rule.h"
#include "scan_context_loop/core/gravity_alignment.h"
#include "scan_context_loop/core/odometry_trust.h"

namespace scan_context_loop {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

Loop VerifiedCandidate::toLoop(std::size_t query) const {
  Loop loop;
  loop.query = query;
  loop.match = index;
  loop.viewpoint = viewpoint;
  loop.tracked = tracked;
  loop.alignment = alignment;
  loop.verified = result.accepted;
  loop.verification = result;
  return loop;
}

std::vector<Eigen::Vector2f> lateralViewpoints(const Config& config) {
  std::vector<Eigen::Vector2f> views;
  if (!(config.lateral_offset_step > 0.0)) return views;
  const float step = static_cast<float>(config.lateral_offset_step);
  for (int k = 1; k <= config.lateral_offset_count; ++k) {
    views.emplace_back(0.0f, k * step);
    views.emplace_back(0.0f, -k * step);
  }
  return views;
}

void LoopDetector::reconfigure(const Config& config) {
  database_.reconfigure(config);
  verification_ = config.verification;
  verifier_.setConfig(verification_);
  consistency_.reconfigure(config);
}

bool LoopDetector::appendSessions(PriorSessions sessions, std::string* error) {
  const std::size_t n = sessions.keyframes.size();
  const auto fail = [error](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!sessions.gravity_alignment.empty() && sessions.gravity_alignment.size() != n) {
    return fail(std::to_string(sessions.gravity_alignment.size()) + " gravity alignment rotations for " +
                std::to_string(n) + " keyframes");
  }
  if (!sessions.clouds.empty() && sessions.clouds.size() != n) {
    return fail(std::to_string(sessions.clouds.size()) + " registration clouds for " + std::to_string(n) +
                " keyframes");
  }
  for (std::size_t i = 0; i < sessions.clouds.size(); ++i) {
    const VoxelCloud* cloud = sessions.clouds[i].get();
    if (const std::string problem = cloud ? cloudMismatch(*cloud) : ""; !problem.empty()) {
      return fail("keyframe " + std::to_string(i) + ": " + problem);
    }
  }
  const std::size_t first = database_.size();
  // Room first, so that once the database holds the keyframes, extending the side array cannot fail and
  // leave every later keyframe's gravity alignment one off.
  gravity_alignment_.reserve(first + n);
  if (!database_.appendSessions(std::move(sessions.keyframes), error, sessions.descriptors_checked)) return false;
  if (sessions.gravity_alignment.empty()) {
    gravity_alignment_.resize(first + n, Eigen::Matrix3f::Identity());
  } else {
    for (const Eigen::Matrix3f& g : sessions.gravity_alignment) gravity_alignment_.push_back(g);
  }
  for (std::size_t i = 0; i < sessions.clouds.size(); ++i) {
    if (sessions.clouds[i]) store_.add(first + i, std::move(*sessions.clouds[i]));
  }
  return true;
}

Detection LoopDetector::process(const PointView& raw, const KeyframeInfo& info) {
  Detection detection;
  const Config& config = database_.config();
  if (!database_.acceptable(info, &detection.error)) return detection;
  // Query (from every viewpoint) before adding, so the keyframe never finds itself.
  GravityAlignedScan described;
  if (database_.session() != world_tilt_session_) {
    world_tilt_.reset();  // another session, another odometry frame
    world_tilt_session_ = database_.session();
    posed_keyframes_ = 0;
  }
  const auto t_tilt = Clock::now();
  updateWorldTilt(raw, info, &detection);  // first: the first keyframe's fit says which axis is up
  detection.ground_check_seconds = secondsSince(t_tilt);
  describeAndQuery(raw, info, &described, &detection);
  const Eigen::Matrix3f to_gravity = described.to_gravity;
  const PointView& points = described.points;  // the raw cloud: to_gravity turns it
  const auto t2 = Clock::now();
  detection.index = database_.size();
  // Room first: once the database holds the keyframe, its gravity alignment must be stored too. The
  // alignments grow by chunks: growing never copies those of a million keyframes into new memory.
  gravity_alignment_.reserve(gravity_alignment_.size() + 1);
  detection.accepted = database_.add(info, std::move(described.descriptor), &detection.error);
  detection.query_seconds += secondsSince(t2);
  if (!detection.accepted) return detection;
  gravity_alignment_.push_back(to_gravity);
  if (config.verification.enabled) {
    const auto start = Clock::now();
    VoxelCloud cloud = prepareCloud(points, verification_, to_gravity);
    const std::optional<TrackedCandidate> tracked =
        tracker_.predict(database_, detection.index, detection.query.eligible,
                         [this](std::size_t i) { return store_.get(i) != nullptr; });
    try {
      verifyCandidates(cloud, database_.keyframe(detection.index).descriptor, to_gravity, true,
                       tracked ? &*tracked : nullptr, &detection);
    } catch (...) {
      // The keyframe is in the database: its registration data go with it even when verifying it threw
      // (the caller's exception barrier reports that), so later keyframes can still verify loops to it.
      store_.add(detection.index, std::move(cloud));
      throw;
    }
    store_.add(detection.index, std::move(cloud));
    detection.verify_seconds = secondsSince(start);
  }
  const auto t_choose = Clock::now();
  chooseLoops(&detection);
  detection.choose_seconds = secondsSince(t_choose);
  return detection;
}

void LoopDetector::describeAndQuery(const PointView& raw, const KeyframeInfo& info, GravityAlignedScan* out,
                                    Detection* detection) {
  const Config& config = database_.config();
  const auto t0 = Clock::now();
  // Gravity-aligned keyframes are described and registered in their gravity-aligned frame: the binning
  // turns each point as it reads it, for the real viewpoint and the virtual ones in one pass.
  out->to_gravity = gravityAlignmentOf(raw, info, detection);
  out->points = raw;
  std::vector<Eigen::Vector2f> views = {Eigen::Vector2f::Zero()};
  for (const Eigen::Vector2f& view : lateralViewpoints(config)) views.push_back(view);
  std::vector<HeightGrid> grids = makeHeightGrids(raw, config, views, out->to_gravity);
  detection->points_used = grids.front().points_used;
  detection->points_skipped = grids.front().points_skipped;
  out->descriptor = makeDescriptor(grids.front(), config);
  detection->descriptor_seconds = secondsSince(t0);
  const auto t1 = Clock::now();
  detection->query = database_.query(out->descriptor, info);
  detection->query_seconds = secondsSince(t1);
  if (out->descriptor.empty()) return;
  views.erase(views.begin());
  grids.erase(grids.begin());
  queryViewpoints(views, grids, info, detection);
}

std::string LoopDetector::cloudMismatch(const VoxelCloud& cloud) const {
  const VoxelOptions voxels = voxelOptions(verification_);
  if (cloud.normals.size() != cloud.means.size()) {
    return "registration data with " + std::to_string(cloud.means.size()) + " voxel means but " +
           std::to_string(cloud.normals.size()) + " normals";
  }
  if (cloud.resolution != voxels.resolution || cloud.max_range != voxels.max_range) {
    return "registration data of " + std::to_string(cloud.resolution) + " m voxels within " +
           std::to_string(cloud.max_range) + " m, but verification uses " + std::to_string(voxels.resolution) +
           " m within " + std::to_string(voxels.max_range) + " m";
  }
  return "";
}

bool LoopDetector::attachCloud(std::size_t index, const Eigen::Matrix3f& gravity_alignment, const VoxelCloud& cloud,
                               std::string* error) {
  std::string problem =
      index < database_.size() ? cloudMismatch(cloud) : "keyframe " + std::to_string(index) + " is not in the database";
  if (!problem.empty()) {
    if (error) *error = problem;
    return false;
  }
  gravity_alignment_.set(index, gravity_alignment);
  store_.add(index, cloud);
  return true;
}

const Eigen::Matrix3f& LoopDetector::gravityAlignment(std::size_t index) const {
  if (index >= gravity_alignment_.size()) {
    throw std::out_of_range("gravity alignment of keyframe " + std::to_string(index) + " of " +
                            std::to_string(gravity_alignment_.size()));
  }
  return gravity_alignment_[index];
}

Detection LoopDetector::locate(const PointView& raw) {
  Detection detection;
  detection.index = database_.size();
  const KeyframeInfo info;  // no stamp or pose: only the windows of the earlier sessions apply
  GravityAlignedScan described;
  describeAndQuery(raw, info, &described, &detection);
  if (described.descriptor.empty() || !database_.config().verification.enabled) return detection;
  const auto t2 = Clock::now();
  verifyCandidates(prepareCloud(described.points, verification_, described.to_gravity), described.descriptor,
                   described.to_gravity, false, nullptr, &detection);
  detection.verify_seconds = secondsSince(t2);
  return detection;
}

Eigen::Matrix3f LoopDetector::gravityAlignmentOf(const PointView& points, const KeyframeInfo& info,
                                                 Detection* detection) const {
  const Config& config = database_.config();
  const GravityAlignmentMode mode = config.gravity_alignment;
  Eigen::Matrix3d to_gravity = Eigen::Matrix3d::Identity();
  bool found = false;
  // The pose (auto: turned so that the world's up axis is z, world_tilt.h, and when its tilt is then
  // plausible). The world's remaining tilt is left in: A-LOAM's and FAST-LIO's worlds start at the first
  // scan's frame, a few degrees off, the same for every keyframe of the session; correcting it by an
  // estimate from ground fits added their error (on a VLP-16 pitched 6 degrees it cost 13 of 203 loops
  // their rotation; gravity-aligning each keyframe by its own ground fit, 79).
  if (info.pose && (mode == GravityAlignmentMode::kAuto || mode == GravityAlignmentMode::kPose)) {
    const Eigen::Matrix3d pose_R = info.pose->linear();
    const Eigen::Matrix3d from_pose = gravityAlignmentFromOrientation(
        mode == GravityAlignmentMode::kAuto ? Eigen::Matrix3d(world_tilt_.axisCorrection() * pose_R) : pose_R);
    const double tilt = Eigen::AngleAxisd(from_pose).angle() * 180.0 / M_PI;
    if (mode == GravityAlignmentMode::kPose || tilt <= config.trusted_pose_max_tilt_deg) {
      to_gravity = from_pose;
      found = true;
      detection->aligned_by = "pose";
    }
  }
  if (!found && (mode == GravityAlignmentMode::kAuto || mode == GravityAlignmentMode::kGround) &&
      gravityAlignmentFromGround(points, GroundFitOptions(), &to_gravity, nullptr)) {
    found = true;
    detection->aligned_by = "ground";
  }
  detection->tilt_deg = found ? Eigen::AngleAxisd(to_gravity).angle() * 180.0 / M_PI : 0.0;
  // Below half a degree the rotation changes nothing a descriptor or a registration would notice.
  if (!found || detection->tilt_deg < 0.5) return Eigen::Matrix3f::Identity();
  return to_gravity.cast<float>();
}

void LoopDetector::updateWorldTilt(const PointView& points, const KeyframeInfo& info, Detection* detection) {
  const GravityAlignmentMode mode = database_.config().gravity_alignment;
  if (!info.pose || !(mode == GravityAlignmentMode::kAuto || mode == GravityAlignmentMode::kPose)) return;
  if (world_tilt_.established() && posed_keyframes_++ % kGravityCheckInterval != 0) return;
  Eigen::Matrix3d ground;
  if (!gravityAlignmentFromGround(points, GroundFitOptions(), &ground, nullptr)) return;
  // Row 2 of L_R_sensor is the up direction in the sensor frame.
  const Eigen::Vector3d up_ground = ground.row(2).transpose().normalized();
  const Eigen::Matrix3d world_R_sensor = info.pose->linear();
  const Eigen::Vector3d up_pose = world_R_sensor.transpose() * Eigen::Vector3d::UnitZ();
  detection->gravity_disagreement_deg = std::acos(std::clamp(up_pose.dot(up_ground), -1.0, 1.0)) * 180.0 / M_PI;
  world_tilt_.add(world_R_sensor, up_ground);
  if (world_tilt_.established()) detection->world_tilt_deg = world_tilt_.tiltDeg();
}

void LoopDetector::queryViewpoints(const std::vector<Eigen::Vector2f>& views, const std::vector<HeightGrid>& grids,
                                   const KeyframeInfo& info, Detection* detection) {
  const Config& config = database_.config();
  if (views.empty()) return;
  std::vector<Candidate>& merged = detection->query.candidates;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Eigen::Vector2f& view = views[v];
    const auto t0 = Clock::now();
    const Descriptor d = makeDescriptor(grids[v], config);
    const auto t1 = Clock::now();
    detection->descriptor_seconds += std::chrono::duration<double>(t1 - t0).count();
    QueryResult r = database_.query(d, info);
    for (Candidate& c : r.candidates) {
      c.viewpoint = view.cast<double>();
      auto same = std::find_if(merged.begin(), merged.end(), [&](const Candidate& m) { return m.index == c.index; });
      if (same == merged.end()) {
        merged.push_back(c);
      } else if (c.alignment.distance < same->alignment.distance) {
        *same = c;
      }
    }
    detection->query_seconds += secondsSince(t1);
  }
  std::stable_sort(merged.begin(), merged.end(),
                   [](const Candidate& a, const Candidate& b) { return a.alignment.distance < b.alignment.distance; });
  if (merged.size() > static_cast<std::size_t>(config.num_candidates)) merged.resize(config.num_candidates);
  detection->query.matched = !merged.empty() && merged.front().alignment.distance < config.distance_threshold;
}

std::vector<Eigen::Isometry3d> LoopDetector::hypotheses(const Candidate& c, const Descriptor& query) const {
  // The candidate's own alignment first (its viewpoint and the sector-key shift), then the other
  // distinct column shifts of the real view, best first: a wrong coarse shift is then only a wrong
  // first guess.
  std::vector<Eigen::Isometry3d> poses = {priorPose(c.alignment.yaw, c.viewpoint)};
  const Descriptor& match = database_.keyframe(c.index).descriptor;
  const int separation = std::max(1, query.num_sectors / 20);
  for (const Alignment& a : alignHypotheses(query, match, kYawHypotheses, separation)) {
    const double gap = std::fabs(wrapAngle(a.yaw - c.alignment.yaw));
    if (gap * query.num_sectors < 2.0 * M_PI * separation) continue;  // the same as the first
    poses.push_back(priorPose(a.yaw));
  }
  return poses;
}

void LoopDetector::verifyCandidates(const VoxelCloud& cloud, const Descriptor& query, const Eigen::Matrix3f& to_gravity,
                                    bool query_stored, const TrackedCandidate* tracked, Detection* detection) {
  const Config& config = database_.config();
  detection->verifications_enabled = true;
  verifier_.setQuery(cloud);
  if (tracked != nullptr) {
    Candidate c;
    c.index = tracked->index;
    c.alignment = align(query, database_.keyframe(c.index).descriptor, config);
    // The guess in the gravity-aligned frames the registration data are in.
    const Eigen::Matrix3d lq = to_gravity.cast<double>(), lm = gravity_alignment_[c.index].cast<double>();
    Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
    guess.linear() = lq * tracked->guess.linear() * lm.transpose();
    guess.translation() = lq * tracked->guess.translation();
    if (verifyOne(c, true, {guess}, to_gravity, query_stored, detection)) return;
  }
  int tried = 0;
  for (const Candidate& c : detection->query.candidates) {
    if (tried >= config.verification.max_candidates || !(c.alignment.distance < config.verification.threshold)) break;
    if (tracked != nullptr && c.index == tracked->index) continue;  // registered from a better guess already
    // A candidate whose data the store dropped (CloudStore, long runs) is listed as unverifiable but
    // does not use up a registration: the next candidates, kept ones among them, get their turn.
    if (store_.get(c.index) != nullptr) ++tried;
    if (verifyOne(c, false, hypotheses(c, query), to_gravity, query_stored, detection)) return;
  }
}

bool LoopDetector::verifyOne(const Candidate& c, bool tracked, const std::vector<Eigen::Isometry3d>& guesses,
                             const Eigen::Matrix3f& to_gravity, bool query_stored, Detection* detection) {
  VerifiedCandidate v;
  v.index = c.index;
  v.alignment = c.alignment;
  v.viewpoint = c.viewpoint;
  v.tracked = tracked;
  const VoxelCloud* stored = store_.get(c.index);
  if (stored == nullptr) {
    v.result.record(unverifiableVerdict());
  } else if (database_.config().verification.submap > 0) {
    v.result = verifier_.verify(submapOf(c.index, detection->index), guesses);
  } else {
    v.result = verifier_.verify(*stored, guesses);
  }
  toSensorFrames(to_gravity, c.index, &v.result);
  if (query_stored && (v.result.accepted || v.result.needs_support)) {
    checkOdometry(detection->index, c.index, &v.result);
  }
  detection->verifications.push_back(v);
  detection->verified = v.result.accepted;
  return v.result.accepted;
}

VoxelCloud LoopDetector::submapOf(std::size_t index, std::size_t query) const {
  VoxelCloud merged = *store_.get(index);
  const auto& centre = database_.keyframe(index).info.pose;
  if (!centre) return merged;
  const int n = database_.config().verification.submap;
  for (long k = static_cast<long>(index) - n; k <= static_cast<long>(index) + n; ++k) {
    if (k < 0 || static_cast<std::size_t>(k) == index || static_cast<std::size_t>(k) >= query) continue;
    const VoxelCloud* other = store_.get(static_cast<std::size_t>(k));
    const auto& pose = database_.keyframe(static_cast<std::size_t>(k)).info.pose;
    if (other == nullptr || !pose || !database_.sameSession(index, static_cast<std::size_t>(k))) continue;
    // Gravity-aligned candidate frame <- gravity-aligned neighbour frame, through the odometry.
    Eigen::Isometry3d moved = centre->inverse() * *pose;
    moved.linear() =
        gravity_alignment_[index].cast<double>() * moved.linear() * gravity_alignment_[k].transpose().cast<double>();
    moved.translation() = gravity_alignment_[index].cast<double>() * moved.translation();
    const Eigen::Matrix3f R = moved.linear().cast<float>();
    const Eigen::Vector3f t = moved.translation().cast<float>();
    for (std::size_t i = 0; i < other->size(); ++i) {
      merged.means.push_back(R * other->means[i] + t);
      const Eigen::Vector3f normal = R * other->normal(i);
      merged.normals.push_back({static_cast<std::int8_t>(std::lround(normal.x() * 127.0f)),
                                static_cast<std::int8_t>(std::lround(normal.y() * 127.0f)),
                                static_cast<std::int8_t>(std::lround(normal.z() * 127.0f)), other->normals[i][3]});
    }
  }
  return merged;
}

void LoopDetector::checkOdometry(std::size_t query, std::size_t match, VerificationResult* result) const {
  const Config& config = database_.config();
  const Keyframe& q = database_.keyframe(query);
  const Keyframe& m = database_.keyframe(match);
  if (!q.info.pose || !m.info.pose || q.session != m.session) return;
  // What the odometry says, directly or through the nearest confirmed loop (odometry_trust.h), against
  // the registered loop; the acceptance rule judges the difference.
  const OdometryTrust& trust = database_.odometryTrust();
  const OdometryPrediction predicted = trust.predict(*q.info.pose, q.path_length, q.session, m);
  OdometryDisagreement d;
  d.rotation_deg =
      Eigen::AngleAxisd(predicted.relative.linear().transpose() * result->relative.linear()).angle() * 180.0 / M_PI;
  d.translation_m = (predicted.relative.translation() - result->relative.translation()).norm();
  d.path = predicted.path;
  d.anchored = predicted.anchored;
  d.drift_rate = allowedDriftRate(config, trust);
  result->odometry_excess = odometryExcess(d, config);
  if (const std::optional<Verdict> verdict = judgeOdometry(d, result->accepted, config)) result->record(*verdict);
}

void LoopDetector::toSensorFrames(const Eigen::Matrix3f& query_alignment, std::size_t match,
                                  VerificationResult* result) const {
  const Eigen::Matrix3d lq = query_alignment.cast<double>(), lm = gravity_alignment_[match].cast<double>();
  if (lq.isIdentity() && lm.isIdentity()) return;
  // T_query<-match = Lq^T * T_Lq<-Lm * Lm, and the covariance turned with Lq^T.
  Eigen::Isometry3d& t = result->relative;
  t.linear() = lq.transpose() * t.linear() * lm;
  t.translation() = lq.transpose() * t.translation();
  Eigen::Matrix<double, 6, 6> turn = Eigen::Matrix<double, 6, 6>::Zero();
  turn.topLeftCorner<3, 3>() = lq.transpose();
  turn.bottomRightCorner<3, 3>() = lq.transpose();
  result->covariance = turn * result->covariance * turn.transpose();
}

void LoopDetector::chooseLoops(Detection* detection) {
  const Config& config = database_.config();
  if (!config.verification.enabled) {
    if (!detection->query.matched) return;
    const Candidate& best = *detection->query.best();
    Loop loop;
    loop.query = detection->index;
    loop.match = best.index;
    loop.viewpoint = best.viewpoint;
    loop.alignment = best.alignment;
    detection->loops.push_back(loop);
    return;
  }
  const bool check = config.consistency_min_support > 0;
  if (check) consistency_.advance(detection->index, &detection->dropped);
  // The accepted candidate, else (with the consistency check, which alone can confirm it) the one that
  // needs support with the largest overlap.
  // Else one that needs support with the largest overlap, else the one the odometry contradicted least
  // (it passed every geometric test; in a street that looks the same both ways round, a registration
  // 180 degrees off passes them too).
  const VerifiedCandidate* chosen = detection->verified ? &detection->verifications.back() : nullptr;
  if (chosen == nullptr && check) {
    for (const VerifiedCandidate& v : detection->verifications) {
      if (v.result.needs_support && (chosen == nullptr || v.result.inlier_ratio > chosen->result.inlier_ratio)) {
        chosen = &v;
      }
    }
  }
  if (chosen == nullptr && check) {
    for (const VerifiedCandidate& v : detection->verifications) {
      if (v.result.odometry_contradicted &&
          (chosen == nullptr || v.result.odometry_excess < chosen->result.odometry_excess)) {
        chosen = &v;
      }
    }
  }
  if (chosen == nullptr) return;
  Loop loop = chosen->toLoop(detection->index);
  if (!check) {
    detection->loops.push_back(loop);
  } else if (tracker_.agrees(loop, database_, loop.verification.needs_support)) {
    // It lands where the revisit's last confirmed loop and the odometry put it (strictly, for one that
    // needs support): that loop is its support. A tracked loop that lands elsewhere waits like any other.
    loop.markConfirmed();
    loop.support = 1;
    detection->loops.push_back(loop);
    consistency_.add(loop, database_, &detection->loops);
  } else {
    consistency_.offer(loop, database_, &detection->loops);
  }
  for (const Loop& reported : detection->loops) {
    tracker_.anchor(reported);
    database_.addConfirmedLoop(reported.query, reported.match, reported.relative());
  }
}

}  // namespace scan_context_loop
