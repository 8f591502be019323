#include "loop_closure/loop_pair.h"

#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {

const char* const kLoopArrayLayout =
    "query_id match_id query_session match_session query_stamp match_stamp verified fitness distance "
    "x y z qx qy qz qw covariance[36]";

std_msgs::Float64MultiArray loopArray(const scan_context_loop::LoopClosure& loop) {
  std_msgs::Float64MultiArray out;
  out.layout.dim.resize(1);
  out.layout.dim[0].label = kLoopArrayLayout;
  out.layout.dim[0].size = kLoopArraySize;
  out.layout.dim[0].stride = kLoopArraySize;
  const geometry_msgs::Pose& p = loop.relative_pose;
  out.data = {static_cast<double>(loop.query_id),
              static_cast<double>(loop.match_id),
              static_cast<double>(loop.query_session),
              static_cast<double>(loop.match_session),
              loop.query_stamp.toSec(),
              loop.match_stamp.toSec(),
              loop.verified ? 1.0 : 0.0,
              loop.fitness,
              loop.distance,
              p.position.x,
              p.position.y,
              p.position.z,
              p.orientation.x,
              p.orientation.y,
              p.orientation.z,
              p.orientation.w};
  out.data.insert(out.data.end(), loop.covariance.begin(), loop.covariance.end());
  return out;
}

std::array<geometry_msgs::PoseWithCovarianceStamped, 2> loopPair(const scan_context_loop::LoopClosure& loop,
                                                                 const Eigen::Isometry3d& world_from_match) {
  std::array<geometry_msgs::PoseWithCovarianceStamped, 2> pair;
  geometry_msgs::PoseWithCovarianceStamped& match = pair[0];
  geometry_msgs::PoseWithCovarianceStamped& query = pair[1];
  match.header.frame_id = query.header.frame_id = loop.header.frame_id;
  match.header.stamp = loop.match_stamp;
  query.header.stamp = loop.query_stamp;
  match.pose.pose = tf2::toMsg(world_from_match);

  Eigen::Isometry3d query_from_match;
  tf2::fromMsg(loop.relative_pose, query_from_match);
  const Eigen::Isometry3d world_from_query = world_from_match * query_from_match.inverse();
  query.pose.pose = tf2::toMsg(world_from_query);
  // Position and rotation perturbations of the query keyframe, from its own axes to the pose frame's.
  Eigen::Matrix<double, 6, 6> rotate = Eigen::Matrix<double, 6, 6>::Zero();
  rotate.topLeftCorner<3, 3>() = world_from_query.linear();
  rotate.bottomRightCorner<3, 3>() = world_from_query.linear();
  const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> local(loop.covariance.data());
  const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> world = rotate * local * rotate.transpose();
  for (int i = 0; i < 36; ++i) query.pose.covariance[i] = world(i / 6, i % 6);
  return pair;
}

}  // namespace scan_context_loop
