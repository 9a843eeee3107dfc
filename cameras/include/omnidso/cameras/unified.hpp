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
// With ξ = 0 the model is the pinhole model.
//
// The α-form used by basalt and Kalibr's "eucm" family, α = ξ/(1+ξ), f_α = f_ξ/(1+ξ),
// describes the same projection; see unifiedFromAlphaForm().

#include <array>
#include <cmath>
#include <Eigen/Core>

namespace omnidso {

template <typename Scalar_ = double>
class UnifiedCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 5;
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

  // Projects a 3D point in camera coordinates. Returns false outside the model's domain
  // (the outputs are still written where they are finite). Jacobians are optional.
  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& xi = params_[4];
    const Scalar rho = sqrt(p.squaredNorm());
    const Scalar D = p.z() + xi * rho;
    const bool valid = rho > Scalar(0) && p.z() > -domainW() * rho && D > Scalar(0);
    if (!valid) return false;

    const Scalar inv_D = Scalar(1) / D;
    const Scalar mx = p.x() * inv_D;
    const Scalar my = p.y() * inv_D;
    uv << fx * mx + cx, fy * my + cy;

    if (d_uv_d_p) {
      // ∂D/∂p = ξ p/ρ + e_z;  ∂m/∂p = (I₂|0)/D − m ∂D/∂p / D
      const Vec3 dD_dp(xi * p.x() / rho, xi * p.y() / rho, Scalar(1) + xi * p.z() / rho);
      Mat23& J = *d_uv_d_p;
      J(0, 0) = fx * (inv_D - mx * dD_dp.x() * inv_D);
      J(0, 1) = -fx * mx * dD_dp.y() * inv_D;
      J(0, 2) = -fx * mx * dD_dp.z() * inv_D;
      J(1, 0) = -fy * my * dD_dp.x() * inv_D;
      J(1, 1) = fy * (inv_D - my * dD_dp.y() * inv_D);
      J(1, 2) = -fy * my * dD_dp.z() * inv_D;
    }
    if (d_uv_d_params) {
      Mat2N& J = *d_uv_d_params;
      J.setZero();
      J(0, 0) = mx;
      J(1, 1) = my;
      J(0, 2) = Scalar(1);
      J(1, 3) = Scalar(1);
      // ∂m/∂ξ = −m ρ / D
      J(0, 4) = -fx * mx * rho * inv_D;
      J(1, 4) = -fy * my * rho * inv_D;
    }
    return true;
  }

  // Unprojects a pixel to a unit bearing (eq. 4 with d = 1). Returns false where the
  // pixel lies outside the model's image of the sphere.
  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& cx = params_[2];
    const Scalar& cy = params_[3];
    const Scalar& xi = params_[4];
    const Scalar mx = (uv.x() - cx) / fx;
    const Scalar my = (uv.y() - cy) / fy;
    const Scalar r2 = mx * mx + my * my;
    const Scalar disc = Scalar(1) + (Scalar(1) - xi * xi) * r2;
    if (disc < Scalar(0)) return false;
    const Scalar s = sqrt(disc);
    const Scalar inv_r2p1 = Scalar(1) / (r2 + Scalar(1));
    const Scalar k = (xi + s) * inv_r2p1;
    bearing << k * mx, k * my, k - xi;
    // Points past the fold (ξ > 1) are not images of the projectable half: reject them.
    if (bearing.z() <= -domainW()) return false;

    if (d_bearing_d_uv || d_bearing_d_params) {
      // dk/dr² = ((1−ξ²)/(2s) − k) / (r² + 1)
      const Scalar dk_dr2 = ((Scalar(1) - xi * xi) / (Scalar(2) * s) - k) * inv_r2p1;
      // ∂bearing/∂(mx, my)
      Eigen::Matrix<Scalar, 3, 2> d_b_d_m;
      const Scalar dk_dmx = dk_dr2 * Scalar(2) * mx;
      const Scalar dk_dmy = dk_dr2 * Scalar(2) * my;
      d_b_d_m << k + mx * dk_dmx, mx * dk_dmy, my * dk_dmx, k + my * dk_dmy, dk_dmx, dk_dmy;
      if (d_bearing_d_uv) {
        d_bearing_d_uv->col(0) = d_b_d_m.col(0) / fx;
        d_bearing_d_uv->col(1) = d_b_d_m.col(1) / fy;
      }
      if (d_bearing_d_params) {
        Mat3N& J = *d_bearing_d_params;
        // mx = (u − cx)/fx: ∂mx/∂fx = −mx/fx, ∂mx/∂cx = −1/fx (likewise y).
        J.col(0) = -d_b_d_m.col(0) * mx / fx;
        J.col(1) = -d_b_d_m.col(1) * my / fy;
        J.col(2) = -d_b_d_m.col(0) / fx;
        J.col(3) = -d_b_d_m.col(1) / fy;
        // ∂k/∂ξ = (1 − ξ r²/s)/(r² + 1); bearing_z also carries −ξ.
        const Scalar dk_dxi = (Scalar(1) - xi * r2 / s) * inv_r2p1;
        J.col(4) << dk_dxi * mx, dk_dxi * my, dk_dxi - Scalar(1);
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
