#pragma once
// Radial–tangential lens distortion (Brown–Conrady with two radial and two tangential terms,
// as in OpenCV, Kalibr "radtan" and Mei's omnidirectional model) on normalised coordinates.
//
// Parameters [k1, k2, p1, p2].  With r² = mx² + my², c = 1 + k1 r² + k2 r⁴:
//   distort:   mdx = mx c + 2 p1 mx my + p2 (r² + 2 mx²)
//              mdy = my c + p1 (r² + 2 my²) + 2 p2 mx my
//   undistort: Gauss–Newton (Newton on the 2×2 system) from m = md until the step is at
//              rounding level (1e-15 relative in double).
// Domain: the radial part r·c(r) must still grow with r, 1 + 3 k1 r² + 5 k2 r⁴ > 0
// (isMonotone); beyond that the image folds back and the map is not invertible.

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class RadTanDistortion {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 4;
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec4 = Eigen::Matrix<Scalar, 4, 1>;
  using Mat22 = Eigen::Matrix<Scalar, 2, 2>;
  using Mat24 = Eigen::Matrix<Scalar, 2, 4>;

  RadTanDistortion() : params_(Vec4::Zero()) {}
  template <typename Derived>
  explicit RadTanDistortion(const Eigen::MatrixBase<Derived>& params) : params_(params) {}

  const Vec4& params() const { return params_; }
  Vec4& params() { return params_; }

  // True where the radial part is still increasing at radius² r2.
  bool isMonotone(const Scalar& r2) const {
    return Scalar(1) + r2 * (Scalar(3) * params_[0] + Scalar(5) * params_[1] * r2) > Scalar(0);
  }

  Vec2 distort(const Vec2& m, Mat22* d_md_d_m = nullptr, Mat24* d_md_d_params = nullptr) const {
    const Scalar& k1 = params_[0];
    const Scalar& k2 = params_[1];
    const Scalar& p1 = params_[2];
    const Scalar& p2 = params_[3];
    const Scalar mx = m.x();
    const Scalar my = m.y();
    const Scalar mx2 = mx * mx;
    const Scalar my2 = my * my;
    const Scalar mxy = mx * my;
    const Scalar r2 = mx2 + my2;
    const Scalar c = Scalar(1) + r2 * (k1 + k2 * r2);
    const Vec2 md(mx * c + Scalar(2) * p1 * mxy + p2 * (r2 + Scalar(2) * mx2),
                  my * c + p1 * (r2 + Scalar(2) * my2) + Scalar(2) * p2 * mxy);
    if (d_md_d_m) {
      // ∂c/∂m = 2 c' m with c' = dc/dr² = k1 + 2 k2 r².
      const Scalar dc = Scalar(2) * (k1 + Scalar(2) * k2 * r2);
      const Scalar cross = dc * mxy + Scalar(2) * (p1 * mx + p2 * my);
      *d_md_d_m << c + dc * mx2 + Scalar(2) * p1 * my + Scalar(6) * p2 * mx, cross,  //
          cross, c + dc * my2 + Scalar(6) * p1 * my + Scalar(2) * p2 * mx;
    }
    if (d_md_d_params) {
      *d_md_d_params << mx * r2, mx * r2 * r2, Scalar(2) * mxy, r2 + Scalar(2) * mx2,  //
          my * r2, my * r2 * r2, r2 + Scalar(2) * my2, Scalar(2) * mxy;
    }
    return md;
  }

  // Solves distort(m) = md for m. Returns false where the iteration does not converge to a
  // point of the monotone region with an invertible Jacobian. d_m_d_md (= (∂md/∂m)⁻¹) is
  // written when requested and the solve succeeded.
  bool undistort(const Vec2& md, Vec2& m, Mat22* d_m_d_md = nullptr) const {
    using std::abs;
    constexpr int kMaxIterations = 100;
    const Scalar tolerance = Scalar(4) * Eigen::NumTraits<Scalar>::epsilon();
    m = md;
    Mat22 J;
    bool converged = false;
    for (int i = 0; i < kMaxIterations && !converged; ++i) {
      const Vec2 residual = distort(m, &J) - md;
      const Vec2 step = J.inverse() * residual;
      m -= step;
      converged = abs(step.x()) + abs(step.y()) <=
                  tolerance * (Scalar(1) + abs(m.x()) + abs(m.y()));
    }
    // One more step after convergence in value: for ceres::Jet it makes the derivative parts
    // exact too (implicit function theorem).
    const Vec2 residual = distort(m, &J) - md;
    m -= J.inverse() * residual;
    if (!(converged && J.determinant() > Scalar(0) && isMonotone(m.squaredNorm()))) {
      return false;
    }
    if (d_m_d_md) *d_m_d_md = J.inverse();
    return true;
  }

  template <typename U>
  RadTanDistortion<U> cast() const {
    return RadTanDistortion<U>(params_.template cast<U>());
  }

 private:
  Vec4 params_;
};

}  // namespace omnidso
