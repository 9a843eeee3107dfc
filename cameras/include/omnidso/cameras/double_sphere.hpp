#pragma once
// Double Sphere camera model (Usenko, Demmel, Cremers 2018, eq. 40–47 of that paper).
//
// Parameters [fx, fy, cx, cy, ξ, α]   (ξ > −1, α ∈ [0, 1]).
//   project:   d1 = ‖x‖,  k = ξ d1 + z,  d2 = √(x² + y² + k²),  D = α d2 + (1−α) k,
//              u = fx·x/D + cx,  v = fy·y/D + cy
//   unproject: mx = (u−cx)/fx, my = (v−cy)/fy, r² = mx² + my²,
//              mz = (1 − α² r²) / (α √(1 − (2α−1) r²) + 1 − α),
//              bearing = (mz ξ + √(mz² + (1−ξ²) r²)) / (mz² + r²) · [mx, my, mz] − [0, 0, ξ]
//              (a unit vector by construction)
// Domain (derived here; it differs from the w2 = (w1 + ξ)/√(2w1ξ + ξ² + 1) printed in the
// paper, which is not where the image folds: for ξ = −0.18, α = 0.59 that formula stops at
// 125.6° while ∂r/∂θ reaches zero at 126.6°, the w2 below). The model is UCM with ξ taking
// the unit bearing b to q = b + ξ e_z, followed by UCM in α-form on q, whose domain is
// q_z > −w1‖q‖ with w1 = α/(1−α) for α ≤ ½, (1−α)/α otherwise (see extended_unified.hpp).
// The boundary point q = t (√(1−w1²), −w1), t = ‖q‖, lies on the unit sphere around ξ e_z:
// t² + 2 w1 ξ t + ξ² − 1 = 0, t = −w1 ξ + √(1 − ξ² + w1² ξ²), hence
//   z > −w2 d1,   w2 = w1 t + ξ                                  (for ξ ≤ 1)
// For ξ > 1 that boundary is never reached, and the first stage folds first (UCM with ξ > 1):
// w2 = 1/ξ. For |ξ| ≤ 1 the direction of q turns monotonically with b, so the domain is
// exactly the set where the image radius still grows with the angle from the axis.
// A pixel unprojects where (2α−1) r² < 1 and mz² + (1−ξ²) r² > 0.
// With ξ = 0 the model is UCM in α-form: unifiedFromAlphaForm(fx, fy, cx, cy, α).

