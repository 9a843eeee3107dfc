#pragma once
// The 6-DoF manifold of a pose parameter block [qx qy qz qw tx ty tz] (se3.hpp), right-
// multiplicative: x ⊞ δ = x · exp(δ), δ = [rho; phi], and y ⊟ x = log(x⁻¹ y).
//
// Plus Jacobian at δ = 0 (7×6, rows [q; t], columns [rho; phi]); R = R(q):
//   ∂t'/∂rho = R,  ∂t'/∂phi = 0        (t' = R V(phi) rho + t)
//   ∂q'/∂rho = 0,  ∂q'/∂phi = ½ Q(q)   (q' = q ⊗ [phi/2; 1] to first order)
// where Q(q) = [w I + [q_v]×; −q_vᵀ] (4×3, Eigen's x y z w storage), the matrix of
// v ↦ q ⊗ [v; 0]. For a unit q the columns of Q are orthonormal, so PᵀP = diag(I, ¼ I) and
// the pseudo-inverse P⁺ = (PᵀP)⁻¹Pᵀ = [[0, Rᵀ], [2 Qᵀ, 0]] (6×7). P⁺ is also the Minus
// Jacobian: log of x⁻¹y at y = x moves with the vector part of q_x* ⊗ q_y times 2 (and so3Log
// is invariant to the quaternion's scale), and with R_xᵀ (t_y − t_x).
//
// Hand-derived cost functions compute the natural tangent Jacobian J_local (N×6) and give
// Ceres the ambient Jacobian J_amb = J_local · P⁺ (see ambientFromTangentJacobian); then
// J_amb · P = J_local exactly, which is all Ceres uses.

#include <ceres/manifold.h>

#include <Eigen/Core>

namespace omnidso {

class SE3Manifold : public ceres::Manifold {
 public:
  static constexpr int kAmbientSize = 7;
  static constexpr int kTangentSize = 6;

  int AmbientSize() const override { return kAmbientSize; }
  int TangentSize() const override { return kTangentSize; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool RightMultiplyByPlusJacobian(const double* x, int num_rows, const double* ambient_matrix,
                                   double* tangent_matrix) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// P⁺ = [[0, Rᵀ], [2 Qᵀ, 0]] (6×7, row-major) of the pose block x (unit quaternion).
Eigen::Matrix<double, 6, 7, Eigen::RowMajor> se3TangentToAmbient(const double* x);

// J_amb = J_local · P⁺ for a row-major N×6 tangent Jacobian, written row-major N×7.
template <int N>
void ambientFromTangentJacobian(const Eigen::Matrix<double, 6, 7, Eigen::RowMajor>& p_plus,
                                const Eigen::Matrix<double, N, 6, Eigen::RowMajor>& j_local,
                                double* j_ambient) {
  Eigen::Map<Eigen::Matrix<double, N, 7, Eigen::RowMajor>>{j_ambient} = j_local * p_plus;
}

}  // namespace omnidso
