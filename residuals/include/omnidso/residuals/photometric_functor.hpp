#pragma once
// Autodiff photometric residual (paper eq. 5–7; notation in photometric_residual.hpp): the
// functor for ceres::AutoDiffCostFunction<PhotometricResidualFunctor<Camera, N>, N,
// 7, 7, 1, 2, 2, Camera<double>::kNumParams>. The camera is built per evaluation as
// Camera<T>(intrinsics scaled to the level), the poses through SE3<T>.
// Instantiated (inside AutoDiffCostFunction) only in residuals/src/photometric_cost_MODEL.cc
// to keep Jet code out of the TUs that merely create cost functions.

#include <cmath>

#include "omnidso/cameras/pyramid_scaling.hpp"
#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/image_sampler.hpp"
#include "omnidso/residuals/photometric_residual.hpp"
#include "omnidso/residuals/residual_pattern.hpp"

namespace omnidso {

template <template <typename> class Camera, int N>
class PhotometricResidualFunctor {
 public:
  static constexpr int kNumIntrinsics = Camera<double>::kNumParams;

  // observation.target_image must outlive the functor.
  explicit PhotometricResidualFunctor(const PhotometricObservation<N>& observation)
      : observation_(observation), sampler_(*observation.target_image, observation.interpolation,
               observation.target_content) {}

  template <typename T>
  bool operator()(const T* host_pose, const T* target_pose, const T* inverse_distance,
                  const T* host_affine, const T* target_affine, const T* intrinsics,
                  T* residuals) const {
    using std::exp;
    using CameraT = Camera<T>;
    const T& d = inverse_distance[0];
    if (!(d >= T(0))) return false;

    const SE3<T> T_target_host =
        SE3<T>::fromParameters(target_pose).inverse() * SE3<T>::fromParameters(host_pose);
    const Eigen::Matrix<T, 3, 3> R = T_target_host.rotationMatrix();
    const Eigen::Matrix<T, 3, 1>& t = T_target_host.translation();

    typename CameraT::VecN params = Eigen::Map<const typename CameraT::VecN>(intrinsics);
    scaleIntrinsicsToLevel(params, observation_.level);
    const CameraT camera(params);

    // s = t_j e^{a_j} / (t_i e^{a_i}) of eq. 5.
    const T s = T(observation_.target_exposure / observation_.host_exposure) *
                exp(target_affine[0] - host_affine[0]);
    for (int o = 0; o < N; ++o) {
      const PatternOffset offset = spreadOffset<N>(o, observation_.host.spread);
      const typename CameraT::Vec2 uv_host(T(observation_.host.pixel.x() + offset.du),
                                           T(observation_.host.pixel.y() + offset.dv));
      typename CameraT::Vec3 b;
      if (!camera.unproject(uv_host, b)) return false;
      const typename CameraT::Vec3 x = R * b + d * t;
      typename CameraT::Vec2 uv;
      if (!camera.project(x, uv)) return false;
      T intensity;
      if (!sampler_.sample(uv.x(), uv.y(), &intensity)) return false;
      const T h = T(observation_.host.intensity[o]) - host_affine[1];
      residuals[o] = T(observation_.host.sqrt_weight[o]) * ((intensity - target_affine[1]) - s * h);
    }
    return true;
  }

 private:
  PhotometricObservation<N> observation_;
  ImageSampler sampler_;
};

}  // namespace omnidso
