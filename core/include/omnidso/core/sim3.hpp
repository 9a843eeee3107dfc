#pragma once
// Similarity transforms Sim(3): x ↦ s R x + t (scale s > 0, rotation R, translation t),
// templated on the scalar like SE3. Monocular odometry is defined only up to such a
// transform, so evaluation aligns estimates to ground truth with one (see alignment.hpp).
//
// Tangent vector [rho; phi; sigma] (7): translation part, rotation vector, log-scale.
// The group exponential of the generator [[σI + [φ]x, ρ], [0, 0]] is
//   s = e^σ,  R = exp([φ]x),  t = W(φ, σ) ρ,
//   W = ∫₀¹ e^{στ} exp(τ[φ]x) dτ = a₀ I + a₁ K + a₂ K²,  K = [φ]x, θ = |φ|, with
//   a₀ = (e^σ − 1)/σ,  a₁ = Im(z)/θ,  a₂ = (a₀ − Re(z))/θ²,  z = ∫₀¹ e^{(σ+iθ)τ} dτ
//      = (e^{σ+iθ} − 1)/(σ + iθ).
// e^{σ+iθ} − 1 is evaluated as expm1(σ)cos θ − 2 sin²(θ/2) + i e^σ sin θ, which keeps
// relative accuracy for small σ and θ; a₁K and a₂K² then carry only rounding-size
// absolute error even as θ → 0. Below θ = 1e-8 the θ → 0 limits
//   a₁ = ∫ e^{στ} τ dτ,  a₂ = ½ ∫ e^{στ} τ² dτ
// are used (relative error O(θ²) = 1e-16), by power series for |σ| < 1.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <omnidso/core/se3.hpp>

namespace omnidso {

template <typename T>
class Sim3 {
 public:
  using Scalar = T;
  using Quaternion = Eigen::Quaternion<T>;
  using Matrix3 = Eigen::Matrix<T, 3, 3>;
  using Matrix4 = Eigen::Matrix<T, 4, 4>;
  using Vector3 = Eigen::Matrix<T, 3, 1>;
  using Tangent = Eigen::Matrix<T, 7, 1>;
  static constexpr int kDoF = 7;

  Sim3() : q_(Quaternion::Identity()), t_(Vector3::Zero()), s_(T(1)) {}
  Sim3(T scale, const Quaternion& q, const Vector3& t) : q_(q.normalized()), t_(t), s_(scale) {}
  Sim3(T scale, const Matrix3& R, const Vector3& t)
      : q_(Quaternion(R).normalized()), t_(t), s_(scale) {}
  explicit Sim3(const SE3<T>& rigid) : q_(rigid.rotation()), t_(rigid.translation()), s_(T(1)) {}

  static Sim3 identity() { return Sim3(); }

  static Sim3 exp(const Tangent& xi) {
    using std::exp;
    const Vector3 rho = xi.template head<3>();
    const Vector3 phi = xi.template segment<3>(3);
    const T sigma = xi(6);
    return Sim3(exp(sigma), so3Exp(phi), matrixW(phi, sigma) * rho);
  }

  Tangent log() const {
    using std::log;
    Tangent xi;
    const Vector3 phi = so3Log(q_);
    const T sigma = log(s_);
    // W is invertible for |θ| ≤ π: its eigenvalues are a₀ and (e^{σ±iθ} − 1)/(σ ± iθ).
    xi.template head<3>() = matrixW(phi, sigma).inverse() * t_;
    xi.template segment<3>(3) = phi;
    xi(6) = sigma;
    return xi;
  }

