#pragma once
// Extended unified camera model (EUCM, Khomutenko, Garcia, Martinet 2016).
//
// Parameters [fx, fy, cx, cy, α, β]   (α ∈ [0, 1], β > 0).
//   project:   d = √(β(x² + y²) + z²),  D = α d + (1−α) z,
//              u = fx·x/D + cx,  v = fy·y/D + cy
//   unproject: mx = (u−cx)/fx, my = (v−cy)/fy, r² = mx² + my²,
//              s = √(1 − (2α−1) β r²),  mz = (1 − β α² r²) / (α s + 1 − α),
//              bearing = [mx, my, mz] / ‖[mx, my, mz]‖
// Derivation of the unprojection: scale the point so that D = 1; then (x, y) = (mx, my) and
// α d = 1 − (1−α) z, squared: (2α−1) z² + 2(1−α) z + (α²β r² − 1) = 0, whose root through
// z = 1 at r = 0 is the mz above (rationalised so that α = ½ needs no special case).
//
// Domain. With ρ' = √β·√(x² + y²) the model is UCM in α-form (ξ = α/(1−α)) applied to the
// plane point (ρ', z), whose norm is d. So the UCM domain carries over with ‖x‖ → d:
//   z > −w d,   w = α/(1−α) for α ≤ ½ (there D > 0 is the binding condition),
//               w = (1−α)/α for α > ½ (the image radius folds back: ∂r/∂θ = 0).
// For α > ½, z > −w d also implies D ≥ d (2α−1)/α > 0. In terms of the angle θ from the
// axis: cos θ_max = −w√β / √(w²β + 1 − w²).
// A pixel unprojects where (2α−1) β r² < 1 (always for α ≤ ½).
// With β = 1 the model is UCM in α-form: unifiedFromAlphaForm(fx, fy, cx, cy, α).

