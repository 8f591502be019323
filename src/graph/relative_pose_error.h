// The pose graph's factor: the whitened error of a measured relative pose T_a<-b, with its Jacobians.
// A private header of the graph library (it includes Ceres); test_graph checks the Jacobians.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Geometry>

#include "scan_context_loop/graph/pose_graph.h"  // Matrix6d

namespace scan_context_loop {

/// The residual, for any scalar: S [q_a^-1 (p_b - p_a) - p_m; 2 vec(q_m^-1 q_a^-1 q_b)], with S^T S the
/// information. Positions are 3 numbers, rotations Eigen quaternions (x, y, z, w).
struct RelativePoseError {
  RelativePoseError(const Eigen::Isometry3d& measured, const Matrix6d& sqrt_information)
      : p_measured(measured.translation()), q_measured(measured.linear()), sqrt_information(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(pa), p_b(pb);
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(qa), q_b(qb);
    const Eigen::Quaternion<T> q_a_inverse = q_a.conjugate();
    const Eigen::Quaternion<T> q_ab = q_a_inverse * q_b;
    const Eigen::Matrix<T, 3, 1> p_ab = q_a_inverse * (p_b - p_a);
    const Eigen::Quaternion<T> delta = q_measured.cast<T>().conjugate() * q_ab;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r.template head<3>() = p_ab - p_measured.cast<T>();
    r.template tail<3>() = T(2.0) * delta.vec();
    r.applyOnTheLeft(sqrt_information.cast<T>());
    return true;
  }

  Eigen::Vector3d p_measured;
  Eigen::Quaterniond q_measured;
  Matrix6d sqrt_information;
};

/// RelativePoseError with its Jacobians written out (the same products Eigen evaluates, differentiated
/// by hand): automatic differentiation carried 14 derivatives through every product and was most of the
/// solver's time.
class RelativePoseCost : public ceres::SizedCostFunction<6, 3, 4, 3, 4> {
 public:
  RelativePoseCost(const Eigen::Isometry3d& measured, const Matrix6d& sqrt_information)
      : error_(measured, sqrt_information) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    using Eigen::Matrix3d;
    using Eigen::Vector3d;
    const Eigen::Map<const Vector3d> p_a(parameters[0]), p_b(parameters[2]);
    const Eigen::Map<const Eigen::Quaterniond> q_a(parameters[1]), q_b(parameters[3]);
    const auto skew = [](const Vector3d& v) {
      Matrix3d m;
      m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
      return m;
    };
    // q * v is v + 2 w (u x v) + 2 u x (u x v) for q = (u, w); for q_a^-1, u = -u_a.
    const Vector3d u = q_a.vec(), d = p_b - p_a;
    const double w = q_a.w();
    const Matrix3d U = skew(u);
    const Matrix3d turn = Matrix3d::Identity() - 2.0 * w * U + 2.0 * U * U;  // d(q_a^-1 d)/dd
    error_(parameters[0], parameters[1], parameters[2], parameters[3], residuals);
    if (jacobians == nullptr) return true;
    // Quaternion products as 4 x 4 matrices in (x, y, z, w) order: a * b = left(a) b = right(b) a.
    using Matrix4d = Eigen::Matrix4d;
    const auto left = [&](const Eigen::Quaterniond& a) {
      Matrix4d m;
      m.topLeftCorner<3, 3>() = a.w() * Matrix3d::Identity() + skew(a.vec());
      m.topRightCorner<3, 1>() = a.vec();
      m.bottomLeftCorner<1, 3>() = -a.vec().transpose();
      m(3, 3) = a.w();
      return m;
    };
    const auto right = [&](const Eigen::Quaterniond& b) {
      Matrix4d m;
      m.topLeftCorner<3, 3>() = b.w() * Matrix3d::Identity() - skew(b.vec());
      m.topRightCorner<3, 1>() = b.vec();
      m.bottomLeftCorner<1, 3>() = -b.vec().transpose();
      m(3, 3) = b.w();
      return m;
    };
    // delta = m (a b) with m = q_m^-1, a = q_a^-1, b = q_b; the residual's rotation part is 2 vec(delta).
    const Matrix4d m = left(error_.q_measured.conjugate());
    const Eigen::Matrix4d conjugate = Eigen::Vector4d(-1.0, -1.0, -1.0, 1.0).asDiagonal();
    const Eigen::Matrix<double, 3, 4> rotation_by_qa = 2.0 * (m * right(q_b) * conjugate).topRows<3>();
    const Eigen::Matrix<double, 3, 4> rotation_by_qb = 2.0 * (m * left(q_a.conjugate())).topRows<3>();
    const Matrix6d& S = error_.sqrt_information;
    using Jacobian3 = Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>>;
    using Jacobian4 = Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>>;
    if (jacobians[0] != nullptr) Jacobian3{jacobians[0]} = -S.leftCols<3>() * turn;
    if (jacobians[2] != nullptr) Jacobian3{jacobians[2]} = S.leftCols<3>() * turn;
    if (jacobians[1] != nullptr) {
      // The translation part, q_a^-1 d = d - 2 w (u x d) + 2 u x (u x d), by u and by w.
      Eigen::Matrix<double, 3, 4> translation_by_qa;
      translation_by_qa.leftCols<3>() =
          2.0 * w * skew(d) + 2.0 * (u.dot(d) * Matrix3d::Identity() + u * d.transpose() - 2.0 * d * u.transpose());
      translation_by_qa.col(3) = -2.0 * u.cross(d);
      Jacobian4{jacobians[1]} = S.leftCols<3>() * translation_by_qa + S.rightCols<3>() * rotation_by_qa;
    }
    if (jacobians[3] != nullptr) Jacobian4{jacobians[3]} = S.rightCols<3>() * rotation_by_qb;
    return true;
  }

 private:
  RelativePoseError error_;
};

}  // namespace scan_context_loop
