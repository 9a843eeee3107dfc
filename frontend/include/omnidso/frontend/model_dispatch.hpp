#pragma once
// From the run-time Camera to the model *template* the residual kernels are instantiated on
// (residuals/photometric_cost.hpp, tracking_residual.hpp take `template <typename> class`).
// The odometry runs on distortion-free models only: raw radial–tangential images are
// rectified to the undistorted model first (paper Sec. III), so the distorted variants are
// rejected here with a clear message.
//
//   withResidualModel<R>(camera, [&](auto tag, const auto& model) -> R {
//     return work(tag, model);   // work(ModelTag<M>, const M<double>&) deduces M
//   });

#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/error.hpp>
#include <type_traits>

namespace omnidso {

template <template <typename> class Model>
struct ModelTag {};

template <typename R, typename F>
R withResidualModel(const Camera& camera, F&& f) {
  return std::visit(
      [&](const auto& model) -> R {
        using T = std::decay_t<decltype(model)>;
        if constexpr (std::is_same_v<T, PinholeCamera<double>>) {
          return f(ModelTag<PinholeCamera>{}, model);
        } else if constexpr (std::is_same_v<T, UnifiedCamera<double>>) {
          return f(ModelTag<UnifiedCamera>{}, model);
        } else if constexpr (std::is_same_v<T, ExtendedUnifiedCamera<double>>) {
          return f(ModelTag<ExtendedUnifiedCamera>{}, model);
        } else if constexpr (std::is_same_v<T, DoubleSphereCamera<double>>) {
          return f(ModelTag<DoubleSphereCamera>{}, model);
        } else if constexpr (std::is_same_v<T, KannalaBrandtCamera<double>>) {
          return f(ModelTag<KannalaBrandtCamera>{}, model);
        } else if constexpr (std::is_same_v<T, FovCamera<double>>) {
          return f(ModelTag<FovCamera>{}, model);
        } else {
          throw Error("camera model '" + camera.modelName() +
                      "' has distortion: rectify the images to '" +
                      camera.undistortedModel().modelName() + "' before running the odometry");
        }
      },
      camera.model());
}

}  // namespace omnidso
