#pragma once
// Rigid-body transforms SE(3) on Eigen, templated on the scalar so that the same code runs
// in double, float and ceres::Jet (residuals differentiate through it).
//
// Convention (docs/architecture.md): T_a_b maps coordinates in frame b to frame a;
// camera poses are T_world_cam. The tangent vector is [rho; phi] — translation part
// first, rotation part second — and exp/log are the group exponential/logarithm:
//   exp([rho; phi]) = [ R(phi)  V(phi) rho ; 0 1 ],  R = exp([phi]x),
//   V(phi) = I + (1 - cos θ)/θ² [phi]x + (θ - sin θ)/θ³ [phi]x²,  θ = |phi|.
// The 7-number parameter block used by Ceres is [qx qy qz qw tx ty tz] (Eigen's
// quaternion storage order followed by the translation).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace omnidso {

template <typename T>
Eigen::Matrix<T, 3, 3> skew(const Eigen::Matrix<T, 3, 1>& v) {
  Eigen::Matrix<T, 3, 3> m;
  m << T(0), -v.z(), v.y(), v.z(), T(0), -v.x(), -v.y(), v.x(), T(0);
  return m;
}

// SO(3) exponential of a rotation vector, as a unit quaternion. The small-angle branch
// uses the Taylor series of sin(θ/2)/θ so that Jets stay differentiable at θ = 0.
template <typename T>
Eigen::Quaternion<T> so3Exp(const Eigen::Matrix<T, 3, 1>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta_sq = phi.squaredNorm();
  T real, imag_factor;
  if (theta_sq < T(1e-16)) {
    real = T(1) - theta_sq / T(8);
    imag_factor = T(0.5) - theta_sq / T(48);
  } else {
    const T theta = sqrt(theta_sq);
    const T half = theta / T(2);
    real = cos(half);
    imag_factor = sin(half) / theta;
  }
  return Eigen::Quaternion<T>(real, imag_factor * phi.x(), imag_factor * phi.y(),
                              imag_factor * phi.z());
}

// SO(3) logarithm: the rotation vector of a unit quaternion, in (-π, π].
template <typename T>
Eigen::Matrix<T, 3, 1> so3Log(const Eigen::Quaternion<T>& q_in) {
  using std::atan2;
  using std::sqrt;
  // q and -q are the same rotation; choose w >= 0 so that the angle is at most π.
  Eigen::Quaternion<T> q = q_in;
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  const T sin_sq = q.vec().squaredNorm();
  T factor;
  if (sin_sq < T(1e-16)) {
    // θ/sin(θ/2) → 2/w · (1 + sin²/(3w²)) for small angles.
    factor = T(2) / q.w() * (T(1) + sin_sq / (T(3) * q.w() * q.w()));
  } else {
    const T sin_half = sqrt(sin_sq);
    factor = T(2) * atan2(sin_half, q.w()) / sin_half;
  }
  return factor * q.vec();
}

template <typename T>
class SE3 {
 public:
  using Scalar = T;
  using Quaternion = Eigen::Quaternion<T>;
  using Matrix3 = Eigen::Matrix<T, 3, 3>;
  using Matrix4 = Eigen::Matrix<T, 4, 4>;
  using Vector3 = Eigen::Matrix<T, 3, 1>;
  using Tangent = Eigen::Matrix<T, 6, 1>;
  static constexpr int kNumParameters = 7;  // [qx qy qz qw tx ty tz]
  static constexpr int kDoF = 6;

  SE3() : q_(Quaternion::Identity()), t_(Vector3::Zero()) {}
  SE3(const Quaternion& q, const Vector3& t) : q_(q.normalized()), t_(t) {}
  SE3(const Matrix3& R, const Vector3& t) : q_(Quaternion(R).normalized()), t_(t) {}

  static SE3 identity() { return SE3(); }

  // Reads a parameter block [qx qy qz qw tx ty tz]; the quaternion is used as stored
  // (Ceres keeps it unit length through the manifold).
  static SE3 fromParameters(const T* p) {
    SE3 out;
    out.q_ = Quaternion(p[3], p[0], p[1], p[2]);
    out.t_ = Vector3(p[4], p[5], p[6]);
    return out;
  }
  void toParameters(T* p) const {
    p[0] = q_.x();
    p[1] = q_.y();
    p[2] = q_.z();
    p[3] = q_.w();
    p[4] = t_.x();
    p[5] = t_.y();
    p[6] = t_.z();
  }

  static SE3 exp(const Tangent& xi) {
    const Vector3 rho = xi.template head<3>();
    const Vector3 phi = xi.template tail<3>();
    return SE3(so3Exp(phi), leftJacobianSO3(phi) * rho);
  }

  Tangent log() const {
    const Vector3 phi = so3Log(q_);
    Tangent xi;
    xi.template head<3>() = leftJacobianSO3(phi).inverse() * t_;
    xi.template tail<3>() = phi;
    return xi;
  }

  SE3 inverse() const {
    const Quaternion q_inv = q_.conjugate();
    return SE3(q_inv, -(q_inv * t_));
  }

  SE3 operator*(const SE3& other) const { return SE3(q_ * other.q_, q_ * other.t_ + t_); }
  Vector3 operator*(const Vector3& p) const { return q_ * p + t_; }

  const Quaternion& rotation() const { return q_; }
  Matrix3 rotationMatrix() const { return q_.toRotationMatrix(); }
  const Vector3& translation() const { return t_; }
  Vector3& translation() { return t_; }
  Matrix4 matrix() const {
    Matrix4 m = Matrix4::Identity();
    m.template topLeftCorner<3, 3>() = rotationMatrix();
    m.template topRightCorner<3, 1>() = t_;
    return m;
  }

  template <typename U>
  SE3<U> cast() const {
    return SE3<U>(q_.template cast<U>(), t_.template cast<U>());
  }

  // V(phi) of the exponential map (left Jacobian of SO(3)); Taylor branch near zero.
  static Matrix3 leftJacobianSO3(const Vector3& phi) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T theta_sq = phi.squaredNorm();
    const Matrix3 K = skew(phi);
    T a, b;  // V = I + a K + b K²
    if (theta_sq < T(1e-10)) {
      a = T(0.5) - theta_sq / T(24);
      b = T(1) / T(6) - theta_sq / T(120);
    } else {
      const T theta = sqrt(theta_sq);
      // 1 − cos θ = 2 sin²(θ/2) avoids the cancellation that costs 1 − cos θ (and the
      // Jet derivative of a) about half their digits at small θ.
      const T sin_half = sin(theta / T(2));
      a = T(2) * sin_half * sin_half / theta_sq;
      b = (theta - sin(theta)) / (theta_sq * theta);
    }
    return Matrix3::Identity() + a * K + b * K * K;
  }

 private:
  Quaternion q_;
  Vector3 t_;
};

using SE3d = SE3<double>;
using SE3f = SE3<float>;

// Geodesic interpolation a·exp(s·log(a⁻¹ b)): s = 0 gives a, s = 1 gives b.
template <typename T>
SE3<T> interpolate(const SE3<T>& a, const SE3<T>& b, T s) {
  return a * SE3<T>::exp(s * (a.inverse() * b).log());
}

}  // namespace omnidso
