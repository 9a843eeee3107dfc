#pragma once
// Unified omnidirectional camera model (UCM, Mei & Rives; paper eq. 2–4).
//
// Parameters [fx, fy, cx, cy, xi].
//   project:   D = z + ξ‖x‖,  u = fx·x/D + cx,  v = fy·y/D + cy                    (eq. 2)
//   unproject: ũ = (u−cx)/fx, ṽ = (v−cy)/fy, r² = ũ² + ṽ²,
//              k = (ξ + √(1 + (1−ξ²) r²)) / (r² + 1),
//              bearing = k·[ũ, ṽ, 1] − [0, 0, ξ]  (unit length)                    (eq. 4, d = 1)
// Domain: a point is projectable where z > −w‖x‖ with w = ξ for ξ ≤ 1 and w = 1/ξ for
// ξ > 1 (beyond that angle the image of a ray folds back: ∂r/∂θ = 0 at cos θ = −1/ξ).
// The largest angle from the optical axis is therefore acos(−w): 180° at ξ = 1, so a
// fisheye with ξ near 1 sees well beyond a 180° field of view, including points behind
// the camera (z < 0), which is why points carry inverse *distance* 1/‖x‖.
// A pixel is unprojectable where 1 + (1−ξ²) r² ≥ 0 (always for ξ ≤ 1).
// projectNormalised / unprojectNormalised expose the step to and from the normalised plane
// m = (x, y)/D for DistortedCamera (Mei's model = UCM + radial-tangential distortion).
// With ξ = 0 the model is the pinhole model.
//
// The α-form used by basalt and Kalibr's "eucm" family, α = ξ/(1+ξ), f_α = f_ξ/(1+ξ),
// describes the same projection; see unifiedFromAlphaForm().

#include <array>
#include <cmath>
#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>

