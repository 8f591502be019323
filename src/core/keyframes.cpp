#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/keyframes.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include <pcl/filters/voxel_grid.h>

#include "scan_context_loop/core/gravity_alignment.h"
#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {

Eigen::Matrix<double, 6, 6> loopCovariance(const Loop& loop, const Config& config) {
  if (loop.verified || !loop.verification.reason.empty()) return loop.verification.covariance;
  const double half_sector = M_PI / config.num_sectors;
  Eigen::Matrix<double, 6, 1> diagonal;
  diagonal << config.covariance_translation, config.covariance_translation, config.covariance_translation,
      config.covariance_rotation, config.covariance_rotation, half_sector * half_sector;
  return diagonal.asDiagonal();
}

pcl::PointCloud<pcl::PointXYZ> keyframeCloud(const PointView& points, const Config& config) {
  pcl::PointCloud<pcl::PointXYZ> kept;
  kept.reserve(points.count);
  const double min_squared = config.min_range * config.min_range;
  const double max_squared = config.max_radius * config.max_radius;
  for (std::size_t i = 0; i < points.count; ++i) {
    const std::uint8_t* p = points.data + i * points.stride;
    float x, y, z;
    std::memcpy(&x, p + points.offset_x, sizeof x);
    std::memcpy(&y, p + points.offset_y, sizeof y);
    std::memcpy(&z, p + points.offset_z, sizeof z);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
    const double horizontal = static_cast<double>(x) * x + static_cast<double>(y) * y;
    if (horizontal < min_squared || horizontal > max_squared) continue;
    kept.push_back(pcl::PointXYZ(x, y, z));
  }
  return kept;
}

struct KeyframePipeline::Scan {
  double stamp = 0.0, path = 0.0;
  pcl::PointCloud<pcl::PointXYZ> world;
};

KeyframePipeline::KeyframePipeline(const Config& config) : detector_(config) {}

std::string KeyframePipeline::reconfigure(const Config& config) {
  const auto fixed = fixedSettingsChanged(configSettings(), this->config(), config);
  if (!fixed.empty()) {
    std::string keys;
    for (const auto& k : fixed) keys += (keys.empty() ? "" : ", ") + k;
    return "cannot change while running: " + keys;
  }
  const auto problems = config.validate();
  if (!problems.empty()) {
    std::string text;
    for (const auto& p : problems) text += (text.empty() ? "" : "; ") + p;
    return text;
  }
  detector_.reconfigure(config);
  return "";
}
KeyframePipeline::~KeyframePipeline() = default;

void KeyframePipeline::forgetOdometry() {
  // Another run of odometry: nothing of the last one carries over to keyframe selection or scans.
  has_last_ = has_previous_ = has_seen_ = false;
  seen_pose_.reset();
  jump_direction_ = 0;
  jump_count_ = 0;
  recent_.clear();
  path_ = 0.0;
}

bool KeyframePipeline::appendSessions(PriorSessions sessions, std::string* error) {
  if (!detector_.appendSessions(std::move(sessions), error)) return false;
  forgetOdometry();
  return true;
}

bool KeyframePipeline::selected(const KeyframeInfo& info) const {
  const Config& c = config();
  if (c.keyframe_min_distance <= 0.0 && c.keyframe_min_angle <= 0.0) return true;
  if (!has_last_ || !info.pose) return true;
  const Eigen::Isometry3d delta = last_pose_.inverse() * *info.pose;
  const bool moved = c.keyframe_min_distance > 0.0 && delta.translation().norm() >= c.keyframe_min_distance;
  const double yaw = std::atan2(delta(1, 0), delta(0, 0));
  const bool turned = c.keyframe_min_angle > 0.0 && std::fabs(yaw) * 180.0 / M_PI >= c.keyframe_min_angle;
  return moved || turned;
}

void KeyframePipeline::startSession() {
  const Database& database = detector_.database();
  if (database.size() == database.sessionStart()) return;
  detector_.startSession();
  forgetOdometry();
}

namespace {

/// Keyframes in a row whose stamps jump the same way that make the jump believed: one or two are a
/// glitch (a corrupt header, a clock sync stepping), three in order are a clock of their own (a bag
/// played again, a restarted odometry, clouds back after an outage). Each one refused before is lost,
/// so the count stays small.
constexpr std::size_t kStampJumpEvidence = 3;

/// A pose this far [m] from the last cloud's, with a stamp jumped back, is another odometry run: one run
/// moves a few metres between clouds at most (3 m at 108 km/h and 10 Hz).
constexpr double kOdometryRestartJump = 10.0;

}  // namespace

