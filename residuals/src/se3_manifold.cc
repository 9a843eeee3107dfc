#include "omnidso/residuals/se3_manifold.hpp"

#include "omnidso/core/se3.hpp"

namespace omnidso {
namespace {

using Mat43 = Eigen::Matrix<double, 4, 3>;

// Q(q) = [w I + [q_v]×; −q_vᵀ]: the matrix of v ↦ q ⊗ [v; 0] in x y z w storage.
Mat43 quaternionLeftProductOfPure(const double* x) {
  const Eigen::Vector3d qv(x[0], x[1], x[2]);
  const double w = x[3];
  Mat43 Q;
  Q.topRows<3>() = w * Eigen::Matrix3d::Identity() + skew(qv);
  Q.row(3) = -qv.transpose();
  return Q;
}

Eigen::Matrix3d rotationOf(const double* x) {
  return Eigen::Quaterniond(x[3], x[0], x[1], x[2]).toRotationMatrix();
}

}  // namespace

bool SE3Manifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Matrix<double, 6, 1>> d(delta);
  (SE3d::fromParameters(x) * SE3d::exp(d)).toParameters(x_plus_delta);
  return true;
}

bool SE3Manifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> P(jacobian);
  P.setZero();
  P.block<4, 3>(0, 3) = 0.5 * quaternionLeftProductOfPure(x);
  P.block<3, 3>(4, 0) = rotationOf(x);
  return true;
}

bool SE3Manifold::RightMultiplyByPlusJacobian(const double* x, int num_rows,
                                              const double* ambient_matrix,
                                              double* tangent_matrix) const {
  using RowMajorX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajorX> A(ambient_matrix, num_rows, 7);
  Eigen::Map<RowMajorX> out(tangent_matrix, num_rows, 6);
  // A · P: the rho columns see only the translation part, the phi columns only q.
  out.leftCols<3>() = A.rightCols<3>() * rotationOf(x);
  out.rightCols<3>() = A.leftCols<4>() * (0.5 * quaternionLeftProductOfPure(x));
  return true;
}

bool SE3Manifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Eigen::Matrix<double, 6, 1>>{y_minus_x} =
      (SE3d::fromParameters(x).inverse() * SE3d::fromParameters(y)).log();
  return true;
}

bool SE3Manifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>>{jacobian} = se3TangentToAmbient(x);
  return true;
}

Eigen::Matrix<double, 6, 7, Eigen::RowMajor> se3TangentToAmbient(const double* x) {
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> p_plus;
  p_plus.setZero();
  p_plus.block<3, 3>(0, 4) = rotationOf(x).transpose();
  p_plus.block<3, 4>(3, 0) = 2.0 * quaternionLeftProductOfPure(x).transpose();
  return p_plus;
}

}  // namespace omnidso
