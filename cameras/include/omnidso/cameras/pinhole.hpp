#pragma once
// Pinhole camera model (paper eq. 1).
//
// Parameters [fx, fy, cx, cy].
//   project:   u = fx·x/z + cx,  v = fy·y/z + cy                 (valid for z > 0)
//   unproject: bearing = [ũ, ṽ, 1] / ‖[ũ, ṽ, 1]‖,  ũ = (u−cx)/fx, ṽ = (v−cy)/fy
// The field of view is below 180°: only points in front of the image plane project.
//
// projectNormalised / unprojectNormalised expose the step to and from the normalised plane
// m = (x/z, y/z) so that DistortedCamera can insert a lens distortion between it and the
// affine step [fx, fy, cx, cy].

#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>
#include <array>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class PinholeCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 4;
  // Parameters after [fx, fy, cx, cy] that act on the normalised plane: none.
  static constexpr int kNumExtraParams = kNumParams - 4;
  static constexpr const char* kName = "pinhole";
  static constexpr std::array<const char*, kNumParams> kParamNames = {"fx", "fy", "cx", "cy"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;
  using Mat2E = Eigen::Matrix<Scalar, 2, kNumExtraParams>;
  using Mat3E = Eigen::Matrix<Scalar, 3, kNumExtraParams>;

  PinholeCamera() { params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0); }
  explicit PinholeCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }

  // m = (x/z, y/z). Points are projectable when in front of the camera; the threshold keeps
  // 1/z finite.
  bool projectNormalised(const Vec3& p, Vec2& m, Mat23* d_m_d_p = nullptr,
                         Mat2E* /*d_m_d_extra*/ = nullptr) const {
    if (!(p.z() > Scalar(kMinDepth))) return false;
    const Scalar inv_z = Scalar(1) / p.z();
    m << p.x() * inv_z, p.y() * inv_z;
    if (d_m_d_p) {
      *d_m_d_p << inv_z, Scalar(0), -m.x() * inv_z, Scalar(0), inv_z, -m.y() * inv_z;
    }
    return true;
  }

  // bearing = [m, 1]/‖[m, 1]‖; every point of the plane is the image of a ray.
  bool unprojectNormalised(const Vec2& m, Vec3& bearing, Mat32* d_bearing_d_m = nullptr,
                           Mat3E* /*d_bearing_d_extra*/ = nullptr) const {
    using std::sqrt;
    const Vec3 h(m.x(), m.y(), Scalar(1));
    const Scalar inv_norm = Scalar(1) / sqrt(h.squaredNorm());
    bearing = h * inv_norm;
    if (d_bearing_d_m) {
      // ∂(h/‖h‖)/∂h = (I − b bᵀ)/‖h‖; only the first two columns vary.
      *d_bearing_d_m = (Eigen::Matrix<Scalar, 3, 2>::Identity() -
                        bearing * bearing.template head<2>().transpose()) *
                       inv_norm;
    }
    return true;
  }

  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    Vec2 m;
    if (!projectNormalised(p, m, d_uv_d_p)) return false;
    uv << fx * m.x() + params_[2], fy * m.y() + params_[3];
    if (d_uv_d_p) {
      d_uv_d_p->row(0) *= fx;
      d_uv_d_p->row(1) *= fy;
    }
    if (d_uv_d_params) {
      *d_uv_d_params << m.x(), Scalar(0), Scalar(1), Scalar(0), Scalar(0), m.y(), Scalar(0),
          Scalar(1);
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Vec2 m((uv.x() - params_[2]) / fx, (uv.y() - params_[3]) / fy);
    const bool want_jacobian = d_bearing_d_uv || d_bearing_d_params;
    Mat32 d_b_d_m;
    unprojectNormalised(m, bearing, want_jacobian ? &d_b_d_m : nullptr);
    chainAffineIntrinsics(d_b_d_m, m, fx, fy, d_bearing_d_uv, d_bearing_d_params);
    return true;
  }

  Scalar maxAngleFromAxis() const { return Scalar(M_PI / 2); }

  template <typename U>
  PinholeCamera<U> cast() const {
    return PinholeCamera<U>(params_.template cast<U>());
  }

 private:
  static constexpr double kMinDepth = 1e-9;
  VecN params_;
};

}  // namespace omnidso
