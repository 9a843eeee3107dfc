#pragma once
// Kannala–Brandt camera model with four radial terms (KB4, the "equidistant" model of Kalibr
// and cv::fisheye; Kannala & Brandt 2006).
//
// Parameters [fx, fy, cx, cy, k1, k2, k3, k4].
//   project:   r = √(x² + y²),  θ = atan2(r, z),
//              θd = θ (1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸) = θ P(θ),
//              u = fx·θd·x/r + cx,  v = fy·θd·y/r + cy
//   unproject: mx = (u−cx)/fx, my = (v−cy)/fy, θd = √(mx² + my²), solve θ P(θ) = θd for θ
//              by Newton's method (to machine precision), then
//              bearing = [sin θ · mx/θd, sin θ · my/θd, cos θ]
// Domain: 0 ≤ θ < θ_max, where θ_max is the first zero in (0, π) of
//   Q(θ) = dθd/dθ = 1 + 3k1θ² + 5k2θ⁴ + 7k3θ⁶ + 9k4θ⁸   (beyond it the image folds back),
// or π. project and unproject test Q(θ) > 0 at the point itself, which equals θ < θ_max
// when Q changes sign at most once on (0, π), as for every calibrated lens; the exact θ_max
// is maxAngleFromAxis().
// Near the optical axis (r → 0) the ratios θd/r, sin θ/θd and their derivatives are written
// in θ with sinc θ = sin θ/θ and the series of (θ − sin θ cos θ)/θ³ and
// (θ cos θ − sin θ)/θ³, so that they stay exact at r = 0 (their limits are those of the
// pinhole model). For ceres::Jet the derivative of r = √(x² + y²) is undefined at r = 0
// exactly; keep Jet evaluations off the exact axis.

