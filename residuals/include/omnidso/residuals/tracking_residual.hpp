#pragma once
// The photometric residual for coarse-to-fine tracking: the kernel of eq. 5–7 with ONE
// relative pose block T_target_host (7, SE3Manifold) and the target affine [a_j, b_j] (2)
// free; the point, the host frame (affine, exposure) and the intrinsics are fixed, so the
// host bearings b_o = π⁻¹(p + o) are computed once at creation (makeTrackingObservation).
// Works on any pyramid level: pass the camera scaled to that level
// (scaleIntrinsicsToLevel), the host patch sampled on that level and the target image of
// that level.
//   x̃_o = R b_o + d t,  [R t] = T_target_host,  r_o as in photometric_residual.hpp.
// Jacobian (T ⊞ δ = T exp(δ)): ∂x̃/∂rho = d R, ∂x̃/∂phi = −R [b]×, mapped to the ambient
// 7-vector with SE3Manifold's P⁺; ∂r/∂a_j = −√w s h, ∂r/∂b_j = −√w.

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <array>
#include <optional>

#include "omnidso/residuals/image_sampler.hpp"
#include "omnidso/residuals/photometric_residual.hpp"

namespace omnidso {

template <int N>
struct TrackingObservation {
  std::array<Eigen::Vector3d, N> host_bearings;  // b_o, unit, host camera frame
  double inverse_distance = 1.0;                 // d = 1/‖x‖ ≥ 0
  std::array<double, N> host_intensity{};        // I_i[p + o]
  std::array<double, N> sqrt_weight{};           // √w_o
  const ImageF* target_image = nullptr;          // target image of the level; not owned
  const Mask* target_content = nullptr;          // its content (photometric_residual.hpp)
  double host_exposure = 1.0;                    // t_i
  double target_exposure = 1.0;                  // t_j
  double host_a = 0.0;                           // host affine, fixed while tracking
  double host_b = 0.0;
  ImageInterpolation interpolation = ImageInterpolation::kBilinear;
  ImageGradient gradient = ImageGradient::kInterpolant;
};

// The bearings of the patch's pattern pixels through `level_camera`; nullopt if a pattern
// pixel does not unproject. Exposures, host affine, image and interpolation are left at
// their defaults for the caller to fill.
template <template <typename> class Camera, int N>
std::optional<TrackingObservation<N>> makeTrackingObservation(const Camera<double>& level_camera,
                                                              const HostPatch<N>& patch,
                                                              double inverse_distance);

// The kernel of TrackingResidualAnalytic with the pose as [R t] = T_target_host and the target
// affine [a_j, b_j]: r (N) and, where the pointers are not null, the TANGENT Jacobians
// ∂r/∂δ (N×6, T ⊞ δ = T exp(δ)) and ∂r/∂[a_j b_j] (N×2) — what Ceres obtains as J_amb · P
// (se3_manifold.hpp), without the round trip through the ambient 7-vector. For solvers that
// evaluate many observations at one pose (frontend/tracker_solver.hpp): R is formed once,
// and one sampler serves all observations of a target image.
template <int N>
using TrackingPoseJacobian = Eigen::Matrix<double, N, 6, Eigen::RowMajor>;
template <int N>
using TrackingAffineJacobian = Eigen::Matrix<double, N, 2, Eigen::RowMajor>;

template <template <typename> class Camera, int N>
PhotometricStatus evaluateTrackingResidual(
    const Camera<double>& level_camera, const TrackingObservation<N>& observation,
    const ImageSampler& sampler, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
    const double* target_affine, double* residuals, TrackingPoseJacobian<N>* pose_jacobian,
    TrackingAffineJacobian<N>* affine_jacobian);

template <template <typename> class Camera, int N>
class TrackingResidualAnalytic : public ceres::SizedCostFunction<N, 7, 2> {
 public:
  // observation.target_image must outlive the cost function.
  TrackingResidualAnalytic(const Camera<double>& level_camera,
                           const TrackingObservation<N>& observation);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;
  PhotometricStatus evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const;

 private:
  Camera<double> camera_;
  TrackingObservation<N> observation_;
  ImageSampler sampler_;
};

// Analytic or autodiff (the twin used to test the analytic one); caller owns the result.
template <template <typename> class Camera, int N>
ceres::CostFunction* makeTrackingCost(DifferentiationMode mode, const Camera<double>& level_camera,
                                      const TrackingObservation<N>& observation);

}  // namespace omnidso