namespace omnidso {

template <typename Scalar_ = double>
class UnifiedCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 5;
  // Parameters after [fx, fy, cx, cy] that act on the normalised plane: ξ.
  static constexpr int kNumExtraParams = kNumParams - 4;
  static constexpr const char* kName = "ucm";
  static constexpr std::array<const char*, kNumParams> kParamNames = {"fx", "fy", "cx", "cy",
                                                                     "xi"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;
  using Mat2E = Eigen::Matrix<Scalar, 2, kNumExtraParams>;
  using Mat3E = Eigen::Matrix<Scalar, 3, kNumExtraParams>;

  UnifiedCamera() { params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0), Scalar(0); }
  explicit UnifiedCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }
  Scalar xi() const { return params_[4]; }

  // The w of the domain test z > −w‖x‖ (see the header comment).
  Scalar domainW() const {
    const Scalar& xi = params_[4];
    return xi <= Scalar(1) ? xi : Scalar(1) / xi;
  }

  // m = (x, y)/D with D = z + ξ‖x‖ (eq. 2 without [fx, fy, cx, cy]). Returns false outside
  // the model's domain. d_m_d_extra is ∂m/∂ξ.
  bool projectNormalised(const Vec3& p, Vec2& m, Mat23* d_m_d_p = nullptr,
                         Mat2E* d_m_d_extra = nullptr) const {
    using std::sqrt;
    const Scalar& xi = params_[4];
    const Scalar rho = sqrt(p.squaredNorm());
    const Scalar D = p.z() + xi * rho;
    const bool valid = rho > Scalar(0) && p.z() > -domainW() * rho && D > Scalar(0);
    if (!valid) return false;
    const Scalar inv_D = Scalar(1) / D;
    m << p.x() * inv_D, p.y() * inv_D;
    if (d_m_d_p) {
      // ∂D/∂p = ξ p/ρ + e_z;  ∂m/∂p = (I₂|0)/D − m ∂D/∂pᵀ / D
      const Scalar xi_over_rho = xi / rho;
      const Vec3 dD_dp(xi_over_rho * p.x(), xi_over_rho * p.y(),
                       Scalar(1) + xi_over_rho * p.z());
      *d_m_d_p << inv_D, Scalar(0), Scalar(0), Scalar(0), inv_D, Scalar(0);
      d_m_d_p->noalias() -= (m * inv_D) * dD_dp.transpose();
    }
    // ∂m/∂ξ = −m ρ / D
    if (d_m_d_extra) *d_m_d_extra = -m * (rho * inv_D);
    return true;
  }

  // Lifts a normalised point to the unit sphere (eq. 4 with d = 1). Returns false where m
  // lies outside the model's image of the sphere. d_bearing_d_extra is ∂bearing/∂ξ.
  bool unprojectNormalised(const Vec2& m, Vec3& bearing, Mat32* d_bearing_d_m = nullptr,
                           Mat3E* d_bearing_d_extra = nullptr) const {
    using std::sqrt;
    const Scalar& xi = params_[4];
    const Scalar r2 = m.squaredNorm();
    const Scalar disc = Scalar(1) + (Scalar(1) - xi * xi) * r2;
    if (!(disc >= Scalar(0))) return false;
    const Scalar s = sqrt(disc);
    const Scalar inv_r2p1 = Scalar(1) / (r2 + Scalar(1));
    const Scalar k = (xi + s) * inv_r2p1;
    bearing << k * m.x(), k * m.y(), k - xi;
    // Points past the fold (ξ > 1) are not images of the projectable half: reject them.
    if (bearing.z() <= -domainW()) return false;
    if (d_bearing_d_m) {
      // dk/dr² = ((1−ξ²)/(2s) − k) / (r² + 1)
      const Scalar dk_dr2 = ((Scalar(1) - xi * xi) / (Scalar(2) * s) - k) * inv_r2p1;
      const Scalar dk_dmx = dk_dr2 * Scalar(2) * m.x();
      const Scalar dk_dmy = dk_dr2 * Scalar(2) * m.y();
      *d_bearing_d_m << k + m.x() * dk_dmx, m.x() * dk_dmy, m.y() * dk_dmx, k + m.y() * dk_dmy,
          dk_dmx, dk_dmy;
    }
    if (d_bearing_d_extra) {
      // ∂k/∂ξ = (1 − ξ r²/s)/(r² + 1); bearing_z also carries −ξ.
      const Scalar dk_dxi = (Scalar(1) - xi * r2 / s) * inv_r2p1;
      *d_bearing_d_extra << dk_dxi * m.x(), dk_dxi * m.y(), dk_dxi - Scalar(1);
    }
    return true;
  }

  // Projects a 3D point in camera coordinates. Returns false outside the model's domain.
  // Jacobians are optional.
  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    Vec2 m;
    Mat2E d_m_d_xi;
    if (!projectNormalised(p, m, d_uv_d_p, d_uv_d_params ? &d_m_d_xi : nullptr)) return false;
    uv << fx * m.x() + params_[2], fy * m.y() + params_[3];
    if (d_uv_d_p) {
      d_uv_d_p->row(0) *= fx;
      d_uv_d_p->row(1) *= fy;
    }
    if (d_uv_d_params) {
      Mat2N& J = *d_uv_d_params;
      J << m.x(), Scalar(0), Scalar(1), Scalar(0), fx * d_m_d_xi(0, 0),  //
          Scalar(0), m.y(), Scalar(0), Scalar(1), fy * d_m_d_xi(1, 0);
    }
    return true;
  }

  // Unprojects a pixel to a unit bearing (eq. 4 with d = 1). Returns false where the
  // pixel lies outside the model's image of the sphere.
  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Vec2 m((uv.x() - params_[2]) / fx, (uv.y() - params_[3]) / fy);
    const bool want_jacobian = d_bearing_d_uv || d_bearing_d_params;
    Mat32 d_b_d_m;
    Mat3E d_b_d_xi;
    if (!unprojectNormalised(m, bearing, want_jacobian ? &d_b_d_m : nullptr,
                             d_bearing_d_params ? &d_b_d_xi : nullptr)) {
      return false;
    }
    chainAffineIntrinsics(d_b_d_m, m, fx, fy, d_bearing_d_uv, d_bearing_d_params);
    if (d_bearing_d_params) d_bearing_d_params->col(4) = d_b_d_xi;
    return true;
  }

  // Largest angle between a projectable ray and the optical axis (radians).
  Scalar maxAngleFromAxis() const {
    using std::acos;
    return acos(-domainW());
  }

  template <typename U>
  UnifiedCamera<U> cast() const {
    return UnifiedCamera<U>(params_.template cast<U>());
  }

 private:
  VecN params_;
};

// UCM from the α-form [fx_α, fy_α, cx, cy, α] (α ∈ [0, 1)): ξ = α/(1−α), f_ξ = f_α/(1−α).
template <typename Scalar>
UnifiedCamera<Scalar> unifiedFromAlphaForm(Scalar fx_a, Scalar fy_a, Scalar cx, Scalar cy,
                                           Scalar alpha) {
  const Scalar one_minus = Scalar(1) - alpha;
  typename UnifiedCamera<Scalar>::VecN p;
  p << fx_a / one_minus, fy_a / one_minus, cx, cy, alpha / one_minus;
  return UnifiedCamera<Scalar>(p);
}

}  // namespace omnidso
