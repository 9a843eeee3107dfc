#pragma once
// FOV ("ATAN") camera model of Devernay & Faugeras (2001, "Straight lines have to be
// straight", the field-of-view model r_d = atan(2 r_u tan(ω/2))/ω): the model of DSO's
// camera.txt with 5 numbers and of the TUM monoVO dataset; Kalibr's pinhole camera with
// distortion_model "fov".
//
// Parameters [fx, fy, cx, cy, ω], 0 < ω < π (Camera::create); k = 2·tan(ω/2).
//   project:   r = √(x² + y²),  φ = atan2(k·r, z),  r_d = φ/ω,
//              u = fx·(r_d/r)·x + cx,  v = fy·(r_d/r)·y + cy
//              (for z > 0, φ = atan(2·r_u·tan(ω/2)) with r_u = r/z: the paper's r_d; atan2
//              extends it beyond 90° from the axis)
//   unproject: m = ((u−cx)/fx, (v−cy)/fy),  r_d = |m|,  φ = ω·r_d (< π, else false),
//              θ = atan2(sin φ, k·cos φ),  bearing = [sin θ · m/r_d, cos θ]
//              With E = √(sin²φ + k²cos²φ): sin θ = sin φ/E, cos θ = k·cos φ/E, so
//              bearing = [ω·sinc φ · m, k·cos φ]/E (sin φ/r_d = ω·sinc φ) needs no sin θ, cos θ.
// Domain: ρ = |p| > 0 and φ < π (every direction but straight behind). On the unit sphere
// dφ/dθ = k/(cos²θ + k²sin²θ) > 0: the image radius grows on all of [0, π) and never folds,
// so maxAngleFromAxis() is π, as for a KB4 lens without a fold.
// Near the optical axis (r → 0) the ratios are written with D = √(k²r² + z²), sin φ = k·r/D,
// cos φ = z/D, sinc φ = sin φ/φ and h(φ) = (φ − sin φ cos φ)/φ³ (angle_ratios.hpp), so that
// they stay exact at r = 0:
//   r_d/r = φ/(ω·r) = k/(ω·D·sinc φ)          → k/(ω·z) on the axis,
//   sin θ/r_d = ω·sinc φ/E                    → ω/k.
// As ω → 0, k/ω = 1 + ω²/12 + O(ω⁴) → 1: both are the pinhole's 1/z and 1/√(1 + r_d²), and
// the model tends to the pinhole model (r_d = r_u(1 + ω²/12) − ω²r_u³/3 + O(ω⁴)). ω itself
// must be > 0 (the formula divides by it). ∂/∂ω divides an O(ω) difference by ω: for ω below
// ~1e-4 that column carries an absolute error ~ε/ω (the values stay exact).
// For ceres::Jet the derivative of r = √(x² + y²) is undefined at r = 0 exactly (and that of
// r_d = |m| at the principal point); keep Jet evaluations off the exact axis.