#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>
#include <array>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class DoubleSphereCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 6;
  static constexpr const char* kName = "ds";
  static constexpr std::array<const char*, kNumParams> kParamNames = {"fx", "fy", "cx",
                                                                     "cy", "xi", "alpha"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;

  DoubleSphereCamera() {
    params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0), Scalar(0), Scalar(0);
  }
  explicit DoubleSphereCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }

  // The w2 of the domain test z > −w2 ‖x‖ (see the header comment).
  Scalar domainW() const {
    using std::sqrt;
    const Scalar& xi = params_[4];
    const Scalar& alpha = params_[5];
    if (xi > Scalar(1)) return Scalar(1) / xi;
    const Scalar w1 =
        alpha <= Scalar(0.5) ? alpha / (Scalar(1) - alpha) : (Scalar(1) - alpha) / alpha;
    const Scalar t = -w1 * xi + sqrt(Scalar(1) - xi * xi + w1 * w1 * xi * xi);
    return w1 * t + xi;
  }

  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& xi = params_[4];
    const Scalar& alpha = params_[5];
    const Scalar r2 = p.x() * p.x() + p.y() * p.y();
    const Scalar d1 = sqrt(r2 + p.z() * p.z());
    if (!(d1 > Scalar(0) && p.z() > -domainW() * d1)) return false;
    const Scalar k = xi * d1 + p.z();
    const Scalar d2 = sqrt(r2 + k * k);
    const Scalar D = alpha * d2 + (Scalar(1) - alpha) * k;
    if (!(D > Scalar(0))) return false;
    const Scalar inv_D = Scalar(1) / D;
    const Scalar mx = p.x() * inv_D;
    const Scalar my = p.y() * inv_D;
    uv << fx * mx + params_[2], fy * my + params_[3];

    if (d_uv_d_p) {
      // ∂k/∂p = ξ p/d1 + e_z;  ∂d2/∂p = ((x, y, 0) + k ∂k/∂p)/d2;
      // ∂D/∂p = α ∂d2/∂p + (1−α) ∂k/∂p;  ∂m/∂p = ((I₂|0) − m ∂D/∂pᵀ)/D
      const Vec3 dk_dp = p * (xi / d1) + Vec3(Scalar(0), Scalar(0), Scalar(1));
      const Scalar inv_d2 = Scalar(1) / d2;
      const Vec3 dd2_dp =
          (Vec3(p.x(), p.y(), Scalar(0)) + k * dk_dp) * inv_d2;
      const Vec3 dD_dp = alpha * dd2_dp + (Scalar(1) - alpha) * dk_dp;
      Mat23& J = *d_uv_d_p;
      J << fx * inv_D, Scalar(0), Scalar(0), Scalar(0), fy * inv_D, Scalar(0);
      J.row(0) -= (fx * mx * inv_D) * dD_dp.transpose();
      J.row(1) -= (fy * my * inv_D) * dD_dp.transpose();
    }
    if (d_uv_d_params) {
      // ∂D/∂ξ = α k d1/d2 + (1−α) d1,  ∂D/∂α = d2 − k;  ∂m/∂θ = −m ∂D/∂θ / D
      const Scalar dm_dxi = -(alpha * k / d2 + Scalar(1) - alpha) * d1 * inv_D;
      const Scalar dm_dalpha = -(d2 - k) * inv_D;
      *d_uv_d_params << mx, Scalar(0), Scalar(1), Scalar(0), fx * mx * dm_dxi,
          fx * mx * dm_dalpha,  //
          Scalar(0), my, Scalar(0), Scalar(1), fy * my * dm_dxi, fy * my * dm_dalpha;
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& xi = params_[4];
    const Scalar& alpha = params_[5];
    const Scalar mx = (uv.x() - params_[2]) / fx;
    const Scalar my = (uv.y() - params_[3]) / fy;
    const Scalar r2 = mx * mx + my * my;
    const Scalar two_alpha_m1 = Scalar(2) * alpha - Scalar(1);
    const Scalar s2 = Scalar(1) - two_alpha_m1 * r2;
    if (!(s2 > Scalar(0))) return false;
    const Scalar s = sqrt(s2);
    // Second stage inverse (EUCM with β = 1): point on the sphere around ξ e_z.
    const Scalar num = Scalar(1) - alpha * alpha * r2;
    const Scalar den = alpha * s + Scalar(1) - alpha;
    const Scalar inv_den = Scalar(1) / den;
    const Scalar mz = num * inv_den;
    // First stage inverse (UCM with ξ): back to the unit sphere around the centre.
    const Scalar t2 = mz * mz + (Scalar(1) - xi * xi) * r2;
    if (!(t2 > Scalar(0))) return false;
    const Scalar t = sqrt(t2);
    const Scalar q2 = mz * mz + r2;
    const Scalar inv_q2 = Scalar(1) / q2;
    const Scalar c = (mz * xi + t) * inv_q2;
    bearing << c * mx, c * my, c * mz - xi;
    if (!(bearing.z() > -domainW())) return false;

    if (d_bearing_d_uv || d_bearing_d_params) {
      // mz(r², α): ∂mz/∂r² = (−α² − mz α s'(r²))/den, s'(r²) = −(2α−1)/(2s).
      const Scalar dmz_dr2 = (-alpha * alpha + mz * alpha * two_alpha_m1 / (Scalar(2) * s)) *
                             inv_den;
      // c(mz, r², ξ) = (mz ξ + t)/q2 with t² = mz² + (1−ξ²) r², q2 = mz² + r²:
      const Scalar dc_dmz = ((xi + mz / t) - c * Scalar(2) * mz) * inv_q2;
      const Scalar dc_dr2_explicit = ((Scalar(1) - xi * xi) / (Scalar(2) * t) - c) * inv_q2;
      const Scalar dc_dr2 = dc_dr2_explicit + dc_dmz * dmz_dr2;
      // bearing = c (mx, my, mz) − ξ e_z; mz and c depend on (mx, my) through r².
      Mat32 d_b_d_m;
      const Scalar two_mx = Scalar(2) * mx;
      const Scalar two_my = Scalar(2) * my;
      const Vec3 d_b_d_r2(mx * dc_dr2, my * dc_dr2, mz * dc_dr2 + c * dmz_dr2);
      d_b_d_m.col(0) = d_b_d_r2 * two_mx;
      d_b_d_m.col(1) = d_b_d_r2 * two_my;
      d_b_d_m(0, 0) += c;
      d_b_d_m(1, 1) += c;
      chainAffineIntrinsics(d_b_d_m, Vec2(mx, my), fx, fy, d_bearing_d_uv, d_bearing_d_params);
      if (d_bearing_d_params) {
        Mat3N& J = *d_bearing_d_params;
        // ∂c/∂ξ = (mz − ξ r²/t)/q2;  ∂bearing/∂ξ = c_ξ (mx, my, mz) − e_z
        const Scalar dc_dxi = (mz - xi * r2 / t) * inv_q2;
        J.col(4) << dc_dxi * mx, dc_dxi * my, dc_dxi * mz - Scalar(1);
        // ∂mz/∂α = (−2α r² − mz (s + α s_α − 1))/den with s_α = −r²/s.
        const Scalar dmz_dalpha =
            (-Scalar(2) * alpha * r2 - mz * (s - alpha * r2 / s - Scalar(1))) * inv_den;
        const Scalar dc_dalpha = dc_dmz * dmz_dalpha;
        J.col(5) << dc_dalpha * mx, dc_dalpha * my, dc_dalpha * mz + c * dmz_dalpha;
      }
    }
    return true;
  }

  // Largest angle between a projectable ray and the optical axis (radians).
  Scalar maxAngleFromAxis() const {
    using std::acos;
    return acos(-domainW());
  }

  template <typename U>
  DoubleSphereCamera<U> cast() const {
    return DoubleSphereCamera<U>(params_.template cast<U>());
  }

 private:
  VecN params_;
};

}  // namespace omnidso
