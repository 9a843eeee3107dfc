#pragma once
// A central camera model followed by radial–tangential distortion on its normalised plane:
// Kalibr's pinhole + radtan ("pinhole-radtan") and omni + radtan ("ucm-radtan", the model of
// Mei & Rives 2007 that cv::omnidir calibrates; paper Sec. III-B).
//
// Parameters [base params..., k1, k2, p1, p2], base = [fx, fy, cx, cy, extra...].
//   project:   m = base.projectNormalised(x)   (pinhole: (x, y)/z; UCM: (x, y)/(z + ξ‖x‖))
//              md = radtan(m),  u = fx·mdx + cx,  v = fy·mdy + cy
//   unproject: md = ((u−cx)/fx, (v−cy)/fy),  m = radtan⁻¹(md) (Gauss–Newton),
//              bearing = base.unprojectNormalised(m)
// Domain: the base model's domain, restricted to where the radial distortion is monotone
// (RadTanDistortion::isMonotone). maxAngleFromAxis() is the base model's.

#include <omnidso/cameras/pinhole.hpp>
#include <omnidso/cameras/radtan.hpp>
#include <omnidso/cameras/unified.hpp>

#include <Eigen/Core>
#include <omnidso/cameras/affine_intrinsics.hpp>
#include <array>
#include <cstddef>
#include <utility>

namespace omnidso {

namespace detail {
// [base..., dist...] as one constexpr array (parameter names of a composed model).
template <std::size_t NB, std::size_t ND, std::size_t... I>
constexpr std::array<const char*, NB + ND> concatNames(const std::array<const char*, NB>& base,
                                                       const std::array<const char*, ND>& dist,
                                                       std::index_sequence<I...>) {
  return {{(I < NB ? base[I] : dist[I - NB])...}};
}
}  // namespace detail

template <typename Base>
struct RadTanModelName;
template <typename S>
struct RadTanModelName<PinholeCamera<S>> {
  static constexpr const char* value = "pinhole-radtan";
};
template <typename S>
struct RadTanModelName<UnifiedCamera<S>> {
  static constexpr const char* value = "ucm-radtan";
};

template <typename Base>
class DistortedCamera {
 public:
  using BaseModel = Base;
  using Scalar = typename Base::Scalar;
  using Distortion = RadTanDistortion<Scalar>;
  static constexpr int kNumBaseParams = Base::kNumParams;
  static constexpr int kNumExtraParams = Base::kNumExtraParams;
  static constexpr int kNumParams = kNumBaseParams + Distortion::kNumParams;
  static constexpr const char* kName = RadTanModelName<Base>::value;
  static constexpr std::array<const char*, kNumParams> kParamNames =
      detail::concatNames(Base::kParamNames, std::array<const char*, 4>{"k1", "k2", "p1", "p2"},
                  std::make_index_sequence<kNumParams>{});
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  using VecN = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Mat23 = Eigen::Matrix<Scalar, 2, 3>;
  using Mat2N = Eigen::Matrix<Scalar, 2, kNumParams>;
  using Mat32 = Eigen::Matrix<Scalar, 3, 2>;
  using Mat3N = Eigen::Matrix<Scalar, 3, kNumParams>;

  DistortedCamera() {
    params_ << Base().params(), Eigen::Matrix<Scalar, 4, 1>::Zero();
  }
  explicit DistortedCamera(const VecN& params) : params_(params) {}
  DistortedCamera(const Base& base, const Eigen::Matrix<Scalar, 4, 1>& distortion) {
    params_ << base.params(), distortion;
  }

  const VecN& params() const { return params_; }
  VecN& params() { return params_; }
  Base base() const {
    return Base(params_.template head<kNumBaseParams>());
  }
  Distortion distortion() const { return Distortion(params_.template tail<4>()); }

