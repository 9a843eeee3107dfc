#pragma once
// The photometric residual of one pattern (paper eq. 5–7; notation in
// photometric_residual.hpp), split where its inputs change at different rates, so that the
// Ceres cost function (photometric_analytic.hpp) and the window's native solver
// (backend/window_photometric_terms.hpp) evaluate the same function the same way:
//   per host pixel (changes with the intrinsics only):  b_o = π⁻¹(p + o),  ∂b_o/∂c
//   per host–target pair:  [R t] = T_target_host,  s = t_j e^{a_j} / (t_i e^{a_i}),  b_i, b_j
//   per pattern pixel:     x̃_o = R b_o + d t,  p'_o = π(x̃_o),
//                          r_o = √w_o [(I_j[p'_o] − b_j) − s h_o],  h_o = I_i[p + o] − b_i
// and the rows every Jacobian is built from:
//   g_o       = √w_o ∇I_j(p'_o) ∂π/∂x̃                     (∂r_o/∂x̃_o, 1×3)
//   ∂r_o/∂c_L = √w_o ∇I_j (∂π/∂c + ∂π/∂x̃ R ∂b_o/∂c)      (level-L intrinsics, 1×K)
// The pose, inverse-distance and affine Jacobians follow from g_o, x̃_o, b_o and h_o
// (photometric_analytic.hpp lists them); each user forms the ones it needs.
//
// Validity is decided in the same order as a pixel-by-pixel evaluation: d < 0 first, then
// per pattern pixel the host unprojection, the projection and the target sample, so the
// status names the first pixel that fails.

#include <Eigen/Core>
#include <array>

#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/image_sampler.hpp"
#include "omnidso/residuals/photometric_residual.hpp"
#include "omnidso/residuals/residual_pattern.hpp"