KeyframePipeline::StampStep KeyframePipeline::checkStamp(const KeyframeInfo& info, std::string* why) {
  const Database& database = detector_.database();
  const Config& c = config();
  int direction = 0;
  double last = 0.0;
  if (database.size() > database.sessionStart() && std::isfinite(info.stamp)) {
    last = database.keyframe(database.size() - 1).info.stamp;
    if (c.new_session_jump > 0.0 && info.stamp <= last - c.new_session_jump) {
      direction = -1;
    } else if (c.max_stamp_step > 0.0 && has_seen_ && info.stamp > seen_stamp_ + c.max_stamp_step) {
      direction = 1;
      last = seen_stamp_;
    }
  }
  const bool restarted = direction < 0 && info.pose && seen_pose_ &&
                         (info.pose->translation() - seen_pose_->translation()).norm() >= kOdometryRestartJump;
  if (direction == 0 || restarted) {
    jump_direction_ = 0;
    jump_count_ = 0;
    return restarted ? StampStep::kNewSession : StampStep::kGoesOn;
  }
  if (direction == jump_direction_ && info.stamp >= jump_stamp_) {
    ++jump_count_;
  } else {
    jump_direction_ = direction;
    jump_count_ = 1;
  }
  jump_stamp_ = info.stamp;
  if (jump_count_ >= kStampJumpEvidence) {
    jump_direction_ = 0;
    jump_count_ = 0;
    return direction < 0 ? StampStep::kNewSession : StampStep::kGoesOn;
  }
  std::ostringstream text;
  text.precision(17);
  text << "keyframe stamp " << info.stamp << " is " << std::fabs(info.stamp - last) << " s "
       << (direction < 0 ? "earlier than the previous keyframe's" : "later than the previous cloud's") << " " << last
       << ": refused as " << (direction < 0 ? "out of order" : "a stamp far ahead (max_stamp_step)") << " unless "
       << kStampJumpEvidence << " keyframes in a row show the same jump"
       << (direction < 0 ? " or the odometry jumps too (a bag played again, a restarted odometry: a new session)"
                         : " (clouds back after an outage)");
  if (why) *why = text.str();
  return StampStep::kRefused;
}

void KeyframePipeline::remember(const PointView& cloud, const KeyframeInfo& info) {
  const Config& c = config();
  if (has_previous_) path_ += (info.pose->translation() - previous_pose_.translation()).norm();
  has_previous_ = true;
  previous_pose_ = *info.pose;
  // Kept in the world frame, so that any later keyframe can take it into its own.
  auto scan = std::make_unique<Scan>();
  scan->stamp = info.stamp;
  scan->path = path_;
  scan->world = c.cloud_in_world_frame ? transformedCloud(cloud, Eigen::Affine3f::Identity())
                                       : transformedCloud(cloud, Eigen::Affine3f(info.pose->matrix().cast<float>()));
  recent_.push_back(std::move(scan));
  while (!recent_.empty() &&
         ((c.accumulate_seconds > 0.0 && recent_.front()->stamp < info.stamp - c.accumulate_seconds) ||
          (c.accumulate_distance > 0.0 && recent_.front()->path < path_ - c.accumulate_distance))) {
    recent_.pop_front();
  }
}

Detection KeyframePipeline::process(const PointView& cloud, const KeyframeInfo& info,
                                    pcl::PointCloud<pcl::PointXYZ>* described) {
  const Config& c = config();
  const bool accumulate = c.accumulate_seconds > 0.0 || c.accumulate_distance > 0.0;
  if ((c.cloud_in_world_frame || accumulate) && !info.pose) {
    Detection refused;
    refused.error = c.cloud_in_world_frame
                        ? "a cloud registered in the world frame (cloud_in_world_frame) needs its pose"
                        : "accumulating scans into keyframes (accumulate_seconds / accumulate_distance) needs poses";
    return refused;
  }
  std::string why;
  const StampStep step = checkStamp(info, &why);
  if (step == StampStep::kRefused) {
    Detection refused;
    refused.error = why;
    return refused;
  }
  const bool new_session = step == StampStep::kNewSession;
  if (new_session) startSession();
  if (std::isfinite(info.stamp)) {
    has_seen_ = true;
    seen_stamp_ = info.stamp;
    seen_pose_ = info.pose;
  }
  if (accumulate) remember(cloud, info);
  if (!new_session && !selected(info)) {
    Detection skipped;
    skipped.selected = false;
    return skipped;
  }
  PointView view = cloud;
  pcl::PointCloud<pcl::PointXYZ> copy;
  if (accumulate) {
    // The remembered scans, this one included, in this keyframe's sensor frame.
    const Eigen::Affine3f to_sensor(info.pose->inverse().matrix().cast<float>());
    for (const auto& scan : recent_) copy += transformedCloud(viewOf(scan->world), to_sensor);
  } else if (c.cloud_in_world_frame) {
    copy = transformedCloud(cloud, Eigen::Affine3f(info.pose->inverse().matrix().cast<float>()));
  } else if (c.voxel_leaf > 0.0) {
    copy = transformedCloud(cloud, Eigen::Affine3f::Identity());
  }
  if (c.voxel_leaf > 0.0 && !copy.empty()) {
    pcl::PointCloud<pcl::PointXYZ> filtered;
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    const float leaf = static_cast<float>(c.voxel_leaf);
    grid.setLeafSize(leaf, leaf, leaf);
    grid.setInputCloud(copy.makeShared());
    grid.filter(filtered);
    copy.swap(filtered);
  }
  if (accumulate || c.cloud_in_world_frame || c.voxel_leaf > 0.0) view = viewOf(copy);
  Detection detection = detector_.process(view, info);
  detection.new_session = new_session;
  if (described && detection.accepted) *described = keyframeCloud(view, c);
  if (detection.accepted && info.pose) {
    has_last_ = true;
    last_pose_ = *info.pose;
  }
  return detection;
}

}  // namespace scan_context_loop
