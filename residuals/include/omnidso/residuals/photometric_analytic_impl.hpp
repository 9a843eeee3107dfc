#pragma once
// Member definitions of PhotometricResidualAnalytic (derivation in photometric_analytic.hpp).
// Include only where the class is explicitly instantiated (residuals/src) or in tests that
// need another pattern/model combination.

#include <cmath>

#include "omnidso/cameras/pyramid_scaling.hpp"
#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/photometric_analytic.hpp"
#include "omnidso/residuals/photometric_kernel.hpp"
#include "omnidso/residuals/residual_pattern.hpp"
#include "omnidso/residuals/se3_manifold.hpp"

namespace omnidso {

template <template <typename> class Camera, int N>
PhotometricResidualAnalytic<Camera, N>::PhotometricResidualAnalytic(
    const PhotometricObservation<N>& observation)
    : observation_(observation), sampler_(*observation.target_image, observation.interpolation,
               observation.target_content, observation.gradient) {}

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

  const PhotometricPair pair =
      makePhotometricPair(parameters[0], parameters[1], parameters[3], parameters[4],
                          observation_.host_exposure, observation_.target_exposure);
  typename CameraD::VecN intrinsics = Eigen::Map<const typename CameraD::VecN>(parameters[5]);
  scaleIntrinsicsToLevel(intrinsics, observation_.level);
  const CameraD camera(intrinsics);
  const double level_scale = 1.0 / static_cast<double>(1 << observation_.level);

  // Any Jacobian request computes the geometric ones too (cheap next to the sampling).
  const bool want_intrinsics = jacobians && jacobians[5];
  HostBearings<N, kNumIntrinsics> bearings;
  unprojectHostPattern(camera, observation_.host, want_intrinsics, &bearings);
  // Zeroed for GCC 12's -Wmaybe-uninitialized, which does not follow the status check below.
  Eigen::Matrix<double, N, 1> r = Eigen::Matrix<double, N, 1>::Zero();
  PatchDerivatives<N, kNumIntrinsics> patch;
  const PhotometricStatus status =
      evaluatePhotometricPatch(camera, sampler_, observation_.host, bearings, pair, d, r.data(),
                               jacobians ? &patch : nullptr, want_intrinsics);
  if (status != PhotometricStatus::kValid) return status;
  Eigen::Map<Eigen::Matrix<double, N, 1>>{residuals} = r;
  if (!jacobians) return PhotometricStatus::kValid;

  // The Jacobians of photometric_analytic.hpp from the kernel's rows g_o, x̃_o, h_o.
  RowN6 J_host, J_target;
  Eigen::Matrix<double, N, 1> J_d;
  RowN2 J_aff_host, J_aff_target;
  const Eigen::Matrix3d& R = pair.R;
  for (int o = 0; o < N; ++o) {
    const double sw = observation_.host.sqrt_weight[o];
    const double h = patch.host_term[o];
    J_aff_host.row(o) << sw * pair.s * h, sw * pair.s;
    J_aff_target.row(o) << -sw * pair.s * h, -sw;
    const Eigen::RowVector3d g = patch.d_r_d_x.row(o);
    const Eigen::Vector3d x = patch.point.row(o).transpose();
    const Eigen::RowVector3d gR = g * R;
    J_host.row(o) << d * gR, -gR * skew(bearings.bearing[o]);
    J_target.row(o) << -d * g, g * skew(x);
    J_d[o] = g.dot(pair.t);
  }
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
    RowNK J_intr = patch.d_r_d_intrinsics;
    J_intr.template leftCols<4>() *= level_scale;
    Eigen::Map<RowNK>{jacobians[5]} = J_intr;
  }
  return PhotometricStatus::kValid;
}

}  // namespace omnidso