namespace omnidso {

// b_o and ∂b_o/∂c of a host pattern on one pyramid level (intrinsics of that level).
template <int N, int K>
struct HostBearings {
  std::array<Eigen::Vector3d, N> bearing;
  std::array<Eigen::Matrix<double, 3, K>, N> d_bearing_d_intrinsics;  // filled on request
  int num_valid = 0;  // pattern pixels before the first that does not unproject
};

template <class CameraD, int N>
void unprojectHostPattern(const CameraD& camera, const HostPatch<N>& host,
                          bool with_intrinsics_jacobian,
                          HostBearings<N, CameraD::kNumParams>* out) {
  out->num_valid = 0;
  for (int o = 0; o < N; ++o) {
    const PatternOffset offset = spreadOffset<N>(o, host.spread);
    const typename CameraD::Vec2 uv(host.pixel.x() + offset.du, host.pixel.y() + offset.dv);
    if (!camera.unproject(uv, out->bearing[o], nullptr,
                          with_intrinsics_jacobian ? &out->d_bearing_d_intrinsics[o] : nullptr))
      return;
    ++out->num_valid;
  }
}

// The host–target pair: relative transform and brightness transfer of eq. 5–7.
struct PhotometricPair {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  double s = 1.0;    // t_j e^{a_j} / (t_i e^{a_i})
  double b_host = 0.0;
  double b_target = 0.0;
};

// From the parameter blocks T_world_host, T_world_target, [a_i b_i], [a_j b_j] and the
// exposures t_i, t_j.
inline PhotometricPair makePhotometricPair(const double* pose_host, const double* pose_target,
                                           const double* affine_host, const double* affine_target,
                                           double host_exposure, double target_exposure) {
  const SE3d T_target_host =
      SE3d::fromParameters(pose_target).inverse() * SE3d::fromParameters(pose_host);
  PhotometricPair pair;
  pair.R = T_target_host.rotationMatrix();
  pair.t = T_target_host.translation();
  pair.s = target_exposure / host_exposure * std::exp(affine_target[0] - affine_host[0]);
  pair.b_host = affine_host[1];
  pair.b_target = affine_target[1];
  return pair;
}

// Per pattern pixel: g_o, x̃_o, h_o and (on request) ∂r_o/∂c_L.
template <int N, int K>
struct PatchDerivatives {
  Eigen::Matrix<double, N, 3, Eigen::RowMajor> d_r_d_x;
  Eigen::Matrix<double, N, 3, Eigen::RowMajor> point;
  Eigen::Matrix<double, N, 1> host_term;
  Eigen::Matrix<double, N, K, Eigen::RowMajor> d_r_d_intrinsics;
};

// ∇I_j(p'_o) per pattern pixel, without the weight √w_o.
template <int N>
using PatchImageGradients = Eigen::Matrix<double, N, 2, Eigen::RowMajor>;

// r_o for every pattern pixel, and the derivative rows when `derivatives` is given
// (∂r/∂c_L only with want_intrinsics; `bearings` must then hold ∂b/∂c). On any status but
// kValid, `residuals` and `derivatives` hold partial values and must not be used.
// `sampled_gradients` receives ∇I_j at this evaluation's p'_o. With `image_gradients` the
// derivative rows take ∇I_j from there instead of from this evaluation: first-estimate
// Jacobians (DSO, Engel et al. 2018, sec. 2.3) evaluate the geometry ∂π/∂x̃ at the
// linearisation point but the image gradient at the current estimate, where the residual
// is — the image is not smooth on the scale of how far p'_o moves between the two.
// Two passes: first every pixel's projection and target sample, then the residuals and
// derivative rows — the target-image reads, where the solvers wait on memory, are then
// issued close together instead of one per pixel's worth of arithmetic. The first failure
// in pixel order decides the status, as in a pixel-by-pixel evaluation.
template <class CameraD, int N>
PhotometricStatus evaluatePhotometricPatch(
    const CameraD& camera, const ImageSampler& sampler, const HostPatch<N>& host,
    const HostBearings<N, CameraD::kNumParams>& bearings, const PhotometricPair& pair,
    double inverse_distance, double* residuals,
    PatchDerivatives<N, CameraD::kNumParams>* derivatives, bool want_intrinsics,
    PatchImageGradients<N>* sampled_gradients = nullptr,
    const PatchImageGradients<N>* image_gradients = nullptr) {
  const double d = inverse_distance;
  if (!(d >= 0.0)) return PhotometricStatus::kNegativeInverseDistance;
  std::array<Eigen::Vector3d, N> x;
  std::array<typename CameraD::Vec2, N> uv;
  std::array<typename CameraD::Mat23, N> d_uv_d_x;
  std::array<typename CameraD::Mat2N, N> d_uv_d_c;
  int num_projected = 0;
  PhotometricStatus projection_status = PhotometricStatus::kValid;
  for (; num_projected < N; ++num_projected) {
    const int o = num_projected;
    if (o >= bearings.num_valid) {
      projection_status = PhotometricStatus::kHostOutsideDomain;
      break;
    }
    x[o] = pair.R * bearings.bearing[o] + d * pair.t;
    if (!camera.project(x[o], uv[o], derivatives ? &d_uv_d_x[o] : nullptr,
                        want_intrinsics ? &d_uv_d_c[o] : nullptr)) {
      projection_status = projectionFailure(camera, x[o]);
      break;
    }
  }
  std::array<double, N> intensity, di_du, di_dv;
  for (int o = 0; o < num_projected; ++o) {
    if (!sampler.sampleWithGradient(uv[o].x(), uv[o].y(), &intensity[o], &di_du[o], &di_dv[o]))
      return PhotometricStatus::kOutsideImage;
  }
  if (num_projected < N) return projection_status;
  if (sampled_gradients)
    for (int o = 0; o < N; ++o) sampled_gradients->row(o) << di_du[o], di_dv[o];

  for (int o = 0; o < N; ++o) {
    const double sw = host.sqrt_weight[o];
    const double h = host.intensity[o] - pair.b_host;
    residuals[o] = sw * ((intensity[o] - pair.b_target) - pair.s * h);
    if (!derivatives) continue;
    const Eigen::RowVector2d grad =
        sw * (image_gradients ? Eigen::RowVector2d(image_gradients->row(o))
                              : Eigen::RowVector2d(di_du[o], di_dv[o]));
    const Eigen::RowVector3d g = grad * d_uv_d_x[o];  // ∂r/∂x̃
    derivatives->d_r_d_x.row(o) = g;
    derivatives->point.row(o) = x[o].transpose();
    derivatives->host_term[o] = h;
    if (want_intrinsics) {
      const Eigen::RowVector3d gR = g * pair.R;
      derivatives->d_r_d_intrinsics.row(o) =
          grad * d_uv_d_c[o] + gR * bearings.d_bearing_d_intrinsics[o];
    }
  }
  return PhotometricStatus::kValid;
}

}  // namespace omnidso
