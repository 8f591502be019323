#include "scan_context_loop/ros/loop_pair.h"

#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {

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