  // (s₁,R₁,t₁)(s₂,R₂,t₂) = (s₁s₂, R₁R₂, s₁R₁t₂ + t₁).
  Sim3 operator*(const Sim3& other) const {
    return Sim3(s_ * other.s_, q_ * other.q_, s_ * (q_ * other.t_) + t_);
  }
  // (s,R,t)⁻¹ = (1/s, Rᵀ, −Rᵀt/s).
  Sim3 inverse() const {
    const Quaternion q_inv = q_.conjugate();
    return Sim3(T(1) / s_, q_inv, -(q_inv * t_) / s_);
  }
  Vector3 operator*(const Vector3& p) const { return s_ * (q_ * p) + t_; }
  // Applied to a pose T = (R_T, t_T) from the left: S·T = (R R_T, s R t_T + t), a rigid
  // pose again (the scale acts on positions only) — how an aligned trajectory is formed.
  SE3<T> operator*(const SE3<T>& pose) const {
    return SE3<T>(q_ * pose.rotation(), s_ * (q_ * pose.translation()) + t_);
  }

  T scale() const { return s_; }
  const Quaternion& rotation() const { return q_; }
  Matrix3 rotationMatrix() const { return q_.toRotationMatrix(); }
  const Vector3& translation() const { return t_; }
  Matrix4 matrix() const {
    Matrix4 m = Matrix4::Identity();
    m.template topLeftCorner<3, 3>() = s_ * rotationMatrix();
    m.template topRightCorner<3, 1>() = t_;
    return m;
  }

  template <typename U>
  Sim3<U> cast() const {
    return Sim3<U>(U(s_), q_.template cast<U>(), t_.template cast<U>());
  }

  // W(φ, σ) of the exponential (see the file comment for the formulas).
  static Matrix3 matrixW(const Vector3& phi, T sigma) {
    using std::abs;
    using std::cos;
    using std::exp;
    using std::expm1;
    using std::sin;
    using std::sqrt;
    const T theta = sqrt(phi.squaredNorm());
    const T a0 = abs(sigma) < T(1e-8) ? T(1) + sigma / T(2) : expm1(sigma) / sigma;
    T a1, a2;
    if (theta < T(1e-8)) {
      a1 = momentOfExp(sigma, 1);
      a2 = momentOfExp(sigma, 2) / T(2);
    } else {
      const T half_sin = sin(theta / T(2));
      const T z_num_re = expm1(sigma) * cos(theta) - T(2) * half_sin * half_sin;
      const T z_num_im = exp(sigma) * sin(theta);
      const T denom = sigma * sigma + theta * theta;
      // (z_num_re + i z_num_im) / (σ + iθ)
      const T z_re = (z_num_re * sigma + z_num_im * theta) / denom;
      const T z_im = (z_num_im * sigma - z_num_re * theta) / denom;
      a1 = z_im / theta;
      a2 = (a0 - z_re) / (theta * theta);
    }
    const Matrix3 K = skew(phi);
    return a0 * Matrix3::Identity() + a1 * K + a2 * K * K;
  }

 private:
  // ∫₀¹ e^{στ} τⁿ dτ for n = 1, 2. For |σ| < 1 the series Σ_k σᵏ/(k!(k+n+1)) (30 terms
  // leave < 1/30! ≈ 4e-33); otherwise the closed forms, which do not cancel there.
  static T momentOfExp(T sigma, int n) {
    using std::abs;
    using std::exp;
    if (abs(sigma) < T(1)) {
      T sum(0), power(1);  // power = σᵏ/k!
      for (int k = 0; k < 30; ++k) {
        sum += power / T(k + n + 1);
        power *= sigma / T(k + 1);
      }
      return sum;
    }
    const T e = exp(sigma);
    if (n == 1) return (e * (sigma - T(1)) + T(1)) / (sigma * sigma);
    return (e * (sigma * sigma - T(2) * sigma + T(2)) - T(2)) / (sigma * sigma * sigma);
  }

  Quaternion q_;
  Vector3 t_;
  T s_;
};

using Sim3d = Sim3<double>;
using Sim3f = Sim3<float>;

// Geodesic interpolation a·exp(u·log(a⁻¹ b)): u = 0 gives a, u = 1 gives b.
template <typename T>
Sim3<T> interpolate(const Sim3<T>& a, const Sim3<T>& b, T u) {
  return a * Sim3<T>::exp(u * (a.inverse() * b).log());
}

}  // namespace omnidso