#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>
#include <omnidso/cameras/angle_ratios.hpp>
#include <array>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class KannalaBrandtCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 8;
  static constexpr const char* kName = "kb4";
  static constexpr std::array<const char*, kNumParams> kParamNames = {
      "fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;

  KannalaBrandtCamera() {
    params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0), Scalar(0), Scalar(0), Scalar(0),
        Scalar(0);
  }
  explicit KannalaBrandtCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }

  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    using std::atan2;
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar r2 = p.x() * p.x() + p.y() * p.y();
    const Scalar rho2 = r2 + p.z() * p.z();
    const Scalar r = sqrt(r2);
    const Scalar theta = atan2(r, p.z());
    const Scalar t2 = theta * theta;
    const Scalar P = polyP(t2);
    const Scalar Q = polyQ(t2);
    // θ < π excludes the ray straight behind the camera (r = 0, z < 0), imaged on a circle.
    if (!(rho2 > Scalar(0) && theta < Scalar(M_PI) && Q > Scalar(0))) return false;
    const Scalar rho = sqrt(rho2);
    // sin θ = r/ρ saves a call to sin.
    const Scalar sc = sinc(theta, r / rho);
    const Scalar inv_rho_sinc = Scalar(1) / (rho * sc);  // = θ/r
    const Scalar a = P * inv_rho_sinc;                   // = θd/r
    uv << fx * a * p.x() + params_[2], fy * a * p.y() + params_[3];

    if (d_uv_d_p) {
      // ∂a/∂x = x·G, G = (Q z r/ρ² − θd)/r³ = (R sinc θ cos θ − P h2(θ)) / (ρ³ sinc³θ),
      // with R = (Q − P)/θ² = 2k1 + 4k2θ² + 6k3θ⁴ + 8k4θ⁶, h2 = (θ − sin θ cos θ)/θ³.
      // ∂a/∂z = Q ∂θ/∂z / r = −Q/ρ².
      const Scalar R = polyR(t2);
      const Scalar cos_theta = p.z() / rho;
      const Scalar G = (R * sc * cos_theta -
                        P * angleMinusSinCosOverCube(theta, r / rho, cos_theta)) *
                       inv_rho_sinc * inv_rho_sinc * inv_rho_sinc;
      const Scalar da_dz = -Q / rho2;
      *d_uv_d_p << fx * (a + p.x() * p.x() * G), fx * p.x() * p.y() * G, fx * p.x() * da_dz,
          fy * p.x() * p.y() * G, fy * (a + p.y() * p.y() * G), fy * p.y() * da_dz;
    }
    if (d_uv_d_params) {
      // ∂u/∂k_i = fx x θ^(2i+1)/r = fx x θ^(2i) · (θ/r)
      const Scalar t4 = t2 * t2;
      const Eigen::Matrix<Scalar, 4, 1> powers(t2, t4, t4 * t2, t4 * t4);
      const Scalar bx = p.x() * inv_rho_sinc;
      const Scalar by = p.y() * inv_rho_sinc;
      Mat2N& J = *d_uv_d_params;
      J.template leftCols<4>() << a * p.x(), Scalar(0), Scalar(1), Scalar(0), Scalar(0),
          a * p.y(), Scalar(0), Scalar(1);
      J.template block<1, 4>(0, 4) = (fx * bx) * powers.transpose();
      J.template block<1, 4>(1, 4) = (fy * by) * powers.transpose();
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar mx = (uv.x() - params_[2]) / fx;
    const Scalar my = (uv.y() - params_[3]) / fy;
    const Scalar theta_d = sqrt(mx * mx + my * my);
    Scalar theta;
    if (!solveTheta(theta_d, theta)) return false;
    const Scalar t2 = theta * theta;
    const Scalar P = polyP(t2);
    const Scalar Q = polyQ(t2);
    const Scalar sin_theta = sin(theta);
    const Scalar cos_theta = cos(theta);
    const Scalar sc = sinc(theta, sin_theta);
    const Scalar s = sc / P;  // = sin θ/θd, → 1 on the axis
    bearing << s * mx, s * my, cos_theta;

    if (d_bearing_d_uv || d_bearing_d_params) {
      // dθ/dθd = 1/Q. With s(θd) = sin θ/θd: ∂(s m)/∂m = s I + g m mᵀ where
      // g = s'(θd)/θd = (P h(θ) − sinc θ · R)/(Q P³), h = (θ cos θ − sin θ)/θ³.
      // ∂cos θ/∂m = −sin θ/(Q θd) m = −(s/Q) m.
      const Scalar inv_Q = Scalar(1) / Q;
      const Scalar g = (P * angleCosMinusSinOverCube(theta, sin_theta, cos_theta) -
                        sc * polyR(t2)) *
                       inv_Q / (P * P * P);
      Mat32 d_b_d_m;
      d_b_d_m << s + g * mx * mx, g * mx * my, g * mx * my, s + g * my * my,
          -s * inv_Q * mx, -s * inv_Q * my;
      chainAffineIntrinsics(d_b_d_m, Vec2(mx, my), fx, fy, d_bearing_d_uv, d_bearing_d_params);
      if (d_bearing_d_params) {
        Mat3N& J = *d_bearing_d_params;
        // At fixed θd: ∂θ/∂k_i = −θ^(2i+1)/Q. Then ∂(s m)/∂k_i = m cos θ θ^(2i)/(P Q)·(−1)
        // (s = sin θ/θd, θd = θP) and ∂cos θ/∂k_i = sin θ θ^(2i+1)/Q.
        const Scalar t4 = t2 * t2;
        const Eigen::Matrix<Scalar, 4, 1> powers(t2, t4, t4 * t2, t4 * t4);
        const Scalar lateral = -cos_theta * inv_Q / P;
        const Scalar axial = sin_theta * theta * inv_Q;
        for (int i = 0; i < 4; ++i) {
          J.col(4 + i) << lateral * powers[i] * mx, lateral * powers[i] * my,
              axial * powers[i];
        }
      }
    }
    return true;
  }

  // θ_max: the first zero of Q(θ) = dθd/dθ in (0, π), or π. A scan brackets the first sign
  // change (Q is a quartic in θ², so a step of π/256 cannot step over a pair of roots of a
  // calibrated lens), bisection then halves the bracket to machine precision.
  Scalar maxAngleFromAxis() const {
    constexpr int kScanSteps = 256;
    const Scalar step = Scalar(M_PI / kScanSteps);
    for (int i = 1; i <= kScanSteps; ++i) {
      Scalar hi = step * Scalar(i);
      if (polyQ(hi * hi) > Scalar(0)) continue;
      Scalar lo = hi - step;
      for (int j = 0; j < 60; ++j) {
        const Scalar mid = Scalar(0.5) * (lo + hi);
        (polyQ(mid * mid) > Scalar(0) ? lo : hi) = mid;
      }
      return lo;
    }
    return Scalar(M_PI);
  }

  template <typename U>
  KannalaBrandtCamera<U> cast() const {
    return KannalaBrandtCamera<U>(params_.template cast<U>());
  }

 private:
  // P(θ) = 1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸ (Horner in θ²)
  Scalar polyP(const Scalar& t2) const {
    return Scalar(1) +
           t2 * (params_[4] + t2 * (params_[5] + t2 * (params_[6] + t2 * params_[7])));
  }
  // Q(θ) = d(θP)/dθ = 1 + 3k1θ² + 5k2θ⁴ + 7k3θ⁶ + 9k4θ⁸
  Scalar polyQ(const Scalar& t2) const {
    return Scalar(1) + t2 * (Scalar(3) * params_[4] +
                             t2 * (Scalar(5) * params_[5] +
                                   t2 * (Scalar(7) * params_[6] + t2 * Scalar(9) * params_[7])));
  }
  // R(θ) = P'(θ)/θ = 2k1 + 4k2θ² + 6k3θ⁴ + 8k4θ⁶
  Scalar polyR(const Scalar& t2) const {
    return Scalar(2) * params_[4] +
           t2 * (Scalar(4) * params_[5] + t2 * (Scalar(6) * params_[6] +
                                                t2 * Scalar(8) * params_[7]));
  }

  // Newton's method on f(θ) = θP(θ) − θd from θ = θd (exact without distortion). Stops when
  // the step is at rounding level; fails where no root with Q > 0 exists (outside the
  // image of the domain).
  bool solveTheta(const Scalar& theta_d, Scalar& theta) const {
    using std::abs;
    constexpr int kMaxIterations = 50;
    const Scalar tolerance = Scalar(4) * Eigen::NumTraits<Scalar>::epsilon();
    theta = theta_d;
    bool converged = false;
    for (int i = 0; i < kMaxIterations && !converged; ++i) {
      const Scalar t2 = theta * theta;
      const Scalar step = (theta * polyP(t2) - theta_d) / polyQ(t2);
      theta -= step;
      converged = abs(step) <= tolerance * (Scalar(1) + theta);
    }
    // One more step after convergence in value: for ceres::Jet it makes the derivative parts
    // exact too (implicit function theorem: dθ = (dθd − ∂f/∂k dk)/Q).
    const Scalar t2 = theta * theta;
    theta -= (theta * polyP(t2) - theta_d) / polyQ(t2);
    return converged && theta >= Scalar(0) && theta < Scalar(M_PI) &&
           polyQ(theta * theta) > Scalar(0);
  }

  VecN params_;
};

}  // namespace omnidso
