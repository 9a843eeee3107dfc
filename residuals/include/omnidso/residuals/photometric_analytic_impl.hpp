#pragma once
// Member definitions of PhotometricResidualAnalytic (derivation in photometric_analytic.hpp).
// Include only where the class is explicitly instantiated (residuals/src) or in tests that
// need another pattern/model combination.

#include <cmath>

#include "omnidso/cameras/pyramid_scaling.hpp"
#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/photometric_analytic.hpp"
#include "omnidso/residuals/residual_pattern.hpp"
#include "omnidso/residuals/se3_manifold.hpp"

namespace omnidso {

template <template <typename> class Camera, int N>
PhotometricResidualAnalytic<Camera, N>::PhotometricResidualAnalytic(
    const PhotometricObservation<N>& observation)
    : observation_(observation), sampler_(*observation.target_image, observation.interpolation,
               observation.target_content) {}

template <template <typename> class Camera, int N>
bool PhotometricResidualAnalytic<Camera, N>::Evaluate(double const* const* parameters,
                                                      double* residuals, double** jacobians) const {
  return evaluate(parameters, residuals, jacobians) == PhotometricStatus::kValid;
}

template <template <typename> class Camera, int N>
PhotometricStatus PhotometricResidualAnalytic<Camera, N>::evaluate(double const* const* parameters,
                                                                   double* residuals,
                                                                   double** jacobians) const {
  using CameraD = Camera<double>;
  using RowN6 = Eigen::Matrix<double, N, 6, Eigen::RowMajor>;
  using RowNK = Eigen::Matrix<double, N, kNumIntrinsics, Eigen::RowMajor>;
  using RowN2 = Eigen::Matrix<double, N, 2, Eigen::RowMajor>;

  const double d = parameters[2][0];
  if (!(d >= 0.0)) return PhotometricStatus::kNegativeInverseDistance;

  const SE3d T_world_host = SE3d::fromParameters(parameters[0]);
  const SE3d T_world_target = SE3d::fromParameters(parameters[1]);
  const SE3d T_target_host = T_world_target.inverse() * T_world_host;
  const Eigen::Matrix3d R = T_target_host.rotationMatrix();
  const Eigen::Vector3d& t = T_target_host.translation();

  typename CameraD::VecN intrinsics = Eigen::Map<const typename CameraD::VecN>(parameters[5]);
  scaleIntrinsicsToLevel(intrinsics, observation_.level);
  const CameraD camera(intrinsics);
  const double level_scale = 1.0 / static_cast<double>(1 << observation_.level);

  const double a_i = parameters[3][0], b_i = parameters[3][1];
  const double a_j = parameters[4][0], b_j = parameters[4][1];
  // s = t_j e^{a_j} / (t_i e^{a_i}) of eq. 5.
  const double s = observation_.target_exposure / observation_.host_exposure * std::exp(a_j - a_i);

  // Any Jacobian request computes the geometric ones too (cheap next to the sampling, and
  // it keeps every local below initialised on every path).
  const bool want_geometry = jacobians != nullptr;
  const bool want_intrinsics = jacobians && jacobians[5];

  Eigen::Matrix<double, N, 1> r;
  RowN6 J_host, J_target;
  Eigen::Matrix<double, N, 1> J_d;
  RowN2 J_aff_host, J_aff_target;
  RowNK J_intr = RowNK::Zero();  // zeroed: only filled when requested

  typename CameraD::Mat23 d_uv_d_x;
  typename CameraD::Mat2N d_uv_d_c;
  typename CameraD::Mat3N d_b_d_c;
  const auto& pattern = ResidualPattern<N>::kOffsets;
  for (int o = 0; o < N; ++o) {
    const typename CameraD::Vec2 uv_host(observation_.host.pixel.x() + pattern[o].du,
                                         observation_.host.pixel.y() + pattern[o].dv);
    Eigen::Vector3d b;
    if (!camera.unproject(uv_host, b, nullptr, want_intrinsics ? &d_b_d_c : nullptr)) {
      return PhotometricStatus::kHostOutsideDomain;
    }
    const Eigen::Vector3d x = R * b + d * t;
    typename CameraD::Vec2 uv;
    if (!camera.project(x, uv, want_geometry ? &d_uv_d_x : nullptr,
                        want_intrinsics ? &d_uv_d_c : nullptr)) {
      return projectionFailure(camera, x);
    }
    double intensity, di_du, di_dv;
    if (!sampler_.sampleWithGradient(uv.x(), uv.y(), &intensity, &di_du, &di_dv)) {
      return PhotometricStatus::kOutsideImage;
    }
    const double sw = observation_.host.sqrt_weight[o];
    const double h = observation_.host.intensity[o] - b_i;
    r[o] = sw * ((intensity - b_j) - s * h);
    if (!jacobians) continue;
    J_aff_host.row(o) << sw * s * h, sw * s;
    J_aff_target.row(o) << -sw * s * h, -sw;

    const Eigen::RowVector2d grad = sw * Eigen::RowVector2d(di_du, di_dv);
    const Eigen::RowVector3d g = grad * d_uv_d_x;  // ∂r/∂x̃
    const Eigen::RowVector3d gR = g * R;
    J_host.row(o) << d * gR, -gR * skew(b);
    J_target.row(o) << -d * g, g * skew(x);
    J_d[o] = g.dot(t);
    if (want_intrinsics) {
      J_intr.row(o) = grad * d_uv_d_c + gR * d_b_d_c;
    }
  }

  Eigen::Map<Eigen::Matrix<double, N, 1>>{residuals} = r;
  if (!jacobians) return PhotometricStatus::kValid;
  if (jacobians[0]) {
    ambientFromTangentJacobian<N>(se3TangentToAmbient(parameters[0]), J_host, jacobians[0]);
  }
  if (jacobians[1]) {
    ambientFromTangentJacobian<N>(se3TangentToAmbient(parameters[1]), J_target, jacobians[1]);
  }
  if (jacobians[2]) Eigen::Map<Eigen::Matrix<double, N, 1>>{jacobians[2]} = J_d;
  if (jacobians[3]) Eigen::Map<RowN2>{jacobians[3]} = J_aff_host;
  if (jacobians[4]) Eigen::Map<RowN2>{jacobians[4]} = J_aff_target;
  if (jacobians[5]) {
    // ∂c_L/∂c_0 = diag(2^-L for fx fy cx cy, 1 for the rest) (pyramid_scaling.hpp).
    J_intr.template leftCols<4>() *= level_scale;
    Eigen::Map<RowNK>{jacobians[5]} = J_intr;
  }
  return PhotometricStatus::kValid;
}

}  // namespace omnidso
