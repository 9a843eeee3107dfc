#pragma once
// Definitions for tracking_residual.hpp; included only by residuals/src/*_MODEL.cc.

#include <ceres/autodiff_cost_function.h>

#include <cmath>

#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/residual_pattern.hpp"
#include "omnidso/residuals/se3_manifold.hpp"
#include "omnidso/residuals/tracking_residual.hpp"

namespace omnidso {

template <template <typename> class Camera, int N>
std::optional<TrackingObservation<N>> makeTrackingObservation(const Camera<double>& level_camera,
                                                              const HostPatch<N>& patch,
                                                              double inverse_distance) {
  TrackingObservation<N> observation;
  for (int o = 0; o < N; ++o) {
    const PatternOffset offset = spreadOffset<N>(o, patch.spread);
    const typename Camera<double>::Vec2 uv(patch.pixel.x() + offset.du,
                                           patch.pixel.y() + offset.dv);
    if (!level_camera.unproject(uv, observation.host_bearings[o])) return std::nullopt;
  }
  observation.inverse_distance = inverse_distance;
  observation.host_intensity = patch.intensity;
  observation.sqrt_weight = patch.sqrt_weight;
  return observation;
}

template <template <typename> class Camera, int N>
TrackingResidualAnalytic<Camera, N>::TrackingResidualAnalytic(
    const Camera<double>& level_camera, const TrackingObservation<N>& observation)
    : camera_(level_camera),
      observation_(observation),
      sampler_(*observation.target_image, observation.interpolation,
               observation.target_content, observation.gradient) {}

template <template <typename> class Camera, int N>
bool TrackingResidualAnalytic<Camera, N>::Evaluate(double const* const* parameters,
                                                   double* residuals, double** jacobians) const {
  return evaluate(parameters, residuals, jacobians) == PhotometricStatus::kValid;
}

template <template <typename> class Camera, int N>
PhotometricStatus evaluateTrackingResidual(
    const Camera<double>& level_camera, const TrackingObservation<N>& observation,
    const ImageSampler& sampler, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
    const double* target_affine, double* residuals, TrackingPoseJacobian<N>* pose_jacobian,
    TrackingAffineJacobian<N>* affine_jacobian) {
  using CameraD = Camera<double>;
  const double d = observation.inverse_distance;
  if (!(d >= 0.0)) return PhotometricStatus::kNegativeInverseDistance;
  const double a_j = target_affine[0], b_j = target_affine[1];
  const double s = observation.target_exposure / observation.host_exposure *
                   std::exp(a_j - observation.host_a);
  const bool want_pose = pose_jacobian != nullptr;

  Eigen::Matrix<double, N, 1> r;
  typename CameraD::Mat23 d_uv_d_x;
  for (int o = 0; o < N; ++o) {
    const Eigen::Vector3d& b = observation.host_bearings[o];
    const Eigen::Vector3d x = R * b + d * t;
    typename CameraD::Vec2 uv;
    if (!level_camera.project(x, uv, want_pose ? &d_uv_d_x : nullptr)) {
      return projectionFailure(level_camera, x);
    }
    double intensity, di_du, di_dv;
    if (!sampler.sampleWithGradient(uv.x(), uv.y(), &intensity, &di_du, &di_dv)) {
      return PhotometricStatus::kOutsideImage;
    }
    const double sw = observation.sqrt_weight[o];
    const double h = observation.host_intensity[o] - observation.host_b;
    r[o] = sw * ((intensity - b_j) - s * h);
    if (affine_jacobian) affine_jacobian->row(o) << -sw * s * h, -sw;
    if (want_pose) {
      const Eigen::RowVector3d gR = sw * Eigen::RowVector2d(di_du, di_dv) * d_uv_d_x * R;
      pose_jacobian->row(o) << d * gR, -gR * skew(b);
    }
  }
  Eigen::Map<Eigen::Matrix<double, N, 1>>{residuals} = r;
  return PhotometricStatus::kValid;
}

template <template <typename> class Camera, int N>
PhotometricStatus TrackingResidualAnalytic<Camera, N>::evaluate(double const* const* parameters,
                                                                double* residuals,
                                                                double** jacobians) const {
  const SE3d T_target_host = SE3d::fromParameters(parameters[0]);
  const bool want_pose = jacobians && jacobians[0];
  const bool want_affine = jacobians && jacobians[1];
  TrackingPoseJacobian<N> J_pose;
  TrackingAffineJacobian<N> J_affine;
  const PhotometricStatus status = evaluateTrackingResidual<Camera, N>(
      camera_, observation_, sampler_, T_target_host.rotationMatrix(),
      T_target_host.translation(), parameters[1], residuals, want_pose ? &J_pose : nullptr,
      want_affine ? &J_affine : nullptr);
  if (status != PhotometricStatus::kValid) return status;
  if (want_pose) {
    ambientFromTangentJacobian<N>(se3TangentToAmbient(parameters[0]), J_pose, jacobians[0]);
  }
  if (want_affine) {
    Eigen::Map<Eigen::Matrix<double, N, 2, Eigen::RowMajor>>{jacobians[1]} = J_affine;
  }
  return PhotometricStatus::kValid;
}

// The autodiff twin of TrackingResidualAnalytic (for tests and benchmarks).
template <template <typename> class Camera, int N>
class TrackingResidualFunctor {
 public:
  TrackingResidualFunctor(const Camera<double>& level_camera,
                          const TrackingObservation<N>& observation)
      : camera_(level_camera),
        observation_(observation),
        sampler_(*observation.target_image, observation.interpolation,
               observation.target_content, observation.gradient) {}

  template <typename T>
  bool operator()(const T* relative_pose, const T* target_affine, T* residuals) const {
    using std::exp;
    const SE3<T> T_target_host = SE3<T>::fromParameters(relative_pose);
    const Eigen::Matrix<T, 3, 3> R = T_target_host.rotationMatrix();
    const Eigen::Matrix<T, 3, 1>& t = T_target_host.translation();
    const Camera<T> camera = camera_.template cast<T>();
    const T d(observation_.inverse_distance);
    const T s = T(observation_.target_exposure / observation_.host_exposure) *
                exp(target_affine[0] - T(observation_.host_a));
    for (int o = 0; o < N; ++o) {
      const Eigen::Matrix<T, 3, 1> x = R * observation_.host_bearings[o].template cast<T>() + d * t;
      typename Camera<T>::Vec2 uv;
      if (!camera.project(x, uv)) return false;
      T intensity;
      if (!sampler_.sample(uv.x(), uv.y(), &intensity)) return false;
      const T h(observation_.host_intensity[o] - observation_.host_b);
      residuals[o] = T(observation_.sqrt_weight[o]) * ((intensity - target_affine[1]) - s * h);
    }
    return true;
  }

 private:
  Camera<double> camera_;
  TrackingObservation<N> observation_;
  ImageSampler sampler_;
};

template <template <typename> class Camera, int N>
ceres::CostFunction* makeTrackingCost(DifferentiationMode mode, const Camera<double>& level_camera,
                                      const TrackingObservation<N>& observation) {
  if (mode == DifferentiationMode::kAnalytic) {
    return new TrackingResidualAnalytic<Camera, N>(level_camera, observation);
  }
  using Functor = TrackingResidualFunctor<Camera, N>;
  return new ceres::AutoDiffCostFunction<Functor, N, 7, 2>(new Functor(level_camera, observation));
}

}  // namespace omnidso