  bool project(const Vec3& p, Vec2& uv, Mat23* d_uv_d_p = nullptr,
               Mat2N* d_uv_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Distortion radtan = distortion();
    Vec2 m;
    typename Base::Mat2E d_m_d_extra;
    if (!base().projectNormalised(p, m, d_uv_d_p, d_uv_d_params ? &d_m_d_extra : nullptr)) {
      return false;
    }
    if (!radtan.isMonotone(m.squaredNorm())) return false;
    const bool want_jacobian = d_uv_d_p || d_uv_d_params;
    Eigen::Matrix<Scalar, 2, 2> d_md_d_m;
    Eigen::Matrix<Scalar, 2, 4> d_md_d_k;
    const Vec2 md = radtan.distort(m, want_jacobian ? &d_md_d_m : nullptr,
                                   d_uv_d_params ? &d_md_d_k : nullptr);
    uv << fx * md.x() + params_[2], fy * md.y() + params_[3];
    // uv = diag(f) md + c:  ∂uv/∂• = diag(f) ∂md/∂m ∂m/∂•
    if (d_uv_d_p) {
      const Mat23 d_m_d_p = *d_uv_d_p;
      d_uv_d_p->noalias() = d_md_d_m * d_m_d_p;
      d_uv_d_p->row(0) *= fx;
      d_uv_d_p->row(1) *= fy;
    }
    if (d_uv_d_params) {
      Mat2N& J = *d_uv_d_params;
      J.template leftCols<4>() << md.x(), Scalar(0), Scalar(1), Scalar(0), Scalar(0), md.y(),
          Scalar(0), Scalar(1);
      J.template middleCols<kNumExtraParams>(4).noalias() = d_md_d_m * d_m_d_extra;
      J.template rightCols<4>() = d_md_d_k;
      J.template rightCols<kNumParams - 4>().row(0) *= fx;
      J.template rightCols<kNumParams - 4>().row(1) *= fy;
    }
    return true;
  }

  bool unproject(const Vec2& uv, Vec3& bearing, Mat32* d_bearing_d_uv = nullptr,
                 Mat3N* d_bearing_d_params = nullptr) const {
    const Scalar& fx = params_[0];
    const Scalar& fy = params_[1];
    const Distortion radtan = distortion();
    const Vec2 md((uv.x() - params_[2]) / fx, (uv.y() - params_[3]) / fy);
    const bool want_jacobian = d_bearing_d_uv || d_bearing_d_params;
    Vec2 m;
    Eigen::Matrix<Scalar, 2, 2> d_m_d_md;
    if (!radtan.undistort(md, m, want_jacobian ? &d_m_d_md : nullptr)) return false;
    Mat32 d_b_d_m;
    typename Base::Mat3E d_b_d_extra;
    if (!base().unprojectNormalised(m, bearing, want_jacobian ? &d_b_d_m : nullptr,
                                    d_bearing_d_params ? &d_b_d_extra : nullptr)) {
      return false;
    }
    if (!want_jacobian) return true;
    const Mat32 d_b_d_md = d_b_d_m * d_m_d_md;
    chainAffineIntrinsics(d_b_d_md, md, fx, fy, d_bearing_d_uv, d_bearing_d_params);
    if (d_bearing_d_params) {
      Mat3N& J = *d_bearing_d_params;
      J.template middleCols<kNumExtraParams>(4) = d_b_d_extra;
      // distort(m(k), k) = md fixed: ∂m/∂k = −(∂md/∂m)⁻¹ ∂md/∂k.
      Eigen::Matrix<Scalar, 2, 2> d_md_d_m;
      Eigen::Matrix<Scalar, 2, 4> d_md_d_k;
      radtan.distort(m, &d_md_d_m, &d_md_d_k);
      J.template rightCols<4>().noalias() = -d_b_d_md * d_md_d_k;
    }
    return true;
  }

  Scalar maxAngleFromAxis() const { return base().maxAngleFromAxis(); }

  template <typename U>
  auto cast() const {
    using BaseU = decltype(std::declval<Base>().template cast<U>());
    return DistortedCamera<BaseU>(params_.template cast<U>());
  }

 private:
  VecN params_;
};

// Kalibr's pinhole + radtan.
template <typename Scalar = double>
using PinholeRadTanCamera = DistortedCamera<PinholeCamera<Scalar>>;
// Mei's model: UCM + radtan (Kalibr "omni" + "radtan", cv::omnidir).
template <typename Scalar = double>
using UnifiedRadTanCamera = DistortedCamera<UnifiedCamera<Scalar>>;

}  // namespace omnidso
