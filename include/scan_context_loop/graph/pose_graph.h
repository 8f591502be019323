// A reference pose-graph backend: keyframe odometry poses as a chain of relative-pose factors, loop
// closures as relative-pose factors with their covariance under a robust loss, solved with Ceres.
// ROS-free (Eigen, Ceres, std); the `pose_graph` node wraps it.
//
// Conventions (doc/pose_graph.md says the same):
// - A pose is T_world<-keyframe (the sensor's pose, as the loop-closure node receives it).
// - A factor between keyframes a and b measures T_a<-b. Its residual is
//   [ p_ab - p̂_ab ; 2 vec(q̂_ab^-1 q_ab) ], with p̂_ab, q̂_ab the measurement and p_ab, q_ab the
//   estimate (T_a^-1 T_b): translation in a's axes [m], rotation as a small angle about a's axes [rad].
//   This is the order of a LoopClosure's covariance (x y z roll pitch yaw, in the query frame).
// - A loop closure (query q, match m, relative_pose T_q<-m) is the factor a = q, b = m.
// - Keyframes come in chains, one per odometry frame (one per robot; addKeyframe's `chain`, 0 by
//   default). Odometry between consecutive keyframes of one chain is the factor a = i, b = j (j the
//   chain's next keyframe) with the odometry's own T_i^-1 T_j and a diagonal covariance that grows with
//   the step (PoseGraphConfig). Chains are independent until loops join them.
// - Groups and gauges: chains joined by loops form a group; fixed keyframes (addFixedKeyframe: a prior
//   map's, at their stored poses) form one of their own that never moves. A group without fixed keyframes
//   holds the first keyframe of its lowest chain (the gauge): chain 0's group (the anchor's) starts where
//   chain 0's odometry did, an unjoined chain where its own did. The first loop between two groups moves
//   one of them rigidly so that the loop holds and frees its gauge: the group with the fixed keyframes
//   stays, else the one with the lower chain (chain 0's group always stays). From then the loop is a
//   normal factor, and the group moves as one (chains joined among themselves, then to the anchor's,
//   move together).
// - frame(c) = T_world<-odom_c: the corrected pose of chain c's first keyframe x inverse(its odometry
//   pose). joined(c): chain c is in chain 0's group, i.e. frame(c) is an estimate in the anchor's frame.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct PoseGraphConfig {
  /// Odometry noise per step: standard deviation = floor + per_metre x step length (the step's
  /// translation) + per_radian x the step's rotation angle (rotation only). Translation in metres,
  /// rotation in radians. The defaults (1 cm + 1% of the step; 0.0005 rad + 0.0002 rad per metre, i.e.
  /// 0.03 deg + 0.011 deg/m; nothing per radian) describe a LiDAR odometry that drifts about 1% of
  /// distance, mostly in translation (doc/defaults.md says how they were chosen; doc/pose_graph.md#what-limits-the-corrected-trajectory
  /// why no other weights did better over many drifts).
  double odometry_translation_floor = 0.01;
  double odometry_translation_per_metre = 0.01;
  double odometry_rotation_floor = 0.0005;
  double odometry_rotation_per_metre = 0.0002;
  /// Growth of the rotation's standard deviation per radian the step turns [rad/rad]: for an odometry
  /// whose heading error comes from its turns (a gyro's or a scan matcher's scale error on the angle)
  /// more than from the metres driven. 0 by default.
  double odometry_rotation_per_radian = 0.0;
  /// Robust loss on loop factors: Cauchy with this scale on the whitened residual's norm [-] (0: none,
  /// plain least squares). A loop whose residual is many standard deviations off loses its pull.
  double loop_robust_scale = 1.0;
  /// Solver iterations per optimize() call.
  int max_iterations = 50;

  /// Problems with the values, one line each (empty when usable).
  std::vector<std::string> validate() const;
};

/// One factor of the graph as it was added: it measures T_a<-b with `covariance` (x y z roll pitch yaw,
/// in a's axes; the residual's order above).
struct PoseGraphFactor {
  std::size_t a = 0, b = 0;
  Eigen::Isometry3d measurement = Eigen::Isometry3d::Identity();  ///< T_a<-b
  Matrix6d covariance = Matrix6d::Identity();
  bool loop = false;  ///< a loop factor (else odometry between consecutive keyframes of one chain)
};

struct PoseGraphResult {
  bool solved = false;  ///< Ceres reported a usable solution
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;
  std::string message;  ///< Ceres' brief report, or why nothing was solved
};

class PoseGraph {
 public:
  explicit PoseGraph(const PoseGraphConfig& config = PoseGraphConfig());
  ~PoseGraph();
  PoseGraph(const PoseGraph&) = delete;
  PoseGraph& operator=(const PoseGraph&) = delete;