#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>
#include <omnidso/cameras/angle_ratios.hpp>
#include <array>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class FovCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 5;
  static constexpr const char* kName = "fov";
  static constexpr std::array<const char*, kNumParams> kParamNames = {"fx", "fy", "cx", "cy",
                                                                     "w"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;

  // ω = 1 rad (a 1-rad lens); ω = 0 is not a camera.
  FovCamera() { params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0), Scalar(1); }
  explicit FovCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }
  Scalar omega() const { return params_[4]; }

  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    using std::atan2;
    using std::sqrt;
    using std::tan;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& omega = params_[4];
    const Scalar t = tan(omega / Scalar(2));
    const Scalar k = Scalar(2) * t;
    const Scalar r2 = p.x() * p.x() + p.y() * p.y();
    const Scalar r = sqrt(r2);
    const Scalar kr = k * r;
    const Scalar phi = atan2(kr, p.z());
    // φ < π excludes the ray straight behind the camera (r = 0, z < 0), imaged on a circle.
    if (!(r2 + p.z() * p.z() > Scalar(0) && phi < Scalar(M_PI))) return false;
    const Scalar D2 = kr * kr + p.z() * p.z();
    const Scalar D = sqrt(D2);
    const Scalar sin_phi = kr / D;  // saves a call to sin
    const Scalar sc = sinc(phi, sin_phi);
    const Scalar inv_omega = Scalar(1) / omega;
    const Scalar inv_D_sinc = Scalar(1) / (D * sc);
    const Scalar a = k * inv_omega * inv_D_sinc;  // = r_d/r
    // Row by row, not `uv << u, v`: GCC 12.2 at -O3 drops the row change of a comma
    // initialiser here when two projections are inlined into one caller (the second call's
    // v and the Jacobians' second rows kept the first call's values; clang, -O2 and
    // -fno-ipa-modref are right). Hence no multi-row comma initialiser in this file.
    uv.x() = fx * a * p.x() + params_[2];
    uv.y() = fy * a * p.y() + params_[3];

    if (d_uv_d_p) {
      // a(r, z) = φ/(ω r) with ∂φ/∂r = k z/D², ∂φ/∂z = −k r/D². ∂a/∂x = x·G with
      // G = (k z r/D² − φ)/(ω r³); k z r/D² = sin φ cos φ and r = D sin φ/k turn it into
      // G = −k³ h(φ)/(ω D³ sinc³φ), h = (φ − sin φ cos φ)/φ³ (→ 2/3 on the axis).
      // ∂a/∂z = −k/(ω D²).
      const Scalar h = angleMinusSinCosOverCube(phi, sin_phi, p.z() / D);
      const Scalar G = -k * k * k * inv_omega * h * inv_D_sinc * inv_D_sinc * inv_D_sinc;
      const Scalar da_dz = -k * inv_omega / D2;
      d_uv_d_p->row(0) << fx * (a + p.x() * p.x() * G), fx * p.x() * p.y() * G,
          fx * p.x() * da_dz;
      d_uv_d_p->row(1) << fy * p.x() * p.y() * G, fy * (a + p.y() * p.y() * G),
          fy * p.y() * da_dz;
    }
    if (d_uv_d_params) {
      // ∂φ/∂k = r z/D² and dk/dω = 1 + t², so ∂a/∂ω = ((1 + t²) z/D² − a)/ω.
      const Scalar da_domega = ((Scalar(1) + t * t) * p.z() / D2 - a) * inv_omega;
      d_uv_d_params->row(0) << a * p.x(), Scalar(0), Scalar(1), Scalar(0),
          fx * p.x() * da_domega;
      d_uv_d_params->row(1) << Scalar(0), a * p.y(), Scalar(0), Scalar(1),
          fy * p.y() * da_domega;
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    using std::tan;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar& omega = params_[4];
    const Scalar mx = (uv.x() - params_[2]) / fx;
    const Scalar my = (uv.y() - params_[3]) / fy;
    const Scalar rd2 = mx * mx + my * my;
    const Scalar phi = omega * sqrt(rd2);
    // φ ≥ π lies outside the image circle of the sphere (r_d = π/ω is straight behind).
    if (!(phi < Scalar(M_PI))) return false;
    const Scalar t = tan(omega / Scalar(2));
    const Scalar k = Scalar(2) * t;
    const Scalar sin_phi = sin(phi);
    const Scalar cos_phi = cos(phi);
    const Scalar sc = sinc(phi, sin_phi);
    const Scalar E2 = sin_phi * sin_phi + k * k * cos_phi * cos_phi;
    const Scalar inv_E = Scalar(1) / sqrt(E2);
    const Scalar s = omega * sc * inv_E;  // = sin θ/r_d
    const Scalar c = k * cos_phi * inv_E;  // = cos θ
    bearing = Vec3(s * mx, s * my, c);  // not a comma initialiser: see project()

    if (d_bearing_d_uv || d_bearing_d_params) {
      // dθ/dr_d = ω·∂θ/∂φ = ω k/E². With s(r_d) = sin θ/r_d: ∂(s m)/∂m = s I + g m mᵀ,
      // g = s'/r_d = (cos θ θ' r_d − sin θ)/r_d³ = ω³ (k² cos φ h(φ) − sinc³φ)/E³ after
      // φ − sin φ cos φ = φ³ h(φ) and r_d = φ/ω. ∂cos θ/∂m = −sin θ θ'/r_d m = −s ω k/E² m.
      const Scalar inv_E2 = inv_E * inv_E;
      const Scalar h = angleMinusSinCosOverCube(phi, sin_phi, cos_phi);
      const Scalar g =
          omega * omega * omega * (k * k * cos_phi * h - sc * sc * sc) * inv_E2 * inv_E;
      const Scalar dc = -s * omega * k * inv_E2;
      Mat32 d_b_d_m;
      d_b_d_m.row(0) << s + g * mx * mx, g * mx * my;
      d_b_d_m.row(1) << g * mx * my, s + g * my * my;
      d_b_d_m.row(2) << dc * mx, dc * my;
      chainAffineIntrinsics(d_b_d_m, Vec2(mx, my), fx, fy, d_bearing_d_uv, d_bearing_d_params);
      if (d_bearing_d_params) {
        // At fixed m: ∂θ/∂φ = k/E², ∂θ/∂k = −sin φ cos φ/E², dk/dω = 1 + t², so
        // dθ/dω = r_d q with q = (k − (1 + t²) ω sinc φ cos φ)/E². Then
        // ∂(s m)/∂ω = m cos θ (dθ/dω)/r_d = c q m and ∂cos θ/∂ω = −sin θ dθ/dω = −s r_d² q.
        const Scalar q = (k - (Scalar(1) + t * t) * omega * sc * cos_phi) * inv_E2;
        d_bearing_d_params->col(4) = Vec3(c * q * mx, c * q * my, -s * rd2 * q);
      }
    }
    return true;
  }

  // Every direction with θ < π projects (the header's dφ/dθ > 0): the domain is the sphere
  // without the ray straight behind, as KB4 without a fold.
  Scalar maxAngleFromAxis() const { return Scalar(M_PI); }

  template <typename U>
  FovCamera<U> cast() const {
    return FovCamera<U>(params_.template cast<U>());
  }

 private:
  VecN params_;
};

}  // namespace omnidso
