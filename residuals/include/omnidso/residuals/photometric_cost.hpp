#pragma once
// Factories of the photometric residual cost functions (paper eq. 5–7), instantiated per
// camera model in residuals/src/photometric_cost_MODEL.cc for pattern sizes 1, 5 and 8
// (models: PinholeCamera, UnifiedCamera, ExtendedUnifiedCamera, DoubleSphereCamera,
// KannalaBrandtCamera, FovCamera). Parameter blocks, in order:
//   host pose T_world_host (7, SE3Manifold), target pose T_world_target (7, SE3Manifold),
//   inverse distance (1), host affine [a, b] (2), target affine [a, b] (2),
//   intrinsics (Camera<double>::kNumParams, level-0 values).
// Any block may be held constant. The returned cost function returns false ("cannot
// evaluate") where the residual is invalid; photometricStatus() says why, without Ceres.
//
// Usage:
//   PhotometricObservation<8> obs{makeHostPatch<8>(host_img, host_grad, p), &target_img};
//   problem.AddResidualBlock(makePhotometricCost<UnifiedCamera, 8>(mode, obs),
//                            makePhotometricLoss(8), host_pose, target_pose, &inv_dist,
//                            host_affine, target_affine, intrinsics);

#include "omnidso/residuals/photometric_residual.hpp"

namespace ceres {
class CostFunction;
}

namespace omnidso {

// Owned by the caller (normally handed to ceres::Problem). observation.target_image must
// outlive the cost function.
template <template <typename> class Camera, int N>
ceres::CostFunction* makePhotometricCost(DifferentiationMode mode,
                                         const PhotometricObservation<N>& observation);

// The validity of the residual at the given parameter blocks (same order as above).
template <template <typename> class Camera, int N>
PhotometricStatus photometricStatus(const PhotometricObservation<N>& observation,
                                    double const* const* parameters);

}  // namespace omnidso
