#pragma once
// Pinhole camera model (paper eq. 1).
//
// Parameters [fx, fy, cx, cy].
//   project:   u = fx·x/z + cx,  v = fy·y/z + cy                 (valid for z > 0)
//   unproject: bearing = [ũ, ṽ, 1] / ‖[ũ, ṽ, 1]‖,  ũ = (u−cx)/fx, ṽ = (v−cy)/fy
// The field of view is below 180°: only points in front of the image plane project.

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace omnidso {

template <typename Scalar_ = double>
class PinholeCamera {
 public:
  using Scalar = Scalar_;
  static constexpr int kNumParams = 4;
  static constexpr const char* kName = "pinhole";
  static constexpr std::array<const char*, kNumParams> kParamNames = {"fx", "fy", "cx", "cy"};
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;

  PinholeCamera() { params_ << Scalar(1), Scalar(1), Scalar(0), Scalar(0); }
  explicit PinholeCamera(const VecN& params) : params_(params) {}

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }

  // Points are projectable when in front of the camera. The threshold keeps 1/z finite.
  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    if (!(p.z() > Scalar(kMinDepth))) return false;
    const Scalar inv_z = Scalar(1) / p.z();
    const Scalar mx = p.x() * inv_z;
    const Scalar my = p.y() * inv_z;
    uv << fx * mx + params_[2], fy * my + params_[3];
    if (d_uv_d_p) {
      *d_uv_d_p << fx * inv_z, Scalar(0), -fx * mx * inv_z, Scalar(0), fy * inv_z,
          -fy * my * inv_z;
    }
    if (d_uv_d_params) {
      *d_uv_d_params << mx, Scalar(0), Scalar(1), Scalar(0), Scalar(0), my, Scalar(0),
          Scalar(1);
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    using std::sqrt;
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Scalar mx = (uv.x() - params_[2]) / fx;
    const Scalar my = (uv.y() - params_[3]) / fy;
    const Vec3 m(mx, my, Scalar(1));
    const Scalar inv_norm = Scalar(1) / sqrt(m.squaredNorm());
    bearing = m * inv_norm;
    if (d_bearing_d_uv || d_bearing_d_params) {
      // ∂(m/‖m‖)/∂m = (I − b bᵀ)/‖m‖; only the first two columns vary.
      const Eigen::Matrix<Scalar, 3, 3> P =
          (Eigen::Matrix<Scalar, 3, 3>::Identity() - bearing * bearing.transpose()) * inv_norm;
      if (d_bearing_d_uv) {
        d_bearing_d_uv->col(0) = P.col(0) / fx;
        d_bearing_d_uv->col(1) = P.col(1) / fy;
      }
      if (d_bearing_d_params) {
        d_bearing_d_params->col(0) = -P.col(0) * mx / fx;
        d_bearing_d_params->col(1) = -P.col(1) * my / fy;
        d_bearing_d_params->col(2) = -P.col(0) / fx;
        d_bearing_d_params->col(3) = -P.col(1) / fy;
      }
    }
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
