#pragma once
// Every camera model of the project, for code that handles all of them (typed tests,
// benchmarks, the runtime variant in camera.hpp).
//
//   kName             class                                   parameters
//   "pinhole"         PinholeCamera<S>                        fx fy cx cy
//   "ucm"             UnifiedCamera<S>                        fx fy cx cy xi
//   "eucm"            ExtendedUnifiedCamera<S>                fx fy cx cy alpha beta
//   "ds"              DoubleSphereCamera<S>                   fx fy cx cy xi alpha
//   "kb4"             KannalaBrandtCamera<S>                  fx fy cx cy k1 k2 k3 k4
//   "fov"             FovCamera<S>                            fx fy cx cy w
//   "pinhole-radtan"  PinholeRadTanCamera<S>                  fx fy cx cy k1 k2 p1 p2
//                     = DistortedCamera<PinholeCamera<S>>
//   "ucm-radtan"      UnifiedRadTanCamera<S>                  fx fy cx cy xi k1 k2 p1 p2
//                     = DistortedCamera<UnifiedCamera<S>>
//
// Common interface (S = double, float or ceres::Jet): kNumParams, kName, kParamNames,
// params(), project(p, uv, d_uv_d_p*, d_uv_d_params*), unproject(uv, bearing,
// d_bearing_d_uv*, d_bearing_d_params*), maxAngleFromAxis(), cast<U>().

#include <omnidso/cameras/distorted.hpp>
#include <omnidso/cameras/double_sphere.hpp>
#include <omnidso/cameras/extended_unified.hpp>
#include <omnidso/cameras/fov.hpp>
#include <omnidso/cameras/kannala_brandt.hpp>
#include <omnidso/cameras/pinhole.hpp>
#include <omnidso/cameras/radtan.hpp>
#include <omnidso/cameras/unified.hpp>

#include <tuple>

namespace omnidso {

// The list of model templates applied to one scalar type.
template <typename Scalar>
using CameraModelsOf =
    std::tuple<PinholeCamera<Scalar>, UnifiedCamera<Scalar>, ExtendedUnifiedCamera<Scalar>,
               DoubleSphereCamera<Scalar>, KannalaBrandtCamera<Scalar>, FovCamera<Scalar>,
               PinholeRadTanCamera<Scalar>, UnifiedRadTanCamera<Scalar>>;

using AllCameraModels = CameraModelsOf<double>;

}  // namespace omnidso