  /// Appends a keyframe of chain `chain` with its odometry pose T_odom<-keyframe (odometry frame of
  /// that chain); returns its index. Its estimate starts at the chain's previous keyframe's estimate
  /// moved by the odometry step, so earlier corrections carry on; a chain's first keyframe starts at
  /// its odometry pose and is the gauge of its chain until a loop joins the chain to another group.
  /// Returns -1 (nothing added) if the pose is not finite, a coordinate is beyond kMaxCoordinate, its
  /// rotation is not one, the odometry step's factor cannot be weighted, or `chain` is not below
  /// kMaxChains.
  long addKeyframe(const Eigen::Isometry3d& odometry_pose, std::size_t chain = 0);
  /// Appends a keyframe held fixed at `pose` (T_world<-keyframe; a prior map's keyframe at its stored
  /// pose); returns its index, or -1 (nothing added) as addKeyframe. It belongs to no chain: no
  /// odometry factor ties it to another keyframe; loops may.
  long addFixedKeyframe(const Eigen::Isometry3d& pose);
  /// Keyframe i was added with addFixedKeyframe.
  bool fixed(std::size_t i) const;
  /// Adds a loop factor T_query<-match with its covariance (x y z roll pitch yaw in the query's axes).
  /// A loop between two groups first moves one onto the other (see the conventions above). False
  /// (nothing added) for an unknown keyframe, a self-loop, a non-finite pose or a covariance that is not
  /// symmetric positive definite, or between two fixed keyframes; `error` then says which.
  bool addLoop(std::size_t query, std::size_t match, const Eigen::Isometry3d& query_from_match,
               const Matrix6d& covariance, std::string* error = nullptr);
  /// Solves from the current estimates (warm start).
  PoseGraphResult optimize();

  std::size_t size() const { return odometry_.size(); }
  std::size_t loops() const { return loop_count_; }
  /// The corrected pose T_world<-keyframe of keyframe i (world = the odometry frame at keyframe 0,
  /// or with fixed keyframes their frame).
  Eigen::Isometry3d pose(std::size_t i) const;
  std::vector<Eigen::Isometry3d> poses() const;
  /// The correction T_world<-odom at the newest keyframe of chain `chain`: corrected pose x
  /// inverse(odometry pose); the identity before the chain's first keyframe.
  Eigen::Isometry3d correction(std::size_t chain = 0) const;

  /// Chains are numbered below this.
  static constexpr std::size_t kMaxChains = 1024;
  /// Keyframe coordinates beyond this [m] are refused: no odometry drives that far (10,000 km), and a
  /// step between such poses would overflow its covariance (its length squared).
  static constexpr double kMaxCoordinate = 1e7;
  /// One more than the highest chain any keyframe was added to (0 before the first).
  std::size_t chains() const;
  /// The chain keyframe i was added to; -1 for a fixed keyframe.
  long chainOf(std::size_t i) const;
  /// The keyframes of chain `chain`, in the order added (empty for an unknown chain).
  std::vector<std::size_t> chainKeyframes(std::size_t chain) const;
  /// The estimated T_world<-odom_chain: the corrected pose of the chain's first keyframe x inverse(its
  /// odometry pose); the identity for a chain without keyframes. In chain 0's frame (or the fixed
  /// keyframes') only when joined(chain); else in the frame of the chain's own group.
  Eigen::Isometry3d frame(std::size_t chain) const;
  /// Chain `chain` has keyframes and is in chain 0's group (chain 0 itself: true once it has keyframes).
  bool joined(std::size_t chain) const;
  /// The keyframes held constant now: the gauges of the groups without fixed keyframes, and the fixed
  /// keyframes; increasing.
  std::vector<std::size_t> held() const;

  /// The odometry pose keyframe i was added with (a fixed keyframe's: its fixed pose).
  const Eigen::Isometry3d& odometryPose(std::size_t i) const { return odometry_[i]; }
  /// Every factor in the order it was added (odometry and loops interleaved as they came).
  const std::vector<PoseGraphFactor>& factors() const { return factors_; }
  const PoseGraphConfig& config() const { return config_; }

 private:
  struct Impl;
  PoseGraphConfig config_;
  std::vector<Eigen::Isometry3d> odometry_;
  std::vector<PoseGraphFactor> factors_;
  std::size_t loop_count_ = 0;
  std::unique_ptr<Impl> impl_;
};

/// The odometry factor's covariance for a step T_i<-i+1 under `config` (diagonal).
Matrix6d odometryCovariance(const Eigen::Isometry3d& step, const PoseGraphConfig& config);

}  // namespace scan_context_loop