#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>
#include <array>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class ExtendedUnifiedCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 6;
  static constexpr const char* kName = "eucm";
  static constexpr std::array<const char*, kNumParams> kParamNames = {"fx", "fy", "cx",
                                                                     "cy", "alpha", "beta"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;

  ExtendedUnifiedCamera() {
    params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0), Scalar(0), Scalar(1);
  }
  explicit ExtendedUnifiedCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }

  // The w of the domain test z > −w d (see the header comment).
  Scalar domainW() const {
    const Scalar& alpha = params_[4];
    return alpha <= Scalar(0.5) ? alpha / (Scalar(1) - alpha) : (Scalar(1) - alpha) / alpha;
  }

  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& alpha = params_[4];
    const Scalar& beta = params_[5];
    const Scalar r2 = p.x() * p.x() + p.y() * p.y();
    const Scalar d = sqrt(beta * r2 + p.z() * p.z());
    if (!(d > Scalar(0) && p.z() > -domainW() * d)) return false;
    const Scalar D = alpha * d + (Scalar(1) - alpha) * p.z();
    const Scalar inv_D = Scalar(1) / D;
    const Scalar mx = p.x() * inv_D;
    const Scalar my = p.y() * inv_D;
    uv << fx * mx + params_[2], fy * my + params_[3];

    if (d_uv_d_p) {
      // ∂d/∂p = (βx, βy, z)/d;  ∂D/∂p = α ∂d/∂p + (1−α) e_z;  ∂m/∂p = ((I₂|0) − m ∂D/∂pᵀ)/D
      const Scalar a_over_d = alpha / d;
      const Vec3 dD_dp(a_over_d * beta * p.x(), a_over_d * beta * p.y(),
                       a_over_d * p.z() + Scalar(1) - alpha);
      Mat23& J = *d_uv_d_p;
      J << fx * inv_D, Scalar(0), Scalar(0), Scalar(0), fy * inv_D, Scalar(0);
      J.row(0) -= (fx * mx * inv_D) * dD_dp.transpose();
      J.row(1) -= (fy * my * inv_D) * dD_dp.transpose();
    }
    if (d_uv_d_params) {
      // ∂D/∂α = d − z,  ∂D/∂β = α r² / (2d);  ∂m/∂θ = −m ∂D/∂θ / D
      const Scalar dm_dalpha = -(d - p.z()) * inv_D;
      const Scalar dm_dbeta = -alpha * r2 / (Scalar(2) * d) * inv_D;
      *d_uv_d_params << mx, Scalar(0), Scalar(1), Scalar(0), fx * mx * dm_dalpha,
          fx * mx * dm_dbeta,  //
          Scalar(0), my, Scalar(0), Scalar(1), fy * my * dm_dalpha, fy * my * dm_dbeta;
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& alpha = params_[4];
    const Scalar& beta = params_[5];
    const Scalar mx = (uv.x() - params_[2]) / fx;
    const Scalar my = (uv.y() - params_[3]) / fy;
    const Scalar r2 = mx * mx + my * my;
    const Scalar two_alpha_m1 = Scalar(2) * alpha - Scalar(1);
    const Scalar s2 = Scalar(1) - two_alpha_m1 * beta * r2;
    if (!(s2 > Scalar(0))) return false;
    const Scalar s = sqrt(s2);
    const Scalar num = Scalar(1) - beta * alpha * alpha * r2;
    const Scalar den = alpha * s + Scalar(1) - alpha;
    const Scalar mz = num / den;
    const Vec3 h(mx, my, mz);
    const Scalar inv_norm = Scalar(1) / sqrt(h.squaredNorm());
    bearing = h * inv_norm;

    if (d_bearing_d_uv || d_bearing_d_params) {
      // bearing = h/‖h‖: ∂bearing/∂h = (I − b bᵀ)/‖h‖.
      const Eigen::Matrix<Scalar, 3, 3> P =
          (Eigen::Matrix<Scalar, 3, 3>::Identity() - bearing * bearing.transpose()) * inv_norm;
      // mz = num/den: ∂mz/∂r² = (num' den − num den')/den², num' = −βα², den' = α s'(r²),
      // s'(r²) = −(2α−1)β/(2s).
      const Scalar inv_den = Scalar(1) / den;
      const Scalar ds_dr2 = -two_alpha_m1 * beta / (Scalar(2) * s);
      const Scalar dmz_dr2 = (-beta * alpha * alpha - mz * alpha * ds_dr2) * inv_den;
      // ∂bearing/∂(mx, my) = P [e_x + 2mx mz' e_z, e_y + 2my mz' e_z]
      Mat32 d_b_d_m;
      d_b_d_m.col(0) = P.col(0) + P.col(2) * (Scalar(2) * mx * dmz_dr2);
      d_b_d_m.col(1) = P.col(1) + P.col(2) * (Scalar(2) * my * dmz_dr2);
      chainAffineIntrinsics(d_b_d_m, Vec2(mx, my), fx, fy, d_bearing_d_uv, d_bearing_d_params);
      if (d_bearing_d_params) {
        Mat3N& J = *d_bearing_d_params;
        // ∂s/∂α = −β r²/s,  ∂s/∂β = −(2α−1) r²/(2s)
        const Scalar ds_dalpha = -beta * r2 / s;
        const Scalar ds_dbeta = -two_alpha_m1 * r2 / (Scalar(2) * s);
        const Scalar dnum_dalpha = -Scalar(2) * beta * alpha * r2;
        const Scalar dnum_dbeta = -alpha * alpha * r2;
        const Scalar dden_dalpha = s + alpha * ds_dalpha - Scalar(1);
        const Scalar dden_dbeta = alpha * ds_dbeta;
        const Scalar dmz_dalpha = (dnum_dalpha - mz * dden_dalpha) * inv_den;
        const Scalar dmz_dbeta = (dnum_dbeta - mz * dden_dbeta) * inv_den;
        J.col(4) = P.col(2) * dmz_dalpha;
        J.col(5) = P.col(2) * dmz_dbeta;
      }
    }
    return true;
  }

  // Largest angle between a projectable ray and the optical axis (radians).
  Scalar maxAngleFromAxis() const {
    using std::acos;
    using std::sqrt;
    const Scalar w = domainW();
    const Scalar& beta = params_[5];
    return acos(-w * sqrt(beta) / sqrt(w * w * beta + Scalar(1) - w * w));
  }

  template <typename U>
  ExtendedUnifiedCamera<U> cast() const {
    return ExtendedUnifiedCamera<U>(params_.template cast<U>());
  }

 private:
  VecN params_;
};

}  // namespace omnidso
